//! Writing files so that a reader never sees half of one, and reading files without letting a
//! wrong path (a device such as `/dev/zero`, a pipe, a folder, a huge file) fill memory or block.

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
pub fn atomic_write(
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

/// The message for a file longer than `cap` bytes (`len`: its size where known).
fn too_large(path: &Path, len: Option<u64>, cap: u64, what: &str) -> Error {
    let size = len.map(|n| format!("{n} bytes, ")).unwrap_or_default();
    Error::Parse {
        path: path.display().to_string(),
        message: format!(
            "{size}larger than {}, the most {what} may hold (is it the file meant?)",
            human_size(cap)
        ),
    }
}

/// What a file system entry is, in words, for one that is not a regular file.
fn kind_of(t: std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return "a named pipe";
        }
        if t.is_char_device() {
            return "a character device";
        }
        if t.is_block_device() {
            return "a block device";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    if t.is_dir() {
        "a folder"
    } else {
        "not a regular file"
    }
}

/// Checks `meta`, the metadata of `path`: a regular file of at most `cap` bytes.
fn check_meta(path: &Path, meta: &std::fs::Metadata, cap: u64, what: &str) -> Result<u64> {
    if !meta.is_file() {
        return Err(Error::Parse {
            path: path.display().to_string(),
            message: format!(
                "{}, not a regular file: {what} is read only from a regular file",
                kind_of(meta.file_type())
            ),
        });
    }
    if meta.len() > cap {
        return Err(too_large(path, Some(meta.len()), cap, what));
    }
    Ok(meta.len())
}

/// Checks, without opening it, that `path` is a regular file (not a folder, a device such as
/// `/dev/zero` that never ends, or a pipe that may block forever) of at most `cap` bytes, and
/// returns its length. `what` names the kind of file in messages (`an OBJ mesh`).
///
/// # Errors
/// [`Error::Io`] naming `path` if it cannot be examined; [`Error::Parse`] naming `path` and what
/// it is if it is not a regular file, or its size and `cap` if it is larger.
///
/// # Examples
/// ```
/// use std::path::Path;
/// let e = woven::fsutil::check_regular(Path::new("."), 1 << 20, "a scene file").unwrap_err();
/// assert_eq!(
///     e.to_string(),
///     ".: a folder, not a regular file: a scene file is read only from a regular file"
/// );
/// ```
pub fn check_regular(path: &Path, cap: u64, what: &str) -> Result<u64> {
    let meta = std::fs::metadata(path).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })?;
    check_meta(path, &meta, cap, what)
}

/// Opens `path` for reading after [`check_regular`]'s checks (made again on the file opened, in
/// case the path changed in between); returns the file and its length. A reader still bounds
/// what it reads ([`read_regular`], [`BoundedText`]): a file may grow while it is read.
///
/// # Errors
/// As [`check_regular`]; [`Error::Io`] naming `path` if it cannot be opened.
pub fn open_regular(path: &Path, cap: u64, what: &str) -> Result<(std::fs::File, u64)> {
    let io_error = |source| Error::Io {
        path: path.to_path_buf(),
        source,
    };
    check_regular(path, cap, what)?;
    let file = std::fs::File::open(path).map_err(io_error)?;
    let len = check_meta(path, &file.metadata().map_err(io_error)?, cap, what)?;
    Ok((file, len))
}

/// The whole of `path`, a regular file of at most `cap` bytes ([`open_regular`]); never reads
/// more than `cap + 1` bytes, even from a file that grows meanwhile.
///
/// # Errors
/// As [`open_regular`]; [`Error::Io`] if reading fails; [`Error::Parse`] naming the limit if the
/// file grew past it.
pub fn read_regular(path: &Path, cap: u64, what: &str) -> Result<Vec<u8>> {
    use std::io::Read;
    let (file, len) = open_regular(path, cap, what)?;
    let mut bytes = Vec::with_capacity(len as usize);
    file.take(cap + 1)
        .read_to_end(&mut bytes)
        .map_err(|source| Error::Io {
            path: path.to_path_buf(),
            source,
        })?;
    if bytes.len() as u64 > cap {
        return Err(too_large(path, None, cap, what));
    }
    Ok(bytes)
}

/// Reads the whole of `path` as UTF-8 text: [`read_regular`] (a folder, a device or a pipe is
/// refused before it is opened, so a FIFO without a writer cannot block the read).
/// `what` names the kind of file in the message (`a material file`).
///
/// # Errors
/// [`Error::Io`] naming `path` if it cannot be read or is not UTF-8; [`Error::Parse`] naming
/// `path` and `what` if it is not a regular file, or the limit if it is longer than `cap`.
pub(crate) fn read_text_capped(path: &Path, cap: u64, what: &str) -> Result<String> {
    let bytes = read_regular(path, cap, what)?;
    String::from_utf8(bytes).map_err(|_| Error::Io {
        path: path.to_path_buf(),
        source: io::Error::new(
            io::ErrorKind::InvalidData,
            format!("not UTF-8 text, so not {what}"),
        ),
    })
}

