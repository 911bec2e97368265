//! Bounded reading of the data files the FMUs and the CLI read: the scene file `scene.toml`,
//! block meshes (OBJ, STL) and modal-body text files (issue #48, docs/bounded_inputs.md).
//!
//! Every such read goes through [`read_bytes`], [`read_text`] or [`read_head`], which
//! 1. look at what the path names, following symbolic links, and refuse anything but a regular
//!    file: a FIFO (reading one blocks until a writer comes, forever inside `fmi2Instantiate`),
//!    a device (`/dev/zero` and `/dev/urandom` never end), a socket, a folder; a symbolic-link
//!    loop and a dangling link are reported as such, not as a missing file;
//! 2. refuse a regular file whose size is over the cap of its kind ([`FileKind`]) before
//!    reading a byte;
//! 3. open the file non-blocking (`O_NONBLOCK`: a FIFO swapped in after step 1 does not block
//!    the open; Windows has no FIFOs in the file system, so there a plain open) and check the
//!    opened file again (`fstat`), so what is read is what was checked;
//! 4. read at most cap + 1 bytes (`Read::take`), so a file that grows while it is read is
//!    refused too, and never holds more than cap + 1 bytes in memory.
//!
//! Every refusal is an `Err` whose text names the kind of file, its path and, for a size, the
//! cap (its value and the name of its constant). What is inside the file (table, key, vertex
//! counts) is bounded by the parser of each format.

use std::fs::{File, FileType, Metadata, OpenOptions};
use std::io::{ErrorKind, Read};
#[cfg(unix)]
use std::os::unix::fs::{FileTypeExt, OpenOptionsExt};
use std::path::Path;

/// A kind of data file: its name for messages and its size cap.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FileKind {
    /// What the file is, for messages ("scene file", "mesh file").
    pub what: &'static str,
    /// Largest size read [bytes].
    pub max_bytes: u64,
    /// The name of the constant that holds `max_bytes`, for messages (docs/bounded_inputs.md
    /// gives each cap with its reason).
    pub cap_name: &'static str,
}

/// Why a file was not read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ReadError {
    /// True when nothing exists at the path (not even a dangling link): a caller may treat an
    /// absent optional file as "none given".
    pub missing: bool,
    /// The message: the kind of file, its path and the cause.
    pub message: String,
}

impl std::fmt::Display for ReadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

impl From<ReadError> for String {
    fn from(e: ReadError) -> String {
        e.message
    }
}

/// `ELOOP` (Linux): the error of a path whose symbolic links loop.
#[cfg(unix)]
const ELOOP: i32 = libc::ELOOP;
/// Windows' `ERROR_CANT_RESOLVE_FILENAME`: its error for a symbolic-link loop.
#[cfg(windows)]
const ELOOP: i32 = 1921;

/// Options that open a file for reading without blocking on a FIFO (Unix: `O_NONBLOCK`).
fn read_options() -> OpenOptions {
    let mut o = OpenOptions::new();
    o.read(true);
    #[cfg(unix)]
    o.custom_flags(libc::O_NONBLOCK);
    o
}

/// What a file that is neither a regular file nor a folder is, for messages.
#[cfg(unix)]
fn special_kind(t: FileType) -> &'static str {
    if t.is_fifo() {
        "a FIFO (named pipe)"
    } else if t.is_char_device() {
        "a character device"
    } else if t.is_block_device() {
        "a block device"
    } else if t.is_socket() {
        "a socket"
    } else {
        "a special file"
    }
}

/// What a file that is neither a regular file nor a folder is, for messages.
#[cfg(not(unix))]
fn special_kind(_: FileType) -> &'static str {
    "a special file"
}

/// `n` bytes for messages: "4 MiB" when it is a whole number of MiB, else "4194305 bytes".
pub fn human_bytes(n: u64) -> String {
    const MIB: u64 = 1024 * 1024;
    if n >= MIB && n.is_multiple_of(MIB) {
        format!("{} MiB", n / MIB)
    } else {
        format!("{n} bytes")
    }
}

/// The bytes of the regular file at `path`, at most `kind.max_bytes` of them (module doc).
pub fn read_bytes(path: &Path, kind: &FileKind) -> Result<Vec<u8>, ReadError> {
    let (file, len) = open_checked(path, kind)?;
    read_capped(file, len, path, kind).map_err(|message| ReadError {
        missing: false,
        message,
    })
}

