//! Standard MIDI File writer (SMF 1.0, format 0, one track) for the CC lanes the plugin sends:
//! the same [`CcEncoder`] (controllers, channel, values, only changed values, at most once per
//! frame), each message at its frame's time, so a DAW that imports the file places every change
//! where the plugin would have sent it.
//!
//! Timing: [`TICKS_PER_QUARTER`] ticks per quarter note and one tempo event of
//! [`TEMPO_US_PER_QUARTER`] µs per quarter (120 BPM) with a 4/4 time signature, so a tick is
//! 1/[`TICKS_PER_SECOND`] s and a file lands at the right seconds in any DAW's tempo map that
//! takes the file's tempo (120 Hz frames are exactly 16 ticks apart). A message's time is its
//! frame's `time_s` rounded to the nearest tick.
//!
//! The track's length stands in the header, before the events: [`MidiFileSink`] writes the
//! header with length 0 first, streams the events (memory stays bounded on hour-long renders),
//! and [`MidiFileSink::finish`] ends the track and writes the real header over the first one
//! through [`Seek`]. Write errors are kept (the first one) and reported by
//! [`MidiFileSink::check`] and `finish`, as with the text sinks.

use std::io::{Seek, SeekFrom, Write};

use crate::control::ControlFrame;
use crate::encode::midi_cc::{CcEncoder, CcMap, CcMapError, CcMessage};
use crate::encode::sink::FrameSink;

/// Ticks per quarter note (the header's division).
pub const TICKS_PER_QUARTER: u16 = 960;
/// Tempo: microseconds per quarter note (120 BPM).
pub const TEMPO_US_PER_QUARTER: u32 = 500_000;
/// Ticks per second at that tempo (1920).
pub const TICKS_PER_SECOND: f64 = TICKS_PER_QUARTER as f64 * 1e6 / TEMPO_US_PER_QUARTER as f64;
/// Bytes of the file header (`MThd` chunk) and the track chunk's own header (`MTrk`, length).
pub const HEADER_BYTES: usize = 22;
/// The name of the track (a sequence/track name meta event).
pub const TRACK_NAME: &str = "Pneuma controls";

/// Largest delta time a variable-length quantity holds (four bytes).
const MAX_DELTA_TICKS: u64 = 0x0FFF_FFFF;

/// The tick of a time in seconds (nearest; negative times are 0).
pub fn ticks(time_s: f64) -> u64 {
    (time_s.max(0.0) * TICKS_PER_SECOND).round() as u64
}

/// The file header for a track of `track_bytes` bytes: `MThd`, length 6, format 0, one track,
/// the division; then `MTrk` and the track's length.
pub fn header(track_bytes: u32) -> [u8; HEADER_BYTES] {
    let mut h = [0u8; HEADER_BYTES];
    h[0..4].copy_from_slice(b"MThd");
    h[4..8].copy_from_slice(&6u32.to_be_bytes());
    h[8..10].copy_from_slice(&0u16.to_be_bytes());
    h[10..12].copy_from_slice(&1u16.to_be_bytes());
    h[12..14].copy_from_slice(&TICKS_PER_QUARTER.to_be_bytes());
    h[14..18].copy_from_slice(b"MTrk");
    h[18..22].copy_from_slice(&track_bytes.to_be_bytes());
    h
}

/// Appends `v` (at most [`MAX_DELTA_TICKS`]) as a MIDI variable-length quantity; the bytes used.
fn vlq(v: u64, out: &mut [u8; 4]) -> usize {
    let v = v.min(MAX_DELTA_TICKS) as u32;
    let mut n = 1;
    while n < 4 && v >> (7 * n) != 0 {
        n += 1;
    }
    for (i, b) in out[..n].iter_mut().enumerate() {
        let shift = 7 * (n - 1 - i);
        *b = ((v >> shift) & 0x7f) as u8 | if i + 1 < n { 0x80 } else { 0 };
    }
    n
}

