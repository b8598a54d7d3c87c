//! The OSC 1.0 wire writer: messages and bundles with NTP time tags, written into a caller's
//! buffer without allocating. Only the types `i`, `f`, `s` (see [`super`] for the formats).

use thiserror::Error;

/// A bad OSC buffer or packet.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum OscError {
    /// The caller's buffer is too small for the packet.
    #[error("the OSC buffer ({capacity} bytes) is too small: give at least {needed} bytes")]
    BufferFull {
        /// Bytes needed at least (so far).
        needed: usize,
        /// Bytes available.
        capacity: usize,
    },
    /// An address does not start with `/` or contains a NUL.
    #[error("OSC address {0:?} is invalid: it must start with '/' and contain no NUL")]
    Address(String),
    /// A message this writer cannot carry (more than 15 arguments, a NUL inside a string).
    #[error("malformed OSC packet: {0}")]
    Malformed(&'static str),
}

/// One OSC argument.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum OscArg<'a> {
    /// `i`: 32-bit signed integer.
    Int(i32),
    /// `f`: 32-bit float.
    Float(f32),
    /// `s`: string (must not contain NUL).
    Str(&'a str),
}

impl OscArg<'_> {
    fn tag(&self) -> u8 {
        match self {
            OscArg::Int(_) => b'i',
            OscArg::Float(_) => b'f',
            OscArg::Str(_) => b's',
        }
    }
}

/// An NTP time tag: seconds since 1900-01-01 in the high 32 bits, fraction in the low 32 bits.
/// The value 1 means "immediately".
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct TimeTag(pub u64);

impl TimeTag {
    /// "Process immediately".
    pub const IMMEDIATELY: TimeTag = TimeTag(1);
    /// Seconds from 1900-01-01 (NTP era 0) to 1970-01-01 (Unix epoch).
    pub const UNIX_OFFSET_S: u64 = 2_208_988_800;

    /// The tag for `unix_s` seconds since the Unix epoch (negative values clamp to the epoch).
    pub fn from_unix_seconds(unix_s: f64) -> TimeTag {
        let s = unix_s.max(0.0);
        let whole = s.floor();
        let frac = ((s - whole) * 4_294_967_296.0).min(4_294_967_295.0) as u64;
        TimeTag(((whole as u64 + Self::UNIX_OFFSET_S) << 32) | frac)
    }

    /// Seconds since the Unix epoch.
    pub fn to_unix_seconds(self) -> f64 {
        let secs = (self.0 >> 32) as f64 - Self::UNIX_OFFSET_S as f64;
        secs + (self.0 & 0xFFFF_FFFF) as f64 / 4_294_967_296.0
    }
}

/// Sequential writer over a caller's byte buffer.
struct Cursor<'a> {
    buf: &'a mut [u8],
    len: usize,
}

impl<'a> Cursor<'a> {
    fn reserve(&mut self, n: usize) -> Result<&mut [u8], OscError> {
        let end = self.len + n;
        if end > self.buf.len() {
            return Err(OscError::BufferFull {
                needed: end,
                capacity: self.buf.len(),
            });
        }
        let slot = &mut self.buf[self.len..end];
        self.len = end;
        Ok(slot)
    }

    fn bytes(&mut self, b: &[u8]) -> Result<(), OscError> {
        self.reserve(b.len())?.copy_from_slice(b);
        Ok(())
    }

    /// A NUL-terminated string padded to a multiple of 4 bytes.
    fn padded(&mut self, parts: &[&[u8]]) -> Result<(), OscError> {
        let n: usize = parts.iter().map(|p| p.len()).sum();
        let total = (n + 4) & !3;
        let slot = self.reserve(total)?;
        let mut i = 0;
        for p in parts {
            slot[i..i + p.len()].copy_from_slice(p);
            i += p.len();
        }
        slot[i..].fill(0);
        Ok(())
    }
}

fn check_address(address: &str) -> Result<(), OscError> {
    if !address.starts_with('/') || address.contains('\0') {
        return Err(OscError::Address(address.to_owned()));
    }
    Ok(())
}

/// Writes one OSC message into `buf` and returns its length in bytes. Never allocates (except
/// for the error message of an invalid address).
pub fn write_message(buf: &mut [u8], address: &str, args: &[OscArg]) -> Result<usize, OscError> {
    check_address(address)?;
    let mut c = Cursor { buf, len: 0 };
    c.padded(&[address.as_bytes()])?;
    // Type tag string: ',' + one tag per argument (at most 15 on the stack).
    let mut tags = [0u8; 16];
    tags[0] = b',';
    if args.len() >= tags.len() {
        return Err(OscError::Malformed("more than 15 arguments in one message"));
    }
    for (t, a) in tags[1..].iter_mut().zip(args) {
        *t = a.tag();
    }
    c.padded(&[&tags[..=args.len()]])?;
    for a in args {
        match *a {
            OscArg::Int(v) => c.bytes(&v.to_be_bytes())?,
            OscArg::Float(v) => c.bytes(&v.to_be_bytes())?,
            OscArg::Str(s) => {
                if s.contains('\0') {
                    return Err(OscError::Malformed("string argument contains NUL"));
                }
                c.padded(&[s.as_bytes()])?
            }
        }
    }
    Ok(c.len)
}

/// Writes an OSC bundle into a caller's buffer, one message at a time.
pub struct BundleWriter<'a> {
    cursor: Cursor<'a>,
}

impl<'a> BundleWriter<'a> {
    /// Starts a bundle with time tag `time_tag`.
    pub fn new(buf: &'a mut [u8], time_tag: TimeTag) -> Result<Self, OscError> {
        let mut cursor = Cursor { buf, len: 0 };
        cursor.bytes(b"#bundle\0")?;
        cursor.bytes(&time_tag.0.to_be_bytes())?;
        Ok(Self { cursor })
    }

    /// Appends one message (size-prefixed).
    pub fn message(&mut self, address: &str, args: &[OscArg]) -> Result<(), OscError> {
        let start = self.cursor.len;
        self.cursor.reserve(4)?;
        let capacity = self.cursor.buf.len();
        let n = write_message(&mut self.cursor.buf[start + 4..], address, args).map_err(
            |e| match e {
                OscError::BufferFull { needed, .. } => OscError::BufferFull {
                    needed: needed + start + 4,
                    capacity,
                },
                e => e,
            },
        )?;
        self.cursor.buf[start..start + 4].copy_from_slice(&(n as i32).to_be_bytes());
        self.cursor.len += n;
        Ok(())
    }

    /// The bundle's length in bytes.
    pub fn finish(self) -> usize {
        self.cursor.len
    }
}
