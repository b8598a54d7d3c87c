//! What a tryout by an animator and VTuber met, end to end: an unknown espeak-ng voice was told
//! twice, espeak-ng's line and our question (now once, what to do).

use crate::support::{self, pneuma};

#[test]
fn an_unknown_espeak_voice_is_told_once_with_what_to_do() {
    if !support::tool_or_skip("espeak-ng", "--version", "an_unknown_espeak_voice") {
        return;
    }
    let dir = tempfile::tempdir().expect("temp");
    let out = dir.path().join("spoken");
    let o = pneuma(&[
        "speak",
        "--voice",
        "nonexistent",
        "hello",
        "-o",
        out.to_str().expect("utf-8"),
    ]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("no voice `nonexistent`") && err.contains("`espeak-ng --voices`"),
        "{err}"
    );
    // espeak-ng's own line is not repeated beside ours.
    assert!(!err.contains("does not exist"), "{err}");
    assert!(!out.exists());
}