/// The events at the start of the track: tempo, time signature 4/4, track name (all at tick 0).
fn track_start() -> Vec<u8> {
    let mut t = vec![0x00, 0xff, 0x51, 0x03];
    t.extend_from_slice(&TEMPO_US_PER_QUARTER.to_be_bytes()[1..]);
    // 4/4, a metronome click per quarter (24 MIDI clocks), 8 32nd notes per quarter.
    t.extend_from_slice(&[0x00, 0xff, 0x58, 0x04, 0x04, 0x02, 0x18, 0x08]);
    t.extend_from_slice(&[0x00, 0xff, 0x03, TRACK_NAME.len() as u8]);
    t.extend_from_slice(TRACK_NAME.as_bytes());
    t
}

/// End of track, at the last event's tick.
const END_OF_TRACK: [u8; 4] = [0x00, 0xff, 0x2f, 0x00];

/// A Standard MIDI File of the CC messages of every frame, streamed into `out`.
pub struct MidiFileSink<W: Write> {
    out: W,
    encoder: CcEncoder,
    /// Tick of the last event written.
    tick: u64,
    /// Bytes of the track so far.
    track_bytes: u64,
    /// Messages written.
    messages: u64,
    error: Option<std::io::Error>,
}

impl<W: Write> MidiFileSink<W> {
    /// Writes the header (length still 0) and the track's first events into `out`; the CCs
    /// follow `map` (the plugin's is [`CcMap::default`] with its channel and range settings).
    pub fn new(mut out: W, map: CcMap) -> Result<Self, MidiFileError> {
        let encoder = CcEncoder::new(map)?;
        let start = track_start();
        out.write_all(&header(0))?;
        out.write_all(&start)?;
        Ok(Self {
            out,
            encoder,
            tick: 0,
            track_bytes: start.len() as u64,
            messages: 0,
            error: None,
        })
    }

    /// The CC messages written so far.
    pub fn messages(&self) -> u64 {
        self.messages
    }

    /// The first write error, if any (it stays; no later event is written).
    pub fn check(&self) -> std::io::Result<()> {
        match &self.error {
            None => Ok(()),
            Some(e) => Err(std::io::Error::new(e.kind(), e.to_string())),
        }
    }

    fn message(&mut self, time_s: f64, m: CcMessage) {
        if self.error.is_some() {
            return;
        }
        let tick = ticks(time_s).max(self.tick);
        let mut event = [0u8; 7];
        let mut delta = [0u8; 4];
        let n = vlq(tick - self.tick, &mut delta);
        event[..n].copy_from_slice(&delta[..n]);
        event[n..n + 3].copy_from_slice(&m.to_bytes());
        match self.out.write_all(&event[..n + 3]) {
            Ok(()) => {
                self.tick = tick;
                self.track_bytes += (n + 3) as u64;
                self.messages += 1;
            }
            Err(e) => self.error = Some(e),
        }
    }
}

impl<W: Write + Seek> MidiFileSink<W> {
    /// Ends the track, writes the final header over the first one and returns the writer
    /// (positioned at the end), or the first error.
    pub fn finish(mut self) -> Result<W, MidiFileError> {
        if let Some(e) = self.error.take() {
            return Err(e.into());
        }
        self.out.write_all(&END_OF_TRACK)?;
        let bytes = self.track_bytes + END_OF_TRACK.len() as u64;
        let bytes = u32::try_from(bytes).map_err(|_| MidiFileError::TooLong(bytes))?;
        let end = self.out.stream_position()?;
        self.out.seek(SeekFrom::Start(
            end - HEADER_BYTES as u64 - u64::from(bytes),
        ))?;
        self.out.write_all(&header(bytes))?;
        self.out.seek(SeekFrom::Start(end))?;
        self.out.flush()?;
        Ok(self.out)
    }
}

