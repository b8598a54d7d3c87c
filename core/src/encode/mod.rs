//! Pure encoders: they turn frames into bytes or text and do no I/O themselves; [`sink`] gives
//! them one shape ([`sink::FrameSink`]) that the CLI and the plugin both drive.

pub mod breaths_csv;
pub mod bvh;
pub mod controls_csv;
pub mod features_csv;
pub mod midi_cc;
pub mod midi_file;
pub mod osc;
pub mod sink;
