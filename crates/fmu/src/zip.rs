//! A zip archive of whole files in memory, deflated (APPNOTE 6.3: local headers, data, the
//! central directory, the end record; no ZIP64, so at most 4 GiB and 65535 entries). Every
//! entry is dated 1980-01-01 00:00, so the same contents give the same bytes.

use std::io::Write;

/// An entry: its path inside the archive (`/`-separated) and its bytes.
pub struct Entry {
    pub path: String,
    pub data: Vec<u8>,
    /// Unix permissions recorded for it (0o644, or 0o755 for a binary).
    pub mode: u32,
}

/// Why an archive cannot be made.
#[derive(Debug, thiserror::Error)]
pub enum ZipError {
    #[error("{0} is too large for a zip without ZIP64 (4 GiB)")]
    TooLarge(String),
    #[error("too many files for a zip without ZIP64 (65535)")]
    TooMany,
    #[error("cannot deflate {path}: {cause}")]
    Deflate { path: String, cause: std::io::Error },
}

/// MS-DOS date of 1980-01-01 (the earliest a zip can say).
const DOS_DATE: u16 = (1 << 5) | 1;
/// Bit 11: the names are UTF-8.
const UTF8_NAMES: u16 = 1 << 11;
const DEFLATED: u16 = 8;
/// Version 2.0 (deflate); made by Unix (3) for the permissions in the external attributes.
const VERSION_NEEDED: u16 = 20;
const VERSION_MADE_BY: u16 = (3 << 8) | 20;

fn u16le(out: &mut Vec<u8>, v: u16) {
    out.extend_from_slice(&v.to_le_bytes());
}

fn u32le(out: &mut Vec<u8>, v: u32) {
    out.extend_from_slice(&v.to_le_bytes());
}

fn size(path: &str, n: usize) -> Result<u32, ZipError> {
    u32::try_from(n).map_err(|_| ZipError::TooLarge(path.to_string()))
}

/// The archive of `entries`, in their order.
pub fn archive(entries: &[Entry]) -> Result<Vec<u8>, ZipError> {
    let count = u16::try_from(entries.len()).map_err(|_| ZipError::TooMany)?;
    let mut out = Vec::new();
    let mut central = Vec::new();
    for e in entries {
        let mut encoder =
            flate2::write::DeflateEncoder::new(Vec::new(), flate2::Compression::default());
        let deflated = encoder
            .write_all(&e.data)
            .and_then(|_| encoder.finish())
            .map_err(|cause| ZipError::Deflate {
                path: e.path.clone(),
                cause,
            })?;
        let crc = crc32fast::hash(&e.data);
        let name = e.path.as_bytes();
        let name_len = u16::try_from(name.len()).map_err(|_| ZipError::TooLarge(e.path.clone()))?;
        let offset = size(&e.path, out.len())?;
        let (csize, usize_) = (size(&e.path, deflated.len())?, size(&e.path, e.data.len())?);
        // Local file header.
        u32le(&mut out, 0x0403_4b50);
        u16le(&mut out, VERSION_NEEDED);
        u16le(&mut out, UTF8_NAMES);
        u16le(&mut out, DEFLATED);
        u16le(&mut out, 0);
        u16le(&mut out, DOS_DATE);
        u32le(&mut out, crc);
        u32le(&mut out, csize);
        u32le(&mut out, usize_);
        u16le(&mut out, name_len);
        u16le(&mut out, 0);
        out.extend_from_slice(name);
        out.extend_from_slice(&deflated);
        // Its central directory record.
        u32le(&mut central, 0x0201_4b50);
        u16le(&mut central, VERSION_MADE_BY);
        u16le(&mut central, VERSION_NEEDED);
        u16le(&mut central, UTF8_NAMES);
        u16le(&mut central, DEFLATED);
        u16le(&mut central, 0);
        u16le(&mut central, DOS_DATE);
        u32le(&mut central, crc);
        u32le(&mut central, csize);
        u32le(&mut central, usize_);
        u16le(&mut central, name_len);
        u16le(&mut central, 0); // extra
        u16le(&mut central, 0); // comment
        u16le(&mut central, 0); // disk
        u16le(&mut central, 0); // internal attributes
        u32le(&mut central, (0o100000 | e.mode) << 16);
        u32le(&mut central, offset);
        central.extend_from_slice(name);
    }
    let central_offset = size("the central directory", out.len())?;
    let central_size = size("the central directory", central.len())?;
    out.extend_from_slice(&central);
    // End of central directory.
    u32le(&mut out, 0x0605_4b50);
    u16le(&mut out, 0);
    u16le(&mut out, 0);
    u16le(&mut out, count);
    u16le(&mut out, count);
    u32le(&mut out, central_size);
    u32le(&mut out, central_offset);
    u16le(&mut out, 0);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn archive_ends_with_the_end_record_counting_its_entries() {
        let entries = [
            Entry {
                path: "a.txt".into(),
                data: b"hello hello hello".to_vec(),
                mode: 0o644,
            },
            Entry {
                path: "dir/b.bin".into(),
                data: vec![0; 1000],
                mode: 0o755,
            },
        ];
        let z = archive(&entries).unwrap();
        assert_eq!(&z[..4], &[0x50, 0x4b, 0x03, 0x04]);
        let end = &z[z.len() - 22..];
        assert_eq!(&end[..4], &[0x50, 0x4b, 0x05, 0x06]);
        assert_eq!(u16::from_le_bytes([end[10], end[11]]), 2);
        // 1000 zeros deflate to a few bytes.
        assert!(z.len() < 400, "{} bytes", z.len());
        // The same entries give the same bytes.
        assert_eq!(archive(&entries).unwrap(), z);
    }
}
