//! The length of a chained Ogg file: logical streams one after another, as `cat a.ogg b.ogg`
//! or a radio recorder makes. symphonia decodes every link in turn but announces the length of
//! one, so a progress bar sized by it would cover only part of the audio, and the check of the
//! decoded length against the announced one would not see a later link cut short. Here the page
//! headers are read without decoding and the last granule position (the sample frames up to
//! that page) of each link is added up.
//!
//! The granule positions are taken as they are, which is right for the links that are decoded
//! (Vorbis, FLAC). An Opus link's would count its pre-skip too (RFC 7845: the decoded length is
//! the last granule position less the `OpusHead` pre-skip), but no Opus link is decoded: a file
//! whose first link is Opus is refused as Opus when it is sniffed ([`crate::decode`]), and a
//! later Opus link (its first packet begins `OpusHead`) is found here, before any audio is
//! decoded, and the file refused as Opus too ([`OpusLink`]). Were Opus decoded, each link's
//! pre-skip would have to be subtracted here.

use std::io::{BufReader, Read};
use std::path::Path;

use crate::le_bytes::{u32_at, u64_at};
use crate::read_full::read_full;

/// A link of a chained Ogg file that is Opus, which is not decoded.
#[derive(Debug, PartialEq, Eq)]
pub(crate) struct OpusLink {
    /// The link's place in the file, from 1.
    pub number: usize,
}

/// The sample frames of the chained Ogg file at `path`, the sum of its links' last granule
/// positions; `None` for a file of one link (symphonia's count stands), for links of more than
/// one stream each (grouped, e.g. audio with video) and for a file that cannot be read or is no
/// Ogg from its first page (the decoder then says what is wrong). A damaged page ends the count.
/// An Opus link found before the count ends is an error.
pub(crate) fn chained_frames(path: &Path) -> Result<Option<u64>, OpusLink> {
    let mut opus = None;
    let frames = walk_pages(path, &mut opus);
    match opus {
        Some(number) => Err(OpusLink { number }),
        None => Ok(frames),
    }
}

/// [`chained_frames`]' walk over the pages; stops at an Opus link, its number in `opus`.
fn walk_pages(path: &Path, opus: &mut Option<usize>) -> Option<u64> {
    let mut r = BufReader::new(std::fs::File::open(path).ok()?);
    // The last granule position of each link.
    let mut links: Vec<u64> = Vec::new();
    let mut serials: Vec<u32> = Vec::new();
    // A page after the link's beginning-of-stream pages was seen: the next BOS starts a link.
    let mut in_body = false;
    let mut segments = [0u8; 255];
    loop {
        let mut head = [0u8; 27];
        if read_full(&mut r, &mut head).ok()? < head.len() || &head[..4] != b"OggS" {
            break;
        }
        let n = usize::from(head[26]);
        if read_full(&mut r, &mut segments[..n]).ok()? < n {
            break;
        }
        let body: u64 = segments[..n].iter().map(|&s| u64::from(s)).sum();
        let serial = u32_at(&head, 14);
        // The first bytes of the page's body: a beginning-of-stream page's names its codec.
        let mut magic = [0u8; 8];
        let peeked = read_full(&mut r, &mut magic[..body.min(8) as usize]).ok()?;
        if head[5] & 2 != 0 {
            if in_body || links.is_empty() {
                links.push(0);
                serials.clear();
                in_body = false;
            }
            if peeked == 8 && &magic == b"OpusHead" {
                *opus = Some(links.len());
                return None;
            }
            serials.push(serial);
            if serials.len() > 1 {
                return None;
            }
        } else {
            in_body = true;
        }
        let granule = u64_at(&head, 6);
        if granule != u64::MAX && serials.contains(&serial) {
            *links.last_mut()? = granule;
        }
        let rest = body - peeked as u64;
        if std::io::copy(&mut (&mut r).take(rest), &mut std::io::sink()).ok()? < rest {
            break;
        }
    }
    (links.len() > 1).then(|| links.iter().sum())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An Ogg page of stream `serial` (beginning of stream with `bos`) ending at `granule`,
    /// with a body of `body` bytes (the CRC is not checked here).
    fn page(serial: u32, bos: bool, granule: u64, body: usize) -> Vec<u8> {
        let mut p = b"OggS\0".to_vec();
        p.push(if bos { 2 } else { 0 });
        p.extend_from_slice(&granule.to_le_bytes());
        p.extend_from_slice(&serial.to_le_bytes());
        p.extend_from_slice(&[0; 8]); // sequence number, CRC
        let lacing: Vec<u8> = (0..body / 255)
            .map(|_| 255)
            .chain([(body % 255) as u8])
            .collect();
        p.push(lacing.len() as u8);
        p.extend_from_slice(&lacing);
        p.resize(p.len() + body, 0);
        p
    }

    fn write(pages: &[Vec<u8>]) -> (tempfile::TempDir, std::path::PathBuf) {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("x.ogg");
        std::fs::write(&path, pages.concat()).expect("write");
        (dir, path)
    }

    #[test]
    fn the_links_of_a_chained_file_are_added_up() {
        let link = |serial, frames| {
            vec![
                page(serial, true, 0, 30),
                page(serial, false, 0, 300),
                page(serial, false, frames / 2, 600),
                page(serial, false, u64::MAX, 600),
                page(serial, false, frames, 100),
            ]
        };
        let (_d, chained) = write(&[link(7, 1000), link(9, 500), link(7, 20)].concat());
        assert_eq!(chained_frames(&chained), Ok(Some(1520)));
        let (_d, one) = write(&link(7, 1000));
        assert_eq!(
            chained_frames(&one),
            Ok(None),
            "one link: symphonia's count"
        );
        let grouped = [
            page(1, true, 0, 30),
            page(2, true, 0, 30),
            page(1, false, 9, 9),
        ];
        let (_d, grouped) = write(&grouped);
        assert_eq!(chained_frames(&grouped), Ok(None), "streams side by side");
    }

    #[test]
    fn an_opus_link_after_a_vorbis_one_is_found_before_any_audio() {
        let mut vorbis = page(7, true, 0, 30);
        let at = vorbis.len() - 30;
        vorbis[at..at + 7].copy_from_slice(b"\x01vorbis");
        let mut opus = page(9, true, 0, 19);
        let at = opus.len() - 19;
        opus[at..at + 8].copy_from_slice(b"OpusHead");
        let pages = [
            vorbis,
            page(7, false, 1000, 300),
            opus.clone(),
            page(9, false, 960, 100),
        ];
        let (_d, chained) = write(&pages);
        assert_eq!(chained_frames(&chained), Err(OpusLink { number: 2 }));
        // A tiny page body (shorter than the codec name) is no Opus and is walked over.
        let pages = [
            page(7, true, 0, 3),
            page(7, false, 5, 0),
            page(9, true, 0, 3),
        ];
        let (_d, short) = write(&pages);
        assert_eq!(chained_frames(&short), Ok(Some(5)));
    }
}
