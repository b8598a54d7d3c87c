//! OSC packets decoded by rosc, a decoder written apart from Pneuma's encoder, so the encoder's
//! tests check its bytes against someone else's reading of OSC 1.0. Bundles are flattened into
//! their messages, each with its bundle's time tag.

pub use rosc::OscType;
use rosc::{OscBundle, OscPacket};

/// One decoded message.
#[derive(Debug, Clone, PartialEq)]
pub struct Message {
    /// The time tag of the bundle it came in (NTP: seconds since 1900 in the upper 32 bits,
    /// the fraction in the lower), `None` for a bare message.
    pub time_tag: Option<u64>,
    /// The address.
    pub address: String,
    /// The arguments.
    pub args: Vec<OscType>,
}

/// The messages of `packet` (a message or a bundle, nested bundles flattened). `Err` when rosc
/// cannot read it, when bytes are left over, or when an argument is of a type other than the
/// three Pneuma promises (OSC 1.0's `i`, `f`, `s`).
pub fn decode(packet: &[u8]) -> Result<Vec<Message>, String> {
    let (rest, decoded) = rosc::decoder::decode_udp(packet).map_err(|e| format!("{e:?}"))?;
    if !rest.is_empty() {
        return Err(format!("{} bytes after the packet", rest.len()));
    }
    let mut out = Vec::new();
    flatten(decoded, None, &mut out)?;
    Ok(out)
}

fn flatten(packet: OscPacket, time_tag: Option<u64>, out: &mut Vec<Message>) -> Result<(), String> {
    match packet {
        OscPacket::Message(m) => {
            if let Some(other) = m
                .args
                .iter()
                .find(|a| !matches!(a, OscType::Int(_) | OscType::Float(_) | OscType::String(_)))
            {
                return Err(format!("{}: argument {other:?} is not i, f or s", m.addr));
            }
            out.push(Message {
                time_tag,
                address: m.addr,
                args: m.args,
            });
        }
        OscPacket::Bundle(OscBundle { timetag, content }) => {
            let tag = (u64::from(timetag.seconds) << 32) | u64::from(timetag.fractional);
            for p in content {
                flatten(p, Some(tag), out)?;
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_hand_written_bundle_decodes_with_its_time_tag() {
        let mut b = b"#bundle\0".to_vec();
        b.extend_from_slice(&[0, 0, 0, 2, 0x80, 0, 0, 0]); // 2.5 s after 1900
        let msg: &[u8] = b"/a\0\0,is\0\0\0\0\x07hi\0\0";
        b.extend_from_slice(&(msg.len() as i32).to_be_bytes());
        b.extend_from_slice(msg);
        let m = decode(&b).expect("a valid bundle");
        assert_eq!(
            m,
            [Message {
                time_tag: Some((2 << 32) | 0x8000_0000),
                address: "/a".into(),
                args: vec![OscType::Int(7), OscType::String("hi".into())],
            }]
        );
    }

    #[test]
    fn garbage_and_types_pneuma_never_sends_are_refused() {
        assert!(decode(b"abc").is_err());
        assert!(decode(b"noslash\0").is_err());
        assert!(decode(b"#bundle\0\0\0\0\0\0\0\0\x01\0\0\0\x40").is_err());
        // A double (`d`) is valid OSC but not one of the types Pneuma sends.
        assert!(decode(b"/a\0\0,d\0\0\0\0\0\0\0\0\0\0").is_err());
    }
}
