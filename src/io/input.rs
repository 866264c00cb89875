//! Reading input files within a size cap.
//!
//! Every input file of the crate — scene files (`.toml`, `.json`), Radioss decks, riser
//! decks and URDF descriptions — is read by [`read_input`] (or [`read_input_text`], which
//! calls it), never with `std::fs::read` directly. A file larger than [`MAX_INPUT_BYTES`]
//! (256 MiB) is refused with an [`InputError`] naming the file and the cap, and at most the
//! cap plus one byte is ever held in memory: a file of gigabytes, or a device that never
//! ends such as `/dev/zero`, costs a bounded read, not the machine's memory.
//!
//! Why 256 MiB: a full-vehicle Radioss deck (a few million elements) runs to a couple of
//! hundred MiB and may be given as the deck that holds the KJOINT2 properties; scene files,
//! riser decks and URDF descriptions are kilobytes to a few MiB. Past that, the reader
//! would need several times the file size in memory to parse it. Mesh files named by a URDF
//! are held to the same cap (a larger one is skipped with a notice, see
//! [`super::urdf`]).

use std::io::Read;
use std::path::{Path, PathBuf};

/// The largest input file read, in bytes (256 MiB). The one place the cap is set.
pub const MAX_INPUT_BYTES: u64 = 256 * 1024 * 1024;

/// Why an input file could not be read.
#[derive(Debug, thiserror::Error)]
#[error("{}: {kind}", file.display())]
pub struct InputError {
    /// The file (as given).
    pub file: PathBuf,
    /// What went wrong.
    pub kind: InputErrorKind,
}

/// What went wrong in an [`InputError`] (its text does not repeat the file name, so that
/// readers whose errors already name the file can use it alone).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum InputErrorKind {
    /// The system refused to open or read it.
    #[error("cannot read: {0}")]
    Io(#[source] std::io::Error),
    /// The file is larger than the cap.
    #[error(
        "larger than {}, the size cap of input files (rapier_kjoint::io::MAX_INPUT_BYTES): not read",
        size_text(*cap)
    )]
    TooLarge {
        /// The cap that was applied \[bytes\].
        cap: u64,
    },
    /// The file is not UTF-8 text.
    #[error("not UTF-8 text: invalid bytes at line {line}")]
    NotUtf8 {
        /// 1-based line of the first invalid byte.
        line: usize,
    },
}

impl InputErrorKind {
    /// The error without the `cannot read: ` prefix of [`InputErrorKind::Io`], for readers
    /// whose own message already says "cannot read".
    pub fn reason(&self) -> String {
        match self {
            InputErrorKind::Io(e) => e.to_string(),
            other => other.to_string(),
        }
    }
}

/// `n` bytes as text: `256 MiB`, `64 KiB`, or `100 bytes`.
fn size_text(n: u64) -> String {
    const KIB: u64 = 1024;
    const MIB: u64 = 1024 * 1024;
    if n >= MIB && n % MIB == 0 {
        format!("{} MiB", n / MIB)
    } else if n >= KIB && n % KIB == 0 {
        format!("{} KiB", n / KIB)
    } else {
        format!("{n} bytes")
    }
}

/// Reads a whole input file within [`MAX_INPUT_BYTES`].
pub fn read_input(path: &Path) -> Result<Vec<u8>, InputError> {
    read_input_with_cap(path, MAX_INPUT_BYTES)
}

/// Reads a whole file within `cap` bytes: a regular file whose size exceeds the cap is
/// refused before reading; anything else (a pipe, a device) is read up to `cap + 1` bytes
/// and refused if it gets there.
pub fn read_input_with_cap(path: &Path, cap: u64) -> Result<Vec<u8>, InputError> {
    let err = |kind| InputError {
        file: path.to_path_buf(),
        kind,
    };
    let file = std::fs::File::open(path).map_err(|e| err(InputErrorKind::Io(e)))?;
    let size = file.metadata().map(|m| m.len()).unwrap_or(0);
    if size > cap {
        return Err(err(InputErrorKind::TooLarge { cap }));
    }
    // grown by hand (doubling, never past cap + 1) so that a device that never ends costs
    // cap + 1 bytes, not the next power of two
    let limit = usize::try_from(cap.saturating_add(1)).unwrap_or(usize::MAX);
    let mut bytes = Vec::with_capacity((size as usize).saturating_add(1).min(limit));
    let mut chunk = vec![0u8; 64 * 1024];
    let mut reader = file.take(limit as u64);
    loop {
        let n = match reader.read(&mut chunk) {
            Ok(0) => break,
            Ok(n) => n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(err(InputErrorKind::Io(e))),
        };
        if bytes.len() + n > bytes.capacity() {
            let want = (bytes.capacity() * 2).clamp(bytes.len() + n, limit);
            bytes.reserve_exact(want - bytes.len());
        }
        bytes.extend_from_slice(&chunk[..n]);
    }
    if bytes.len() as u64 > cap {
        return Err(err(InputErrorKind::TooLarge { cap }));
    }
    Ok(bytes)
}

