//! The length of an MP3 file whose first frame holds no frame count (no Xing/Info/VBRI frame:
//! an encoder writing to a pipe cannot go back to add it).
//!
//! For such a file symphonia guesses the length from the file's size and the first 16 frames'
//! average size, which for VBR audio can be far off either way: too long, and the reader would
//! call a whole file cut short; too short, and symphonia trims every frame past the guess, so
//! the end of the recording would vanish without a word. Here the file is read once more as a
//! stream (not seekable, so symphonia makes no guess) and its frames are counted without
//! decoding them: the count is exact, as ffmpeg's is.

use std::path::Path;

use symphonia::core::formats::TrackType;
use symphonia::core::io::ReadOnlySource;

/// The sample frames of the MP3 file at `path` counted frame by frame, when its first frame
/// holds no frame count; `None` when it does (then symphonia's count is the header's) or when
/// the file cannot be read again (the decoder then reports what is wrong). A frame the
/// demuxer cannot read ends the count: decoding reports it.
pub(crate) fn counted_frames(path: &Path) -> Option<u64> {
    let file = std::fs::File::open(path).ok()?;
    let mut reader = crate::probe::probe(Box::new(ReadOnlySource::new(file)), Some("mp3")).ok()?;
    let track = reader.default_track(TrackType::Audio)?;
    if track.num_frames.is_some() {
        return None;
    }
    let track_id = track.id;
    let mut frames = 0u64;
    while let Ok(Some(packet)) = reader.next_packet() {
        if packet.track_id == track_id {
            frames += packet.dur.get();
        }
    }
    Some(frames)
}

#[cfg(test)]
mod tests {
    use crate::{AudioSource, DecodeError, ReadError};

    /// MPEG-1 Layer III bitrate indexes: 32 and 320 kbit/s.
    const LOW: u8 = 1;
    const HIGH: u8 = 14;
    /// Sample frames in one MPEG-1 Layer III frame.
    const FRAME_SAMPLES: u64 = 1152;
    /// Header and mono side information, bytes.
    const TAG_OFFSET: usize = 4 + 17;

    /// A silent mono 44.1 kHz frame at the bitrate index `rate` (side information all zero).
    fn frame(rate: u8) -> Vec<u8> {
        let kbps = [
            0, 32, 40, 48, 56, 64, 80, 96, 112, 128, 160, 192, 224, 256, 320,
        ];
        let len = 144 * kbps[rate as usize] * 1000 / 44_100;
        let mut f = vec![0u8; len];
        f[..4].copy_from_slice(&[0xFF, 0xFB, rate << 4, 0xC0]);
        f
    }

    /// `n` frames at each bitrate index of `runs`, in order.
    fn frames(runs: &[(u8, usize)]) -> Vec<u8> {
        runs.iter()
            .flat_map(|&(rate, n)| std::iter::repeat_n(frame(rate), n).flatten())
            .collect()
    }

    /// Every sample frame of `bytes` saved as an MP3 file, or the error.
    fn read_all(bytes: &[u8]) -> Result<(u64, u64), ReadError> {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("piped.mp3");
        std::fs::write(&path, bytes).unwrap();
        let mut source = AudioSource::open(&path)?;
        let mut buf = Vec::new();
        while source.read_interleaved(4096, &mut buf)? > 0 {}
        Ok((source.info().frames, source.frames_read()))
    }

    #[test]
    fn a_vbr_mp3_without_a_frame_count_that_grows_is_not_called_damaged() {
        // Symphonia guesses from the small first frames about ten times the real length.
        let (announced, read) = read_all(&frames(&[(LOW, 20), (HIGH, 200)])).unwrap();
        assert_eq!(read, 220 * FRAME_SAMPLES);
        assert_eq!(announced, read, "the counted length is announced");
    }

    #[test]
    fn a_vbr_mp3_without_a_frame_count_that_shrinks_is_read_to_its_end() {
        // The guess from the large first frames is a tenth of the file: it was cut there.
        let (announced, read) = read_all(&frames(&[(HIGH, 20), (LOW, 400)])).unwrap();
        assert_eq!(read, 420 * FRAME_SAMPLES);
        assert_eq!(announced, read);
    }

    #[test]
    fn a_truncated_mp3_whose_xing_frame_counts_its_frames_is_damaged() {
        let mut xing = frame(HIGH);
        xing[TAG_OFFSET..TAG_OFFSET + 12].copy_from_slice(b"Xing\0\0\0\x01\0\0\x03\xe8");
        let mut bytes = xing;
        bytes.extend(frames(&[(HIGH, 100)]));
        match read_all(&bytes) {
            Err(ReadError::Decode(DecodeError::Damaged { reason, .. })) => assert!(
                reason.contains("announces 1152000 sample frames"),
                "{reason}"
            ),
            other => panic!("a file of 100 of its 1000 frames: {other:?}"),
        }
    }
}
