//! The avatar's rest pose, sent by the app itself when it ends in a way the plugin's OSC worker
//! cannot see (the JACK server stopped, or a quit the audio backend did not finish).

use pneuma_core::encode::osc::{OscFormat, TimeTag};
use pneuma_core::encode::sink::{FrameSink, OscSink};
use pneuma_core::ControlFrame;
use pneuma_osc::target::{now_unix_s, resolve, send, socket_for};

/// Where the rest pose goes: host, port and format (`None`: no OSC).
pub type RestTarget = Option<(String, u16, OscFormat)>;

/// One frame of the rest pose ([`ControlFrame::rest`]) to `rest`'s target, tagged now (best
/// effort); whether it was sent.
pub fn send_rest_pose(rest: &RestTarget) -> bool {
    let Some((host, port, format)) = rest else {
        return false;
    };
    let Some(addr) = resolve(host, *port) else {
        return false;
    };
    let socket = socket_for(&addr);
    let mut sent = false;
    let mut sink = OscSink::new(
        *format,
        |_: &ControlFrame| TimeTag::from_unix_seconds(now_unix_s()),
        |_: &ControlFrame, packet: &[u8]| {
            sent = send(Some(addr), socket.as_ref(), false, packet).is_ok();
        },
    );
    sink.frame(&ControlFrame::rest(0, 0.0), 0);
    sent
}