/// Reads a whole input file within [`MAX_INPUT_BYTES`] as UTF-8 text.
pub fn read_input_text(path: &Path) -> Result<String, InputError> {
    text(path, read_input(path)?)
}

/// [`read_input_with_cap`] as UTF-8 text.
pub fn read_input_text_with_cap(path: &Path, cap: u64) -> Result<String, InputError> {
    text(path, read_input_with_cap(path, cap)?)
}

fn text(path: &Path, bytes: Vec<u8>) -> Result<String, InputError> {
    String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        let line = e.as_bytes()[..at].iter().filter(|&&b| b == b'\n').count() + 1;
        InputError {
            file: path.to_path_buf(),
            kind: InputErrorKind::NotUtf8 { line },
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Writes `bytes` into `name` in `dir` (removed with its files when the test drops it).
    fn tmp(dir: &tempfile::TempDir, name: &str, bytes: &[u8]) -> PathBuf {
        let p = dir.path().join(name);
        std::fs::write(&p, bytes).unwrap();
        p
    }

    #[test]
    fn a_file_within_the_cap_is_read_whole() {
        let dir = tempfile::tempdir().unwrap();
        let p = tmp(&dir, "ten.txt", b"0123456789");
        assert_eq!(read_input_with_cap(&p, 10).unwrap(), b"0123456789");
        assert_eq!(read_input_text_with_cap(&p, 100).unwrap(), "0123456789");
    }

    #[test]
    fn a_file_over_the_cap_is_refused_naming_file_and_cap() {
        let dir = tempfile::tempdir().unwrap();
        let p = tmp(&dir, "eleven.txt", b"0123456789a");
        let e = read_input_with_cap(&p, 10).unwrap_err();
        assert!(
            matches!(e.kind, InputErrorKind::TooLarge { cap: 10 }),
            "{e}"
        );
        let msg = e.to_string();
        assert!(msg.starts_with(&p.display().to_string()), "{msg}");
        assert!(msg.contains("larger than 10 bytes"), "{msg}");
        assert!(msg.contains("MAX_INPUT_BYTES"), "{msg}");
    }

    #[cfg(unix)]
    #[test]
    fn dev_zero_is_refused_after_a_bounded_read() {
        let p = Path::new("/dev/zero");
        // a small cap: the device is read up to cap + 1 bytes, then refused
        let e = read_input_with_cap(p, 4096).unwrap_err();
        assert!(
            matches!(e.kind, InputErrorKind::TooLarge { cap: 4096 }),
            "{e}"
        );
        assert_eq!(
            e.to_string(),
            "/dev/zero: larger than 4 KiB, the size cap of input files \
             (rapier_kjoint::io::MAX_INPUT_BYTES): not read"
        );
        // and the real cap
        let e = read_input(p).unwrap_err();
        assert!(e.to_string().contains("larger than 256 MiB"), "{e}");
    }

    #[test]
    fn missing_files_and_invalid_utf8_name_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("no-such-file.toml");
        let e = read_input(&p).unwrap_err();
        assert!(matches!(e.kind, InputErrorKind::Io(_)));
        assert!(e.to_string().starts_with(&p.display().to_string()));
        let p = tmp(&dir, "latin1.txt", b"a\nb\n\xe9t\xe9\n");
        let e = read_input_text(&p).unwrap_err();
        assert!(matches!(e.kind, InputErrorKind::NotUtf8 { line: 3 }), "{e}");
    }
}