/// Which bound [`BoundedText`] refused at.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum TextLimit {
    /// Line `line` (1-based) is longer than the limit, in bytes.
    Line {
        /// The line.
        line: u64,
        /// The most bytes a line may hold (without its newline).
        limit: usize,
    },
    /// The text is longer than the limit, in bytes.
    Total {
        /// The most bytes the text may hold.
        limit: u64,
    },
}

impl std::fmt::Display for TextLimit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            TextLimit::Line { line, limit } => {
                write!(
                    f,
                    "line {line} is longer than {}",
                    human_size(*limit as u64)
                )
            }
            TextLimit::Total { limit } => write!(f, "longer than {}", human_size(*limit)),
        }
    }
}

/// A buffered text reader for line-by-line parsers (through [`io::BufRead`]) that never holds
/// more than one chunk and never passes on a line longer than `max_line` bytes or more than
/// `max_total` bytes in all: at either it returns an [`io::ErrorKind::InvalidData`] error, and
/// [`limit_hit`](Self::limit_hit) says which (for parsers that replace the reader's error with
/// their own).
pub struct BoundedText<R> {
    inner: R,
    buf: Box<[u8]>,
    /// The next byte to hand out.
    pos: usize,
    /// The end of the bytes that may be handed out (the first byte of an over-long line, or
    /// `end`).
    allowed: usize,
    /// The end of the bytes read into `buf`.
    end: usize,
    /// The length of the line running at `allowed`.
    line_len: usize,
    /// The 1-based number of the line running at `allowed`.
    line: u64,
    /// Bytes read from `inner` so far.
    total: u64,
    max_line: usize,
    max_total: u64,
    hit: Option<TextLimit>,
}

impl<R: io::Read> BoundedText<R> {
    /// The bytes read in at a time.
    const CHUNK: usize = 1 << 16;

    /// Reads `inner` with lines of at most `max_line` bytes (newline excluded) and at most
    /// `max_total` bytes in all.
    pub fn new(inner: R, max_line: usize, max_total: u64) -> Self {
        BoundedText {
            inner,
            buf: vec![0; Self::CHUNK].into_boxed_slice(),
            pos: 0,
            allowed: 0,
            end: 0,
            line_len: 0,
            line: 1,
            total: 0,
            max_line,
            max_total,
            hit: None,
        }
    }

    /// The bound the text broke, once reading has stopped at it.
    pub fn limit_hit(&self) -> Option<&TextLimit> {
        self.hit.as_ref()
    }

    /// Marks `limit` hit and returns it as an I/O error.
    fn refuse(&mut self, limit: TextLimit) -> io::Error {
        let e = io::Error::new(io::ErrorKind::InvalidData, limit.to_string());
        self.hit = Some(limit);
        e
    }
}

impl<R: io::Read> io::Read for BoundedText<R> {
    fn read(&mut self, out: &mut [u8]) -> io::Result<usize> {
        use io::BufRead;
        let avail = self.fill_buf()?;
        let n = avail.len().min(out.len());
        out[..n].copy_from_slice(&avail[..n]);
        self.consume(n);
        Ok(n)
    }
}

impl<R: io::Read> io::BufRead for BoundedText<R> {
    fn fill_buf(&mut self) -> io::Result<&[u8]> {
        if let Some(limit) = self.hit.clone() {
            return Err(self.refuse(limit));
        }
        if self.pos == self.end {
            // Everything handed out: read the next chunk and find how much of it may pass.
            let n = loop {
                match self.inner.read(&mut self.buf) {
                    Ok(n) => break n,
                    Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                    Err(e) => return Err(e),
                }
            };
            self.total += n as u64;
            if self.total > self.max_total {
                return Err(self.refuse(TextLimit::Total {
                    limit: self.max_total,
                }));
            }
            (self.pos, self.end, self.allowed) = (0, n, n);
            for (i, &b) in self.buf[..n].iter().enumerate() {
                if b == b'\n' {
                    (self.line_len, self.line) = (0, self.line + 1);
                } else if self.line_len == self.max_line {
                    self.allowed = i;
                    break;
                } else {
                    self.line_len += 1;
                }
            }
        }
        if self.pos == self.allowed && self.allowed < self.end {
            // The bytes before the over-long line's excess are out: refuse at it.
            let (line, limit) = (self.line, self.max_line);
            return Err(self.refuse(TextLimit::Line { line, limit }));
        }
        Ok(&self.buf[self.pos..self.allowed])
    }

