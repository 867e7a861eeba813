//! Reading an input file: only regular files, and only up to [`MAX_INPUT_BYTES`], so that a
//! device (`/dev/zero`), a FIFO or a mistaken multi-gigabyte file is refused with a message
//! instead of exhausting memory.

use std::io::Read;
use std::path::Path;

/// The largest input file read (1 GiB: a dataset of a few million parts; the largest real
/// datasets seen are under 1 MB).
pub const MAX_INPUT_BYTES: u64 = 1 << 30;

/// Why an input file cannot be read.
#[derive(Debug, thiserror::Error)]
pub enum InputError {
    #[error("{0}")]
    Io(#[from] std::io::Error),
    /// A directory, a device, a FIFO or a socket.
    #[error("not a regular file")]
    NotAFile,
    /// Larger than [`MAX_INPUT_BYTES`].
    #[error("the file holds more than {} bytes; it is not read", MAX_INPUT_BYTES)]
    TooLarge,
}

/// `bytes` as text: as they are when they are UTF-8 (no copy), else with each invalid
/// sequence replaced by U+FFFD.
pub fn text_of(bytes: Vec<u8>) -> String {
    String::from_utf8(bytes).unwrap_or_else(|e| String::from_utf8_lossy(e.as_bytes()).into_owned())
}

/// The bytes of the regular file at `path` (symbolic links followed), at most
/// [`MAX_INPUT_BYTES`].
pub fn read_input(path: &Path) -> Result<Vec<u8>, InputError> {
    let meta = std::fs::metadata(path)?;
    if !meta.is_file() {
        return Err(InputError::NotAFile);
    }
    if meta.len() > MAX_INPUT_BYTES {
        return Err(InputError::TooLarge);
    }
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    // The file may grow while it is read: never past the bound.
    std::fs::File::open(path)?
        .take(MAX_INPUT_BYTES + 1)
        .read_to_end(&mut bytes)?;
    if bytes.len() as u64 > MAX_INPUT_BYTES {
        return Err(InputError::TooLarge);
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn devices_and_directories_are_refused() {
        assert!(matches!(
            read_input(Path::new("/dev/zero")),
            Err(InputError::NotAFile)
        ));
        assert!(matches!(
            read_input(&std::env::temp_dir()),
            Err(InputError::NotAFile)
        ));
        assert!(matches!(
            read_input(Path::new("/no/such/file")),
            Err(InputError::Io(_))
        ));
    }
}
