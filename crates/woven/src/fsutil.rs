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
/// temporary file `.NAME.PID-N.tmp` beside `path`.
///
/// # Errors
/// [`Error::Io`] naming `path`.
pub(crate) fn atomic_write(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> Result<()> {
    let io_error = |source| Error::Io {
        path: path.to_path_buf(),
        source,
    };
    if let Ok(meta) = std::fs::metadata(path) {
        if !meta.is_file() {
            let mut file = std::fs::OpenOptions::new()
                .write(true)
                .open(path)
                .map_err(io_error)?;
            return write(&mut file)
                .and_then(|()| file.flush())
                .map_err(io_error);
        }
    }
    // A read-only file is refused, not replaced: the rename needs only the folder writable.
    if std::fs::metadata(path).is_ok_and(|m| m.is_file() && m.permissions().readonly()) {
        return Err(io_error(io::Error::new(
            io::ErrorKind::PermissionDenied,
            "the file is read-only: refusing to replace it (make it writable, or write elsewhere)",
        )));
    }
    let Some(name) = path.file_name() else {
        return Err(io_error(io::Error::new(
            io::ErrorKind::InvalidInput,
            "not a file path",
        )));
    };
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    // A name unique within this process (counter) and among processes (pid).
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let (tmp, mut file) = loop {
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
            Err(e) => return Err(io_error(e)),
        }
    };
    let written = write(&mut file).and_then(|()| file.sync_all());
    drop(file);
    let result = written.and_then(|()| std::fs::rename(&tmp, path));
    if let Err(e) = result {
        // The temporary file is ours and incomplete; a failure to remove it changes nothing.
        let _ = std::fs::remove_file(&tmp);
        return Err(io_error(e));
    }
    Ok(())
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
