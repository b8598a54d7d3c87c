//! Pure encoders: they turn frames into bytes or text and do no I/O themselves.

pub mod features_csv;
