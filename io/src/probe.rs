//! Symphonia's format reader for a source, as the decoder and the MP3 frame count open it.

use symphonia::core::errors::Error as SymError;
use symphonia::core::formats::probe::Hint;
use symphonia::core::formats::{FormatOptions, FormatReader};
use symphonia::core::io::{MediaSource, MediaSourceStream, MediaSourceStreamOptions};
use symphonia::core::meta::MetadataOptions;

/// Symphonia's reader of `source`, whose file name ends in `.ext` if given.
pub(crate) fn probe(
    source: Box<dyn MediaSource>,
    ext: Option<&str>,
) -> Result<Box<dyn FormatReader>, SymError> {
    let mss = MediaSourceStream::new(source, MediaSourceStreamOptions::default());
    let mut hint = Hint::new();
    if let Some(ext) = ext {
        hint.with_extension(ext);
    }
    symphonia::default::get_probe().probe(
        &hint,
        mss,
        FormatOptions::default(),
        MetadataOptions::default(),
    )
}
