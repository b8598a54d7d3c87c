//! What follows the first `data` chunk of a WAV file, looked at so that audio after it is
//! refused rather than lost: a second non-empty `data` chunk ([`WavError::DataChunks`]), or
//! bytes that are neither a chunk nor zero padding, audio a header left short (a recorder
//! stopped before it updated the size).
//!
//! [`after_data`] tells what lies right after the data; the chunk walk of a regular file
//! ([`crate::wav_meta`]) seeks to it. A stream (standard input, a pipe) cannot seek: once its
//! data has been read, [`check_stream`] reads on to the end of the stream and refuses what the
//! walk of a file refuses, except that it cannot say how much audio a short header left out
//! without reading it all ([`WavError::UnannouncedStream`], with the `sox` command that reads
//! all of it in the pipe).

use std::io::Read;
use std::path::Path;

use crate::le_bytes::u32_at;
use crate::read_full::read_full;
use crate::wav_error::WavError;
use crate::AudioInfo;

/// What lies right after the end a `data` chunk announces.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum AfterData {
    /// The end of the file: fewer bytes than a chunk header.
    End,
    /// A chunk header (its id printable ASCII) `at` bytes after the announced end: after the
    /// pad byte of an odd chunk, or a byte early where the writer left the pad byte out.
    Chunk {
        /// Bytes from the announced end to the chunk header.
        at: usize,
    },
    /// Zero padding.
    Padding,
    /// Neither: audio the header does not announce, from `at` bytes after the announced end.
    Audio {
        /// Bytes from the announced end to the unannounced audio (the pad byte's place).
        at: usize,
    },
}

/// A chunk id as files write them: four printable ASCII characters (`LIST`, `JUNK`, `id3 `).
pub(crate) fn is_chunk_id(id: &[u8]) -> bool {
    id.iter().all(|b| (b' '..=b'~').contains(b))
}

/// What `bytes` (from the announced end of a `data` chunk of `odd` length: the pad byte's
/// place, then a chunk header; 8 bytes, 9 when odd, fewer at the end of the file) hold.
pub(crate) fn after_data(bytes: &[u8], odd: bool) -> AfterData {
    let pad = usize::from(odd);
    let Some(header) = bytes.get(pad..pad + 8) else {
        return AfterData::End;
    };
    if is_chunk_id(&header[..4]) {
        AfterData::Chunk { at: pad }
    } else if odd && is_chunk_id(&bytes[..4]) {
        AfterData::Chunk { at: 0 }
    } else if header == [0; 8] {
        AfterData::Padding
    } else {
        AfterData::Audio { at: pad }
    }
}

/// What a stream holds after its first `data` chunk.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum StreamTail {
    /// Nothing that would be lost: chunks without audio, padding, or nothing.
    Clean,
    /// This many more non-empty `data` chunks.
    DataChunks(u32),
    /// Audio right after the data that its header does not announce.
    Unannounced,
}

/// Refuses what follows the data of a WAV stream named `path` (`info` from its header, its
/// first `data` chunk announcing `data_bytes`, `block_align` bytes per sample frame) when it
/// would be lost: another `data` chunk ([`WavError::DataChunks`]) or audio after the data
/// ([`WavError::UnannouncedStream`]). `reader` stands just after the whole sample frames of
/// the data; it is read to the end of the stream (skipping, never keeping). Best effort: a
/// read error ends the look as if the stream ended.
pub(crate) fn check_stream(
    reader: &mut impl Read,
    path: &Path,
    data_bytes: u64,
    block_align: usize,
    info: &AudioInfo,
) -> Result<(), WavError> {
    let partial_frame = data_bytes % block_align.max(1) as u64;
    match stream_tail(reader, partial_frame, data_bytes % 2 == 1) {
        StreamTail::Clean => Ok(()),
        StreamTail::DataChunks(more) => Err(WavError::DataChunks {
            path: path.to_owned(),
            count: 1 + more,
        }),
        StreamTail::Unannounced => Err(WavError::UnannouncedStream {
            path: path.to_owned(),
            announced_s: info.frames as f64 / f64::from(info.sample_rate_hz),
        }),
    }
}

/// Reads `n` bytes of `reader` into nothing; the bytes read (fewer at its end).
fn skip(reader: &mut impl Read, n: u64) -> u64 {
    std::io::copy(&mut reader.take(n), &mut std::io::sink()).unwrap_or(0)
}

