//! The Silero VAD weight file (`assets/models/silero_vad_v6_16k.bin`): the 16 kHz network's
//! tensors, copied bit for bit from the ONNX model `silero_vad_op18_ifless.onnx` of the PyPI
//! package `silero-vad` (MIT, Silero Team; `assets/models/README.md`) by `cargo xtask
//! silero-weights`, and embedded in the library.
//!
//! ## Format, version 1 (all integers little-endian `u32`)
//! - the magic `PNSILERO`, the version (1) and the number of tensors (15);
//! - per tensor, in the order of [`TENSORS`]: the length of its name, the name (UTF-8, the ONNX
//!   initializer's), its rank, its dimensions, then its values as little-endian `f32` (row-major,
//!   as ONNX stores them).
//!
//! Reading checks the whole file: its length and FNV-1a digest against the ones this build was
//! written for ([`SHIPPED_LEN`], [`SHIPPED_DIGEST`]), the magic, the version, every name and
//! shape, and that every value is finite. Each failure names what is wrong and what to do.

use thiserror::Error;

/// The magic bytes a weight file starts with.
const MAGIC: &[u8; 8] = b"PNSILERO";
/// The format version this build reads and writes.
const VERSION: u32 = 1;

/// The tensors of the 16 kHz network, in file order: ONNX initializer name and shape.
pub const TENSORS: [(&str, &[usize]); 15] = [
    ("model.stft.forward_basis_buffer", &[258, 1, 256]),
    ("model.encoder.0.reparam_conv.weight", &[128, 129, 3]),
    ("model.encoder.0.reparam_conv.bias", &[128]),
    ("model.encoder.1.reparam_conv.weight", &[64, 128, 3]),
    ("model.encoder.1.reparam_conv.bias", &[64]),
    ("model.encoder.2.reparam_conv.weight", &[64, 64, 3]),
    ("model.encoder.2.reparam_conv.bias", &[64]),
    ("model.encoder.3.reparam_conv.weight", &[128, 64, 3]),
    ("model.encoder.3.reparam_conv.bias", &[128]),
    ("model.decoder.rnn.weight_ih", &[512, 128]),
    ("model.decoder.rnn.weight_hh", &[512, 128]),
    ("model.decoder.rnn.bias_ih", &[512]),
    ("model.decoder.rnn.bias_hh", &[512]),
    ("model.decoder.decoder.2.weight", &[1, 128, 1]),
    ("model.decoder.decoder.2.bias", &[1]),
];

/// Length in bytes of the shipped weight file.
pub const SHIPPED_LEN: usize = 1_239_249;
/// FNV-1a (64 bit) digest of the shipped weight file.
pub const SHIPPED_DIGEST: u64 = 0x1b52_7fd2_d04c_e6a6;

/// The shipped file, embedded.
pub(crate) const SHIPPED: &[u8] = include_bytes!("../../../assets/models/silero_vad_v6_16k.bin");

/// A weight file that cannot be used. Each message says what to do.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SileroWeightsError {
    /// Length or digest differ from the file this build expects.
    #[error("Silero weights: the file is {len} bytes with digest {digest:016x}, this build expects {SHIPPED_LEN} bytes with digest {SHIPPED_DIGEST:016x}; regenerate assets/models/silero_vad_v6_16k.bin with `cargo xtask silero-weights` (or update SHIPPED_LEN/SHIPPED_DIGEST in core/src/speech/weights.rs with a new model)")]
    Digest {
        /// The file's length in bytes.
        len: usize,
        /// The file's FNV-1a digest.
        digest: u64,
    },
    /// The file does not follow the format.
    #[error("Silero weights, byte {at}: {message}; regenerate the file with `cargo xtask silero-weights` (format in core/src/speech/weights.rs)")]
    Format {
        /// Byte offset of the problem.
        at: usize,
        /// What is wrong.
        message: String,
    },
}

/// FNV-1a, 64 bit, of `bytes`.
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// The tensors of a weight file, values in [`TENSORS`] order.
#[derive(Debug, Clone, PartialEq)]
pub struct SileroWeights {
    /// One vector of values per entry of [`TENSORS`].
    pub tensors: Vec<Vec<f32>>,
}

impl SileroWeights {
    /// Reads a weight file, checking its length and digest against the shipped ones first.
    pub fn parse(bytes: &[u8]) -> Result<Self, SileroWeightsError> {
        let digest = fnv1a64(bytes);
        if bytes.len() != SHIPPED_LEN || digest != SHIPPED_DIGEST {
            return Err(SileroWeightsError::Digest {
                len: bytes.len(),
                digest,
            });
        }
        Self::parse_unchecked(bytes)
    }

