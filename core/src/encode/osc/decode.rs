//! A small OSC decoder for tests and tools (allocates): packets back into messages.

use super::wire::{OscError, TimeTag};

/// A decoded argument (owned), for tests and tools.
#[derive(Debug, Clone, PartialEq)]
pub enum OscValue {
    /// `i`
    Int(i32),
    /// `f`
    Float(f32),
    /// `s`
    Str(String),
}

/// A decoded message with the time tag of the bundle it came in (`None` for a bare message).
#[derive(Debug, Clone, PartialEq)]
pub struct OscMessage {
    /// Time tag of the enclosing bundle.
    pub time_tag: Option<TimeTag>,
    /// Address pattern.
    pub address: String,
    /// Arguments.
    pub args: Vec<OscValue>,
}

/// Decodes a packet (message or bundle, nested bundles flattened) into messages. Allocates: for
/// tests and tools, not for the audio thread.
pub fn decode_packet(packet: &[u8]) -> Result<Vec<OscMessage>, OscError> {
    let mut out = Vec::new();
    decode_into(packet, None, &mut out)?;
    Ok(out)
}

fn read_str(b: &[u8], pos: &mut usize) -> Result<String, OscError> {
    let rest = b
        .get(*pos..)
        .ok_or(OscError::Malformed("string past the end"))?;
    let nul = rest
        .iter()
        .position(|&c| c == 0)
        .ok_or(OscError::Malformed("string without NUL"))?;
    let s = std::str::from_utf8(&rest[..nul])
        .map_err(|_| OscError::Malformed("string is not UTF-8"))?
        .to_owned();
    let padded = (nul + 4) & !3;
    if padded > rest.len() {
        return Err(OscError::Malformed("string padding past the end"));
    }
    *pos += padded;
    Ok(s)
}

fn read4(b: &[u8], pos: &mut usize) -> Result<[u8; 4], OscError> {
    let v = b
        .get(*pos..*pos + 4)
        .ok_or(OscError::Malformed("argument past the end"))?;
    *pos += 4;
    Ok([v[0], v[1], v[2], v[3]])
}

fn decode_into(
    b: &[u8],
    time_tag: Option<TimeTag>,
    out: &mut Vec<OscMessage>,
) -> Result<(), OscError> {
    if !b.len().is_multiple_of(4) {
        return Err(OscError::Malformed("size is not a multiple of 4"));
    }
    if b.starts_with(b"#bundle\0") {
        let tag = b
            .get(8..16)
            .ok_or(OscError::Malformed("bundle without time tag"))?;
        let tag = TimeTag(u64::from_be_bytes(tag.try_into().expect("8 bytes")));
        let mut pos = 16;
        while pos < b.len() {
            let n = i32::from_be_bytes(read4(b, &mut pos)?);
            let n = usize::try_from(n).map_err(|_| OscError::Malformed("negative size"))?;
            let element = b
                .get(pos..pos + n)
                .ok_or(OscError::Malformed("bundle element past the end"))?;
            decode_into(element, Some(tag), out)?;
            pos += n;
        }
        return Ok(());
    }
    let mut pos = 0;
    let address = read_str(b, &mut pos)?;
    if !address.starts_with('/') {
        return Err(OscError::Malformed("address does not start with '/'"));
    }
    let tags = if pos < b.len() {
        read_str(b, &mut pos)?
    } else {
        ",".to_owned()
    };
    let tags = tags
        .strip_prefix(',')
        .ok_or(OscError::Malformed("type tags do not start with ','"))?;
    let mut args = Vec::with_capacity(tags.len());
    for t in tags.bytes() {
        args.push(match t {
            b'i' => OscValue::Int(i32::from_be_bytes(read4(b, &mut pos)?)),
            b'f' => OscValue::Float(f32::from_be_bytes(read4(b, &mut pos)?)),
            b's' => OscValue::Str(read_str(b, &mut pos)?),
            _ => return Err(OscError::Malformed("unsupported type tag")),
        });
    }
    out.push(OscMessage {
        time_tag,
        address,
        args,
    });
    Ok(())
}