/// What follows a `data` chunk of `odd` length whose last `partial_frame` bytes (less than a
/// sample frame, not read as audio) are next in `reader`.
fn stream_tail(reader: &mut impl Read, partial_frame: u64, odd: bool) -> StreamTail {
    if skip(reader, partial_frame) < partial_frame {
        return StreamTail::Clean;
    }
    let mut after = [0u8; 9];
    let want = 8 + usize::from(odd);
    let Ok(n) = read_full(reader, &mut after[..want]) else {
        return StreamTail::Clean;
    };
    let at = match after_data(&after[..n], odd) {
        AfterData::End | AfterData::Padding => return StreamTail::Clean,
        AfterData::Audio { .. } => return StreamTail::Unannounced,
        AfterData::Chunk { at } => at,
    };
    // The chunks after the data, walked as the walk of a file walks them: by their sizes.
    let mut rest = (&after[at..n]).chain(reader);
    let mut more = 0;
    loop {
        let mut header = [0u8; 8];
        if !matches!(read_full(&mut rest, &mut header), Ok(8)) {
            break;
        }
        let size = u32_at(&header, 4);
        if &header[..4] == b"data" {
            more += u32::from(size != 0);
            // A stream of unknown length: nothing after it is known.
            if size == 0 || size == u32::MAX {
                break;
            }
        }
        let body = u64::from(size) + u64::from(size & 1);
        if skip(&mut rest, body) < body {
            break;
        }
    }
    if more > 0 {
        StreamTail::DataChunks(more)
    } else {
        StreamTail::Clean
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn what_follows_the_data_is_told_apart() {
        use AfterData::*;
        assert_eq!(after_data(b"LIST\x04\0\0\0", false), Chunk { at: 0 });
        assert_eq!(after_data(b"\0LIST\x04\0\0\0", true), Chunk { at: 1 });
        // An odd chunk whose writer left out the pad byte: the header a byte early.
        assert_eq!(after_data(b"LIST\x04\0\0\0a", true), Chunk { at: 0 });
        assert_eq!(after_data(&[0; 9], true), Padding);
        assert_eq!(
            after_data(&[1, 2, 3, 4, 5, 6, 7, 8], false),
            Audio { at: 0 }
        );
        assert_eq!(
            after_data(&[0, 1, 2, 3, 4, 5, 6, 7, 8], true),
            Audio { at: 1 }
        );
        assert_eq!(after_data(b"LIST\x04\0", false), End);
    }

    #[test]
    fn a_stream_tail_is_walked_to_its_end() {
        let tail = |bytes: &[u8], partial: u64, odd: bool| {
            stream_tail(&mut std::io::Cursor::new(bytes.to_vec()), partial, odd)
        };
        let list = [&b"LIST\x05\0\0\0abcde\0"[..]].concat();
        let data = [&b"data\x04\0\0\0"[..], &[1, 2, 3, 4]].concat();
        assert_eq!(tail(&list, 0, false), StreamTail::Clean);
        assert_eq!(tail(&[], 0, false), StreamTail::Clean);
        assert_eq!(
            tail(&[&list[..], &data, &data].concat(), 0, false),
            StreamTail::DataChunks(2)
        );
        // A partial frame and the pad byte before the next chunk.
        assert_eq!(
            tail(&[&[9u8, 9, 0][..], &data].concat(), 2, true),
            StreamTail::DataChunks(1)
        );
        assert_eq!(tail(&[7; 64], 0, false), StreamTail::Unannounced);
        assert_eq!(tail(&[0; 64], 0, false), StreamTail::Clean);
    }

    /// A chunk: id, size field, body and its pad byte.
    fn chunk(id: &[u8; 4], size: u32, body: &[u8]) -> Vec<u8> {
        let pad = if body.len() % 2 == 1 { &[0u8][..] } else { &[] };
        [&id[..], &size.to_le_bytes(), body, pad].concat()
    }

    /// Reads a WAV stream of 8 kHz 8-bit mono `chunks` (after `fmt `) to its end.
    fn read_stream(chunks: &[Vec<u8>]) -> Result<u64, WavError> {
        let fmt = [1u16, 1, 8000, 0, 8000, 0, 1, 8]
            .map(u16::to_le_bytes)
            .concat();
        let body = [b"WAVE".to_vec(), chunk(b"fmt ", 16, &fmt), chunks.concat()].concat();
        let riff = [&b"RIFF"[..], &(body.len() as u32).to_le_bytes(), &body].concat();
        let name = Path::new(crate::STDIN_NAME);
        let stream = Box::new(std::io::Cursor::new(riff));
        let mut source = crate::WavSource::from_stream(name, stream, None)?;
        let mut block = Vec::new();
        while source.read_interleaved(333, &mut block)? > 0 {}
        Ok(source.frames_read())
    }

    #[test]
    fn a_stream_is_refused_at_the_end_of_its_data_when_audio_would_be_lost() {
        let audio: Vec<u8> = (0..801u32).map(|k| 130 + (k % 50) as u8).collect();
        let data = chunk(b"data", 801, &audio);
        let tags = chunk(b"LIST", 8, b"INFOabcd");
        assert_eq!(read_stream(&[data.clone(), tags.clone()]).ok(), Some(801));
        let e = read_stream(&[data.clone(), tags, data.clone()]).unwrap_err();
        assert_eq!(
            e.to_string(),
            "standard input holds 2 data chunks; Pneuma reads one, and sox and ffmpeg read \
             only the first too: export the recording again as one WAV file"
        );
        // 400 of the 801 samples announced: the rest would be cut.
        let short = [&b"data"[..], &400u32.to_le_bytes(), &audio].concat();
        let e = read_stream(&[short]).unwrap_err();
        assert!(
            matches!(e, WavError::UnannouncedStream { announced_s, .. } if announced_s == 0.05),
            "{e}"
        );
    }
}
