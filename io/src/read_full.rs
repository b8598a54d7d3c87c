//! Reading until a buffer is full or the input ends: a pipe hands its bytes out in pieces,
//! so one `read` is not enough for a header (the WAV reader, the format sniffing, the chunk
//! walks, the Ogg page walk).

use std::io::Read;

/// Reads until `buf` is full or the input ends; returns the bytes read.
pub(crate) fn read_full(r: &mut impl Read, buf: &mut [u8]) -> std::io::Result<usize> {
    let mut n = 0;
    while n < buf.len() {
        match r.read(&mut buf[n..]) {
            Ok(0) => break,
            Ok(k) => n += k,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(n)
}