impl<W: Write> FrameSink for MidiFileSink<W> {
    fn frame(&mut self, frame: &ControlFrame, _at: u64) {
        // Collected first: the encoder calls back while borrowed.
        let mut due = [None; 2 * crate::encode::midi_cc::SIGNAL_COUNT];
        let mut k = 0;
        self.encoder.encode(frame, |m| {
            if let Some(slot) = due.get_mut(k) {
                *slot = Some(m);
                k += 1;
            }
        });
        for m in due.into_iter().flatten() {
            self.message(frame.time_s, m);
        }
    }
}

/// Errors of a MIDI file.
#[derive(Debug, thiserror::Error)]
pub enum MidiFileError {
    /// The CC map.
    #[error("MIDI CC map: {0}")]
    Map(#[from] CcMapError),
    /// The writer.
    #[error(transparent)]
    Io(#[from] std::io::Error),
    /// More than a MIDI track chunk can hold.
    #[error(
        "the MIDI track would be {0} bytes, more than a MIDI file's 4 GiB: render shorter pieces"
    )]
    TooLong(u64),
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Cursor;

    #[test]
    fn variable_length_quantities_follow_the_smf_examples() {
        // The examples of the Standard MIDI File 1.0 specification.
        for (v, want) in [
            (0x00u64, &[0x00u8][..]),
            (0x40, &[0x40]),
            (0x7f, &[0x7f]),
            (0x80, &[0x81, 0x00]),
            (0x2000, &[0xc0, 0x00]),
            (0x3fff, &[0xff, 0x7f]),
            (0x4000, &[0x81, 0x80, 0x00]),
            (0x1f_ffff, &[0xff, 0xff, 0x7f]),
            (0x20_0000, &[0x81, 0x80, 0x80, 0x00]),
            (0x0fff_ffff, &[0xff, 0xff, 0xff, 0x7f]),
        ] {
            let mut b = [0u8; 4];
            let n = vlq(v, &mut b);
            assert_eq!(&b[..n], want, "{v:#x}");
        }
    }

    #[test]
    fn a_file_has_its_header_tempo_and_messages_at_their_ticks() {
        let mut sink = MidiFileSink::new(Cursor::new(Vec::new()), CcMap::default()).expect("sink");
        let mut frame = ControlFrame::default();
        sink.frame(&frame, 0);
        let first = sink.messages();
        assert!(first > 0, "the first frame sends every mapped signal");
        // Nothing changed: nothing sent. Then the lung fills at 0.5 s: one message.
        frame.index = 1;
        frame.time_s = 1.0 / 120.0;
        sink.frame(&frame, 0);
        assert_eq!(sink.messages(), first);
        frame.index = 60;
        frame.time_s = 0.5;
        frame.breathing.lung = 1.0;
        sink.frame(&frame, 0);
        assert_eq!(sink.messages(), first + 1);
        let bytes = sink.finish().expect("finish").into_inner();
        // The header as the specification spells it, with the real track length.
        assert_eq!(&bytes[..14], b"MThd\0\0\0\x06\0\0\0\x01\x03\xc0");
        assert_eq!(&bytes[14..18], b"MTrk");
        let len = u32::from_be_bytes(bytes[18..22].try_into().expect("4")) as usize;
        assert_eq!(len, bytes.len() - HEADER_BYTES);
        // Tempo 500 000 µs per quarter, first event of the track.
        assert_eq!(&bytes[22..29], &[0x00, 0xff, 0x51, 0x03, 0x07, 0xa1, 0x20]);
        assert_eq!(&bytes[bytes.len() - 4..], &END_OF_TRACK);
        // The last message: lung (CC 2) to 127 on channel 1, 0.5 s = 960 ticks after 0.
        let last = &bytes[bytes.len() - 9..bytes.len() - 4];
        assert_eq!(last, &[0x87, 0x40, 0xb0, 0x02, 0x7f]);
    }
}