/// Steps 1-3 of the module doc: the open file and its size.
fn open_checked(path: &Path, kind: &FileKind) -> Result<(File, u64), ReadError> {
    let shown = path.display();
    let refuse = |message: String| ReadError {
        missing: false,
        message,
    };
    let meta = std::fs::metadata(path).map_err(|e| open_error(path, kind, &e))?;
    check_regular(&meta, path, kind).map_err(refuse)?;
    check_size(meta.len(), path, kind).map_err(refuse)?;
    let file = read_options()
        .open(path)
        .map_err(|e| open_error(path, kind, &e))?;
    let opened = file
        .metadata()
        .map_err(|e| refuse(format!("cannot read {} {shown}: {e}", kind.what)))?;
    check_regular(&opened, path, kind).map_err(refuse)?;
    check_size(opened.len(), path, kind).map_err(refuse)?;
    Ok((file, opened.len()))
}

/// The first `n` bytes (fewer if the file is shorter) of the regular file at `path`, with every
/// check of [`read_bytes`] on the whole file: a format whose header gives counts can refuse
/// them before the whole file is read.
pub fn read_head(path: &Path, kind: &FileKind, n: u64) -> Result<Vec<u8>, ReadError> {
    let (file, _) = open_checked(path, kind)?;
    let mut bytes = Vec::new();
    file.take(n.min(kind.max_bytes))
        .read_to_end(&mut bytes)
        .map_err(|e| ReadError {
            missing: false,
            message: format!("cannot read {} {}: {e}", kind.what, path.display()),
        })?;
    Ok(bytes)
}

/// The text of the regular file at `path` (UTF-8), at most `kind.max_bytes` long.
pub fn read_text(path: &Path, kind: &FileKind) -> Result<String, ReadError> {
    let bytes = read_bytes(path, kind)?;
    String::from_utf8(bytes).map_err(|e| ReadError {
        missing: false,
        message: format!(
            "{} {} is not valid UTF-8 text (bad byte at offset {}); save it as UTF-8",
            kind.what,
            path.display(),
            e.utf8_error().valid_up_to()
        ),
    })
}

/// The message for `e`, met when looking at or opening `path`.
fn open_error(path: &Path, kind: &FileKind, e: &std::io::Error) -> ReadError {
    let shown = path.display();
    let what = kind.what;
    let message = if e.raw_os_error() == Some(ELOOP) {
        format!(
            "cannot read {what} {shown}: it is a symbolic-link loop (too many levels of symbolic links)"
        )
    } else if e.kind() == ErrorKind::NotFound {
        match std::fs::read_link(path) {
            Ok(target) => format!(
                "cannot read {what} {shown}: it is a symbolic link to {}, which does not exist",
                target.display()
            ),
            Err(_) if std::fs::symlink_metadata(path).is_err() => {
                return ReadError {
                    missing: true,
                    message: format!("cannot read {what} {shown}: it does not exist"),
                };
            }
            Err(_) => format!("cannot read {what} {shown}: {e}"),
        }
    } else {
        format!("cannot read {what} {shown}: {e}")
    };
    ReadError {
        missing: false,
        message,
    }
}

/// `Err` unless `meta` (of `path`, links followed) is a regular file.
fn check_regular(meta: &Metadata, path: &Path, kind: &FileKind) -> Result<(), String> {
    let t = meta.file_type();
    if t.is_file() {
        return Ok(());
    }
    let is = if t.is_dir() {
        "a folder"
    } else {
        special_kind(t)
    };
    Err(format!(
        "{} {} is not a regular file (it is {is}); only regular files are read, so that reading ends",
        kind.what,
        path.display()
    ))
}

/// `Err` when `len` bytes are over the cap of `kind`.
fn check_size(len: u64, path: &Path, kind: &FileKind) -> Result<(), String> {
    if len <= kind.max_bytes {
        return Ok(());
    }
    Err(over_cap(path, kind, &format!("it has {len} bytes")))
}

/// The message for a file of `kind` at `path` larger than its cap (`has` says by how much).
fn over_cap(path: &Path, kind: &FileKind, has: &str) -> String {
    format!(
        "{} {} is larger than the cap of {} on a {} ({} = {} bytes; docs/bounded_inputs.md): {has}",
        kind.what,
        path.display(),
        human_bytes(kind.max_bytes),
        kind.what,
        kind.cap_name,
        kind.max_bytes,
    )
}

/// At most cap + 1 bytes of `file` (`len` bytes expected); `Err` when there were more than cap.
fn read_capped(file: File, len: u64, path: &Path, kind: &FileKind) -> Result<Vec<u8>, String> {
    let mut bytes = Vec::with_capacity(usize::try_from(len.min(kind.max_bytes)).unwrap_or(0));
    file.take(kind.max_bytes.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|e| format!("cannot read {} {}: {e}", kind.what, path.display()))?;
    if bytes.len() as u64 > kind.max_bytes {
        return Err(over_cap(
            path,
            kind,
            &format!("it grew past {} bytes while being read", kind.max_bytes),
        ));
    }
    Ok(bytes)
}

#[cfg(test)]
#[path = "bounded_file_tests.rs"]
mod tests;
