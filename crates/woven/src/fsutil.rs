//! Writing files so that a reader never sees half of one.

use crate::error::{Error, Result};
use std::io::{self, Write};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Writes `path` atomically: `write` fills a new temporary file in the same folder, which is
/// synced and renamed over `path`, so `path` never holds a partial file; on failure the temporary
/// file is removed. A `path` that exists and is not a regular file (a device such as `/dev/null`,
/// a pipe) is written in place instead — renaming over it would replace the device. A read-only
/// `path` is refused. A library cannot catch signals: a process killed while writing leaves the
/// temporary file `.NAME.PID-N.tmp` beside `path` (see [`atomic_write_with`] for a hook).
///
/// # Errors
/// [`Error::Io`] naming `path`.
pub(crate) fn atomic_write(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> Result<()> {
    atomic_write_with(path, |_| (), write).map_err(|e| {
        let source = match e {
            AtomicWriteError::NotAFile => {
                io::Error::new(io::ErrorKind::InvalidInput, "not a file path")
            }
            AtomicWriteError::ReadOnly => io::Error::new(
                io::ErrorKind::PermissionDenied,
                "the file is read-only: refusing to replace it (make it writable, or write elsewhere)",
            ),
            AtomicWriteError::Io { source, .. } | AtomicWriteError::Write(source) => source,
        };
        Error::Io {
            path: path.to_path_buf(),
            source,
        }
    })
}

/// Why [`atomic_write_with`] failed; `path` is untouched in every case (a special file may have
/// received part of the output).
#[derive(Debug)]
pub enum AtomicWriteError<E> {
    /// The path names no file (a root, or ending in `..`).
    NotAFile,
    /// The path is a read-only regular file: refused rather than replaced (the rename would
    /// succeed, since it needs only the folder to be writable).
    ReadOnly,
    /// A step on the file itself failed.
    Io {
        /// Which step.
        step: WriteStep,
        /// The error.
        source: io::Error,
    },
    /// The caller's `write` returned an error of its own.
    Write(E),
}

/// The steps of [`atomic_write_with`] on the file system.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WriteStep {
    /// Opening a special file (a device, a pipe) for writing in place.
    Open,
    /// Creating the temporary file beside the path.
    CreateTemporary,
    /// Writing, flushing or syncing the output.
    Write,
    /// Renaming the temporary file onto the path.
    Rename,
}

/// The one atomic writer: what `atomic_write` (the library's files) and the command line's
/// outputs use. `write` fills a buffered temporary file `.NAME.PID-N.tmp` in `path`'s folder;
/// when it returns `Ok`, the file is flushed, synced and renamed onto `path`, and `write`'s value
/// returned. On any error the temporary file is removed and an existing `path` is untouched.
///
/// `on_temp` is called with the temporary file's path before anything is written, and its value
/// is dropped once the file is renamed or removed: a program that catches signals registers the
/// path there for removal on interruption. A `path` that exists and is no regular file
/// (`/dev/null`, a named pipe) is written in place (`on_temp` is not called); a read-only regular
/// file is refused.
///
/// # Errors
/// [`AtomicWriteError`]: the step that failed, or `write`'s own error.
pub fn atomic_write_with<T, E, G>(
    path: &Path,
    on_temp: impl FnOnce(&Path) -> G,
    write: impl FnOnce(&mut dyn Write) -> std::result::Result<T, E>,
) -> std::result::Result<T, AtomicWriteError<E>> {
    let io = |step| move |source| AtomicWriteError::Io { step, source };
    let meta = std::fs::metadata(path);
    if meta.as_ref().is_ok_and(|m| !m.is_file() && !m.is_dir()) {
        let file = std::fs::OpenOptions::new()
            .write(true)
            .open(path)
            .map_err(io(WriteStep::Open))?;
        let mut out = io::BufWriter::with_capacity(1 << 16, file);
        let value = write(&mut out).map_err(AtomicWriteError::Write)?;
        out.flush().map_err(io(WriteStep::Write))?;
        return Ok(value);
    }
    if meta.is_ok_and(|m| m.is_file() && m.permissions().readonly()) {
        return Err(AtomicWriteError::ReadOnly);
    }
    let Some(name) = path.file_name() else {
        return Err(AtomicWriteError::NotAFile);
    };
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    // A name unique within this process (counter) and among processes (pid).
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let (tmp, file) = loop {
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let tmp = dir.join(format!(
            ".{}.{}-{n}.tmp",
            name.to_string_lossy(),
            std::process::id()
        ));
        match std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&tmp)
        {
            Ok(file) => break (tmp, file),
            // A leftover of an earlier process with the same pid: try the next name.
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists && n < 1000 => continue,
            Err(e) => return Err(io(WriteStep::CreateTemporary)(e)),
        }
    };
    let guard = on_temp(&tmp);
    let result = (|| {
        let mut out = io::BufWriter::with_capacity(1 << 16, file);
        let value = write(&mut out).map_err(AtomicWriteError::Write)?;
        let file = out
            .into_inner()
            .map_err(|e| io(WriteStep::Write)(e.into_error()))?;
        file.sync_all().map_err(io(WriteStep::Write))?;
        drop(file);
        std::fs::rename(&tmp, path).map_err(io(WriteStep::Rename))?;
        Ok(value)
    })();
    if result.is_err() {
        // The temporary file is ours and incomplete; a failure to remove it changes nothing.
        let _ = std::fs::remove_file(&tmp);
    }
    drop(guard);
    result
}

