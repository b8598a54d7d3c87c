//! WAV output: the name xtask and older code use for [`crate::audio_out::AudioSink`] writing
//! WAV (`WavSink::create(path, info)`).

pub use crate::audio_out::AudioSink as WavSink;