    /// Reads a weight file without the length/digest check (for the xtask that makes one):
    /// every other check applies.
    pub fn parse_unchecked(bytes: &[u8]) -> Result<Self, SileroWeightsError> {
        let mut r = Reader { bytes, at: 0 };
        if r.take(MAGIC.len())? != MAGIC {
            return Err(r.error(
                0,
                "not a Silero weight file (the magic PNSILERO is missing)",
            ));
        }
        let version = r.u32()?;
        if version != VERSION {
            return Err(r.error(
                8,
                &format!("format version {version}, this build reads {VERSION}"),
            ));
        }
        let count = r.u32()? as usize;
        if count != TENSORS.len() {
            return Err(r.error(
                12,
                &format!("{count} tensors, the network has {}", TENSORS.len()),
            ));
        }
        let mut tensors = Vec::with_capacity(count);
        for (name, shape) in TENSORS {
            let at = r.at;
            let len = r.u32()? as usize;
            let found = r.take(len)?;
            if found != name.as_bytes() {
                return Err(r.error(
                    at,
                    &format!(
                        "expected tensor {name}, found {:?}",
                        String::from_utf8_lossy(found)
                    ),
                ));
            }
            let at = r.at;
            let rank = r.u32()? as usize;
            let mut dims = Vec::with_capacity(rank.min(8));
            for _ in 0..rank.min(8) {
                dims.push(r.u32()? as usize);
            }
            if dims != shape {
                return Err(r.error(
                    at,
                    &format!("tensor {name} has shape {dims:?} (rank {rank}), expected {shape:?}"),
                ));
            }
            let n: usize = shape.iter().product();
            let at = r.at;
            let raw = r.take(4 * n)?;
            let values: Vec<f32> = raw
                .chunks_exact(4)
                .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
                .collect();
            if let Some(k) = values.iter().position(|v| !v.is_finite()) {
                return Err(r.error(
                    at + 4 * k,
                    &format!("tensor {name} holds a non-finite value at index {k}"),
                ));
            }
            tensors.push(values);
        }
        if r.at != bytes.len() {
            return Err(r.error(
                r.at,
                &format!("{} bytes after the last tensor", bytes.len() - r.at),
            ));
        }
        Ok(Self { tensors })
    }

    /// The weights as a file (the inverse of [`SileroWeights::parse`]); `None` when a tensor
    /// does not have its shape's number of values.
    pub fn to_bytes(&self) -> Option<Vec<u8>> {
        if self.tensors.len() != TENSORS.len() {
            return None;
        }
        let mut out = Vec::with_capacity(SHIPPED_LEN);
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&VERSION.to_le_bytes());
        out.extend_from_slice(&(TENSORS.len() as u32).to_le_bytes());
        for ((name, shape), values) in TENSORS.iter().zip(&self.tensors) {
            if values.len() != shape.iter().product::<usize>() {
                return None;
            }
            out.extend_from_slice(&(name.len() as u32).to_le_bytes());
            out.extend_from_slice(name.as_bytes());
            out.extend_from_slice(&(shape.len() as u32).to_le_bytes());
            for d in *shape {
                out.extend_from_slice(&(*d as u32).to_le_bytes());
            }
            for v in values {
                out.extend_from_slice(&v.to_le_bytes());
            }
        }
        Some(out)
    }
}

/// A cursor over the file's bytes.
struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    fn error(&self, at: usize, message: &str) -> SileroWeightsError {
        SileroWeightsError::Format {
            at,
            message: message.to_string(),
        }
    }

    fn take(&mut self, n: usize) -> Result<&'a [u8], SileroWeightsError> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.bytes.len());
        let Some(end) = end else {
            return Err(self.error(
                self.at,
                &format!(
                    "the file ends after {} bytes, {n} more were expected here",
                    self.bytes.len()
                ),
            ));
        };
        let s = &self.bytes[self.at..end];
        self.at = end;
        Ok(s)
    }

    fn u32(&mut self) -> Result<u32, SileroWeightsError> {
        let b = self.take(4)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shipped_file_passes_every_check_and_writes_back_bit_for_bit() {
        let w = SileroWeights::parse(SHIPPED).expect("the shipped weights parse");
        assert_eq!(w.to_bytes().as_deref(), Some(SHIPPED));
    }

    #[test]
    fn a_changed_or_cut_file_is_rejected_with_what_to_do() {
        let mut changed = SHIPPED.to_vec();
        changed[1000] ^= 1;
        let e = SileroWeights::parse(&changed).unwrap_err();
        assert!(matches!(e, SileroWeightsError::Digest { .. }), "{e}");
        assert!(e.to_string().contains("cargo xtask silero-weights"), "{e}");
        let e = SileroWeights::parse(&SHIPPED[..SHIPPED.len() - 4]).unwrap_err();
        assert!(matches!(e, SileroWeightsError::Digest { .. }), "{e}");
        // Without the digest check, the format checks name the place.
        let cut = SileroWeights::parse_unchecked(&SHIPPED[..SHIPPED.len() - 4]).unwrap_err();
        assert!(cut.to_string().contains("the file ends"), "{cut}");
        let mut magic = SHIPPED.to_vec();
        magic[0] = b'X';
        let e = SileroWeights::parse_unchecked(&magic).unwrap_err();
        assert!(e.to_string().contains("magic"), "{e}");
        let mut version = SHIPPED.to_vec();
        version[8] = 2;
        let e = SileroWeights::parse_unchecked(&version).unwrap_err();
        assert!(e.to_string().contains("version 2"), "{e}");
        // The first tensor's name starts at byte 20: a wrong name is named.
        let mut name = SHIPPED.to_vec();
        name[20] = b'X';
        let e = SileroWeights::parse_unchecked(&name).unwrap_err();
        assert_eq!(
            e,
            SileroWeightsError::Format {
                at: 16,
                message: "expected tensor model.stft.forward_basis_buffer, found \"Xodel.stft.forward_basis_buffer\"".into()
            }
        );
        let mut nan = SHIPPED.to_vec();
        let first_value = 16 + 4 + TENSORS[0].0.len() + 4 + 3 * 4;
        nan[first_value..first_value + 4].copy_from_slice(&f32::NAN.to_le_bytes());
        let e = SileroWeights::parse_unchecked(&nan).unwrap_err();
        assert!(e.to_string().contains("non-finite value at index 0"), "{e}");
        let mut longer = SHIPPED.to_vec();
        longer.push(0);
        let e = SileroWeights::parse_unchecked(&longer).unwrap_err();
        assert!(
            e.to_string().contains("1 bytes after the last tensor"),
            "{e}"
        );
    }
}
