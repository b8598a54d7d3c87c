//! G.711 µ-law and A-law (WAV format tags 7 and 6, telephone recordings) expanded to 16-bit
//! linear PCM, as ITU-T G.711 defines the decoding: every code maps to one 16-bit value (µ-law
//! to ±32124, A-law to ±32256), so a 16-bit output keeps the decoded signal exactly.

/// The 16-bit linear value of a µ-law code.
pub fn ulaw_to_i16(code: u8) -> i16 {
    let u = !code;
    let t = ((i32::from(u & 0x0f) << 3) + 0x84) << ((u & 0x70) >> 4);
    (if u & 0x80 != 0 { 0x84 - t } else { t - 0x84 }) as i16
}

/// The 16-bit linear value of an A-law code.
pub fn alaw_to_i16(code: u8) -> i16 {
    let a = code ^ 0x55;
    let mut t = i32::from(a & 0x0f) << 4;
    let segment = (a & 0x70) >> 4;
    t += match segment {
        0 => 8,
        _ => 0x108,
    };
    if segment > 1 {
        t <<= segment - 1;
    }
    (if a & 0x80 != 0 { t } else { -t }) as i16
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_expand_to_the_g711_table_values() {
        // Values of the G.711 decoding tables (as sox and ffmpeg decode them).
        assert_eq!(ulaw_to_i16(0xff), 0);
        assert_eq!(ulaw_to_i16(0x7f), 0);
        assert_eq!(ulaw_to_i16(0x80), 32124);
        assert_eq!(ulaw_to_i16(0x00), -32124);
        assert_eq!(ulaw_to_i16(0xfe), 8);
        assert_eq!(ulaw_to_i16(0xf0), 120);
        assert_eq!(alaw_to_i16(0xd5), 8);
        assert_eq!(alaw_to_i16(0x55), -8);
        assert_eq!(alaw_to_i16(0xaa), 32256);
        assert_eq!(alaw_to_i16(0x2a), -32256);
        // Monotonic over the codes of one sign.
        let pos: Vec<i16> = (0x80..=0xffu8).rev().map(ulaw_to_i16).collect();
        assert!(pos.windows(2).all(|w| w[0] < w[1]), "µ-law rises");
    }
}