    fn consume(&mut self, amt: usize) {
        self.pos = (self.pos + amt).min(self.allowed);
    }
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
    fn text_is_read_from_a_regular_file_within_the_cap() {
        // An endless device is refused before it is opened; a file over the cap by its size.
        let e = read_text_capped(Path::new("/dev/zero"), 1 << 16, "a test file").unwrap_err();
        let m = e.to_string();
        assert!(
            m.starts_with("/dev/zero: a character device, not a regular file: a test file"),
            "{m}"
        );
        let dir = scratch("text-cap");
        let path = dir.join("big.txt");
        std::fs::write(&path, vec![b'a'; (1 << 16) + 1]).unwrap();
        let m = read_text_capped(&path, 1 << 16, "a test file")
            .unwrap_err()
            .to_string();
        assert!(
            m.contains("the most a test file may hold is 64 KiB") || m.contains("64 KiB"),
            "{m}"
        );
        std::fs::write(&path, "short").unwrap();
        assert_eq!(
            read_text_capped(&path, 1 << 16, "a test file").unwrap(),
            "short"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A fresh folder for one test.
    fn scratch(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("woven-fsutil-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[cfg(unix)]
    #[test]
    fn devices_pipes_and_folders_are_refused_before_reading() {
        let m = check_regular(Path::new("/dev/zero"), 1 << 20, "an OBJ mesh")
            .unwrap_err()
            .to_string();
        assert_eq!(
            m,
            "/dev/zero: a character device, not a regular file: an OBJ mesh is read only from a \
             regular file"
        );
        let dir = scratch("kinds");
        let m = read_regular(&dir, 1 << 20, "an OBJ mesh")
            .unwrap_err()
            .to_string();
        assert!(m.contains("woven-fsutil-kinds") && m.contains("a folder, not a regular file"));
        // A named pipe with no writer: opening it would block forever, so it must be refused
        // from its metadata alone.
        let fifo = dir.join("pipe");
        match std::process::Command::new("mkfifo").arg(&fifo).status() {
            Ok(s) if s.success() => {
                let m = open_regular(&fifo, 1 << 20, "an environment map")
                    .unwrap_err()
                    .to_string();
                assert!(m.contains("pipe: a named pipe, not a regular file"), "{m}");
            }
            _ => eprintln!("mkfifo unavailable: the pipe case is skipped"),
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_file_over_the_limit_is_refused_with_its_size() {
        let dir = scratch("size");
        let path = dir.join("big.obj");
        std::fs::write(&path, [b'v'; 2049]).unwrap();
        assert_eq!(read_regular(&path, 2049, "x").unwrap().len(), 2049);
        let m = read_regular(&path, 2048, "an OBJ mesh")
            .unwrap_err()
            .to_string();
        assert!(
            m.ends_with("big.obj: 2049 bytes, larger than 2 KiB, the most an OBJ mesh may hold (is it the file meant?)"),
            "{m}"
        );
        assert_eq!(check_regular(&path, 4096, "x").unwrap(), 2049);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// Every line of `text` through [`BoundedText`], or the limit it stopped at.
    fn lines_of(text: &[u8], max_line: usize, max_total: u64) -> Result<usize, TextLimit> {
        use io::BufRead;
        let mut r = BoundedText::new(text, max_line, max_total);
        let mut n = 0;
        for line in (&mut r).lines() {
            if line.is_err() {
                return Err(r.limit_hit().cloned().expect("a limit"));
            }
            n += 1;
        }
        Ok(n)
    }

    #[test]
    fn bounded_text_stops_at_a_long_line_or_a_long_text() {
        assert_eq!(lines_of(b"ab\ncde\n\nfgh", 3, 100), Ok(4));
        assert_eq!(
            lines_of(b"ab\ncdef\n", 3, 100),
            Err(TextLimit::Line { line: 2, limit: 3 })
        );
        assert_eq!(
            lines_of(b"ab\ncd\n", 3, 5),
            Err(TextLimit::Total { limit: 5 })
        );
        // A line longer than a chunk, and lines across chunks.
        let mut long = vec![b'x'; 3 * BoundedText::<&[u8]>::CHUNK];
        assert_eq!(
            lines_of(&long, 1 << 17, u64::MAX),
            Err(TextLimit::Line {
                line: 1,
                limit: 1 << 17
            })
        );
        for k in (0..long.len()).step_by(1000) {
            long[k] = b'\n';
        }
        let newlines = long.iter().filter(|&&b| b == b'\n').count();
        assert_eq!(lines_of(&long, 999, u64::MAX), Ok(newlines + 1));
        // An endless stream without a newline stops at the line limit.
        let zeros = io::Read::take(io::repeat(0), 1 << 40);
        let mut r = BoundedText::new(zeros, 4096, u64::MAX);
        let mut s = String::new();
        assert!(io::BufRead::read_line(&mut r, &mut s).is_err());
        assert!(s.len() <= 4096, "no more than the limit is handed out");
        assert_eq!(
            r.limit_hit().unwrap().to_string(),
            "line 1 is longer than 4 KiB"
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
