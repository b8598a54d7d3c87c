//! Pneuma's mark in the PNG files it writes: a `tEXt` chunk `Software` = `pneuma <version>`,
//! right after the `IHDR` chunk (PNG's own keyword for the program that made an image; image
//! viewers show it). The plot is encoded by plotters, which writes no text chunks, so the chunk
//! is put into the finished file ([`mark`]); [`is_marked`] finds it in a file's first bytes, so
//! a render removes only a plot it wrote itself ([`crate::render::leftovers`]).

/// The PNG signature.
const SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', b'\r', b'\n', 0x1a, b'\n'];
/// The keyword of the mark's text chunk.
const KEYWORD: &str = "Software";
/// What the mark's text starts with (the version follows).
const PROGRAM: &str = "pneuma ";
/// Bytes of a chunk around its data: length, type, CRC.
const CHUNK_FRAME: usize = 12;

/// The mark's text: `pneuma <version>`.
fn software() -> String {
    format!("{PROGRAM}{}", env!("CARGO_PKG_VERSION"))
}

/// The chunks of `png` from the first after the signature, as (type, data), up to the first
/// that does not lie whole in `png` (a file's head holds the first few).
fn chunks(png: &[u8]) -> impl Iterator<Item = ([u8; 4], &[u8])> {
    let mut at = if png.starts_with(&SIGNATURE) {
        SIGNATURE.len()
    } else {
        png.len()
    };
    std::iter::from_fn(move || {
        let len = u32::from_be_bytes(png.get(at..at + 4)?.try_into().ok()?) as usize;
        let kind: [u8; 4] = png.get(at + 4..at + 8)?.try_into().ok()?;
        let data = png.get(at + 8..(at + 8).checked_add(len)?)?;
        at += CHUNK_FRAME + len;
        Some((kind, data))
    })
}

/// CRC-32 of PNG chunks (ISO 3309, polynomial 0xEDB88320): `crc32fast`, which the plot's PNG
/// encoder already builds (through flate2).
fn crc32(bytes: &[u8]) -> u32 {
    crc32fast::hash(bytes)
}

/// `png` with the mark after its `IHDR` chunk; `None` when `png` does not start with one.
pub fn mark(png: &[u8]) -> Option<Vec<u8>> {
    let (kind, ihdr) = chunks(png).next()?;
    if &kind != b"IHDR" {
        return None;
    }
    let after_ihdr = SIGNATURE.len() + CHUNK_FRAME + ihdr.len();
    let mut body = b"tEXt".to_vec();
    body.extend_from_slice(KEYWORD.as_bytes());
    body.push(0);
    body.extend_from_slice(software().as_bytes());
    let head = png.get(..after_ihdr)?;
    let mut out = Vec::with_capacity(png.len() + body.len() + 8);
    out.extend_from_slice(head);
    out.extend_from_slice(&(body.len() as u32 - 4).to_be_bytes());
    out.extend_from_slice(&body);
    out.extend_from_slice(&crc32(&body).to_be_bytes());
    out.extend_from_slice(&png[after_ihdr..]);
    Some(out)
}

/// `head`, a file's first bytes, is a PNG with the mark among its chunks before the image data.
pub fn is_marked(head: &[u8]) -> bool {
    let mut text = KEYWORD.as_bytes().to_vec();
    text.push(0);
    text.extend_from_slice(PROGRAM.as_bytes());
    chunks(head)
        .take_while(|(kind, _)| kind != b"IDAT")
        .any(|(kind, data)| &kind == b"tEXt" && data.starts_with(&text))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 1 × 1 grey PNG as plotters' encoder writes one: IHDR, IDAT, IEND.
    fn tiny_png() -> Vec<u8> {
        let dir = tempfile::tempdir().expect("temp");
        let path = dir.path().join("p.png");
        {
            use plotters::prelude::*;
            let root = BitMapBackend::new(&path, (1, 1)).into_drawing_area();
            root.fill(&RGBColor(128, 128, 128)).expect("fill");
            root.present().expect("present");
        }
        std::fs::read(&path).expect("read")
    }

    #[test]
    fn the_crc_is_pngs() {
        assert_eq!(crc32(b"123456789"), 0xCBF4_3926);
        // The encoder's own IHDR CRC.
        let png = tiny_png();
        let crc = u32::from_be_bytes(png[29..33].try_into().expect("4 bytes"));
        assert_eq!(crc32(&png[12..29]), crc);
    }

    #[test]
    fn a_marked_png_keeps_its_chunks_and_carries_the_mark_where_an_unmarked_does_not() {
        let png = tiny_png();
        assert!(!is_marked(&png));
        let marked = mark(&png).expect("a PNG");
        assert!(is_marked(&marked));
        // Every chunk whole, the text one second, its CRC right, the rest unchanged.
        let all: Vec<([u8; 4], &[u8])> = chunks(&marked).collect();
        let kinds: Vec<&[u8]> = all.iter().map(|(k, _)| &k[..]).collect();
        assert_eq!(kinds, [&b"IHDR"[..], b"tEXt", b"IDAT", b"IEND"]);
        let text = format!("Software\0pneuma {}", env!("CARGO_PKG_VERSION"));
        assert_eq!(all[1].1, text.as_bytes());
        let end = 33 + CHUNK_FRAME + text.len();
        let crc = u32::from_be_bytes(marked[end - 4..end].try_into().expect("4 bytes"));
        assert_eq!(crc32(&marked[37..end - 4]), crc);
        assert_eq!(marked[end..], png[33..]);
        // Not a PNG, or another program's text: no mark.
        assert!(mark(b"GIF89a").is_none() && !is_marked(b"GIF89a"));
        let mut other = marked.clone();
        let at = other
            .windows(7)
            .position(|w| w == b"pneuma ")
            .expect("the mark");
        other[at..at + 7].copy_from_slice(b"GIMP 2 ");
        assert!(!is_marked(&other));
    }
}
