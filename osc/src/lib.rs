//! Pneuma's OSC output over UDP, the one place the doors send OSC from (the bundles themselves
//! are core's encoders, [`pneuma_core::encode::osc`]; core opens no sockets):
//! - [`worker`]: the plugin's sender (and so `pneuma-app`'s): the audio thread pushes frames
//!   into a preallocated lock-free queue, a worker thread encodes and sends them; nothing the
//!   network does reaches the audio thread.
//! - [`paced`]: the CLI's sender: a rendered stream's frames, each sent when it is due, in real
//!   time or at a multiple of it.
//! - [`target`]: the target's address (numeric or `localhost`, names never looked up), the
//!   socket, one send and why a frame was not sent ([`OscError`]).

pub mod paced;
pub mod target;
pub mod worker;

pub use paced::{PacedSender, PacedStats, Speed};
pub use target::OscError;

use pneuma_core::encode::osc::OscFormat;
use pneuma_core::settings::output::{OSC_FORMAT, OSC_PORT};

/// Default OSC host: this machine.
pub const DEFAULT_OSC_HOST: &str = "127.0.0.1";

/// Default OSC port (the table's `osc_port`: the VMC marionette port most avatar apps listen
/// on).
pub const DEFAULT_OSC_PORT: u16 = OSC_PORT.default as u16;

/// The format for an index of the table's `osc_format` choice (`pneuma`, `vmc`); an index
/// out of range is the table's default.
pub fn format_of_index(index: usize) -> OscFormat {
    let formats = [OscFormat::Pneuma, OscFormat::Vmc];
    formats
        .get(index)
        .copied()
        .unwrap_or(formats[OSC_FORMAT.default as usize])
}

/// A voiced control frame `index` at 120 frames a second whose f0 tells the frames apart, for
/// the senders' tests.
#[cfg(test)]
pub(crate) fn test_frame(index: u64) -> pneuma_core::ControlFrame {
    pneuma_core::ControlFrame {
        index,
        time_s: index as f64 / 120.0,
        f0_hz: 100.0 + index as f32,
        voiced: true,
        ..Default::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_follow_the_tables_choice_names() {
        let names = OSC_FORMAT.names();
        assert_eq!(names, ["pneuma", "vmc"]);
        assert_eq!(format_of_index(0), OscFormat::Pneuma);
        assert_eq!(format_of_index(1), OscFormat::Vmc);
        assert_eq!(
            format_of_index(9),
            format_of_index(OSC_FORMAT.default as usize)
        );
    }
}