/// `bytes` as a size for messages: `16 MiB`, `512 KiB`, or bytes.
pub(crate) fn human_size(bytes: u64) -> String {
    if bytes >= 1 << 20 && bytes % (1 << 20) == 0 {
        format!("{} MiB", bytes >> 20)
    } else if bytes >= 1 << 10 && bytes % (1 << 10) == 0 {
        format!("{} KiB", bytes >> 10)
    } else {
        format!("{bytes} bytes")
    }
}

/// Reads the whole of `path` as UTF-8 text, refusing a file longer than `cap` bytes without
/// reading more than `cap + 1` (an endless stream such as `/dev/zero` or a pipe stops there).
/// `what` names the kind of file in the message (`a material file`).
///
/// # Errors
/// [`Error::Io`] naming `path` if it cannot be read or is not UTF-8; [`Error::Parse`] naming
/// `path`, the limit and `what` if it is longer than `cap`.
pub(crate) fn read_text_capped(path: &Path, cap: u64, what: &str) -> Result<String> {
    use std::io::Read;
    let io_error = |source| Error::Io {
        path: path.to_path_buf(),
        source,
    };
    let file = std::fs::File::open(path).map_err(io_error)?;
    let mut bytes = Vec::new();
    file.take(cap + 1)
        .read_to_end(&mut bytes)
        .map_err(io_error)?;
    if bytes.len() as u64 > cap {
        return Err(Error::Parse {
            path: path.display().to_string(),
            message: format!(
                "larger than {}, the most {what} may hold (is it the file meant?)",
                human_size(cap)
            ),
        });
    }
    String::from_utf8(bytes).map_err(|_| {
        io_error(io::Error::new(
            io::ErrorKind::InvalidData,
            format!("not UTF-8 text, so not {what}"),
        ))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_read_as_people_write_them() {
        assert_eq!(human_size(16 << 20), "16 MiB");
        assert_eq!(human_size(512 << 10), "512 KiB");
        assert_eq!(human_size(1000), "1000 bytes");
    }

    #[cfg(unix)]
    #[test]
    fn an_endless_stream_stops_at_the_cap() {
        let e = read_text_capped(Path::new("/dev/zero"), 1 << 16, "a test file").unwrap_err();
        let m = e.to_string();
        assert!(
            m.starts_with("/dev/zero: larger than 64 KiB, the most a test file may hold"),
            "{m}"
        );
    }

    #[test]
    fn text_at_the_cap_is_read() {
        let dir = std::env::temp_dir().join(format!("woven-fsutil-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("f.txt");
        std::fs::write(&path, "abcd").unwrap();
        assert_eq!(read_text_capped(&path, 4, "x").unwrap(), "abcd");
        assert!(read_text_capped(&path, 3, "x").is_err());
        std::fs::write(&path, [0xff, 0xfe]).unwrap();
        let m = read_text_capped(&path, 4, "a WIF file")
            .unwrap_err()
            .to_string();
        assert!(m.contains("f.txt") && m.contains("not UTF-8"), "{m}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
