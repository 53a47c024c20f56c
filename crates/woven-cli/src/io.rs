//! Input and output plumbing shared by the commands: output folders checked before the work,
//! atomic output files, stdin/stdout, and the formatting of numbers in CSV output.

use anyhow::{bail, Context, Result};
use std::fs::File;
use std::io::{self, BufReader, BufWriter, Read, Write};
use std::path::{Path, PathBuf};

/// Where a command reads its input from: a file, or standard input for `-`.
#[derive(Clone, Debug)]
pub enum InputSource {
    /// Standard input.
    Stdin,
    /// A file on disk.
    File(PathBuf),
}

impl InputSource {
    /// Parses a command-line value: `-` is standard input, anything else a path.
    pub fn parse(value: &str) -> Result<Self, String> {
        match value {
            "" => Err("expected a file path, or `-` for standard input".into()),
            "-" => Ok(InputSource::Stdin),
            path => Ok(InputSource::File(PathBuf::from(path))),
        }
    }

    /// Opens the source for buffered reading.
    pub fn open(&self) -> Result<Box<dyn Read + Send>> {
        Ok(match self {
            InputSource::Stdin => Box::new(io::stdin()),
            InputSource::File(path) => Box::new(BufReader::with_capacity(
                1 << 16,
                File::open(path)
                    .with_context(|| format!("cannot open input file `{}`", path.display()))?,
            )),
        })
    }
}

impl std::fmt::Display for InputSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            InputSource::Stdin => f.write_str("<stdin>"),
            InputSource::File(path) => write!(f, "{}", path.display()),
        }
    }
}

/// Checks that every output's folder exists, before a (slow) computation.
pub fn check_output_dirs(outputs: &[PathBuf]) -> Result<()> {
    for path in outputs {
        let dir = match path.parent() {
            Some(parent) if !parent.as_os_str().is_empty() => parent,
            _ => Path::new("."),
        };
        if !dir.is_dir() {
            bail!(
                "--output `{}`: directory `{}` does not exist",
                path.display(),
                dir.display()
            );
        }
    }
    Ok(())
}

/// Writes a file so that it either appears complete or not at all: the library's
/// [`woven::fsutil::atomic_write_with`] (a temporary file beside `path`, renamed into place;
/// special files such as `/dev/null` written in place; a read-only `path` refused), with the
/// temporary file registered for removal if the process is interrupted (SIGINT, SIGTERM, SIGHUP)
/// while writing. SIGKILL cannot be caught, and leaves the temporary file (named `.NAME.*.tmp`)
/// behind.
///
/// # Errors
/// Every error names `path`: an output that cannot be created, written or renamed, and a write
/// failure inside `write` (a full disk). Other errors of `write` (a bad input row) are passed on
/// as they are.
pub fn write_atomically<T>(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> Result<T>,
) -> Result<T> {
    use woven::fsutil::{atomic_write_with, AtomicWriteError, WriteStep};
    let shown = path.display();
    atomic_write_with(path, interrupt::Pending::register, write).map_err(|e| match e {
        AtomicWriteError::NotAFile => {
            anyhow::anyhow!("output path `{shown}` does not name a file")
        }
        AtomicWriteError::ReadOnly => anyhow::anyhow!(
            "`{shown}` is read-only: refusing to replace it (make it writable, or write elsewhere)"
        ),
        AtomicWriteError::Io { step, source } => {
            let what = match step {
                WriteStep::Open => format!("cannot open `{shown}` for writing"),
                WriteStep::CreateTemporary => {
                    let dir = match path.parent() {
                        Some(parent) if !parent.as_os_str().is_empty() => parent,
                        _ => Path::new("."),
                    };
                    format!(
                        "cannot create a temporary file in `{}` for `{shown}`",
                        dir.display()
                    )
                }
                WriteStep::Write => format!("cannot write `{shown}`"),
                WriteStep::Rename => format!("cannot create `{shown}`"),
            };
            anyhow::Error::new(source).context(what)
        }
        // An I/O failure of `write` is a failure to write `path`.
        AtomicWriteError::Write(e) if e.downcast_ref::<io::Error>().is_some() => {
            e.context(format!("cannot write `{shown}`"))
        }
        AtomicWriteError::Write(e) => e,
    })
}

/// Writes each `(path, bytes)` as [`write_atomically`] does, all or none: each file is written
/// (and flushed) to its temporary file inside the previous one's, so the files are renamed in
/// reverse order only once every one is written, and a failure (a full disk) leaves none of
/// them behind: the first, the main output, is renamed last.
///
/// # Errors
/// As [`write_atomically`], for the first file that fails.
pub fn write_all_atomically(files: &[(&Path, &[u8])]) -> Result<()> {
    /// A later file's error, carried through the earlier files' writers unchanged.
    #[derive(Debug)]
    struct Later(anyhow::Error);
    impl std::fmt::Display for Later {
        fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            write!(f, "{:#}", self.0)
        }
    }
    impl std::error::Error for Later {}
    fn nest(files: &[(&Path, &[u8])]) -> Result<()> {
        let Some(((path, bytes), rest)) = files.split_first() else {
            return Ok(());
        };
        write_atomically(path, |w| {
            w.write_all(bytes)?;
            w.flush()?;
            nest(rest).map_err(|e| anyhow::Error::new(Later(e)))
        })
    }
    nest(files).map_err(|e| match e.downcast::<Later>() {
        Ok(Later(inner)) => inner,
        Err(e) => e,
    })
}

/// Removal of unfinished temporary files when the process is interrupted.
mod interrupt {
    use std::path::{Path, PathBuf};
    use std::sync::{Mutex, Once};

    /// The temporary files being written now.
    static PENDING: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

    /// A temporary file registered for removal on interruption while this value lives.
    pub struct Pending(PathBuf);

    impl Pending {
        /// Registers `path` (and installs the signal handler on first use).
        pub fn register(path: &Path) -> Pending {
            static HANDLER: Once = Once::new();
            HANDLER.call_once(|| {
                // SIGINT, SIGTERM and SIGHUP (the `termination` feature). Failure (another
                // handler already set) leaves the default behaviour: the process dies at once.
                let _ = ctrlc::set_handler(|| {
                    let pending = PENDING.lock().unwrap_or_else(|e| e.into_inner());
                    for path in pending.iter() {
                        // Already renamed or removed: nothing left to clean.
                        let _ = std::fs::remove_file(path);
                    }
                    eprintln!("interrupted: no output written");
                    // 128 + SIGINT, the shell's code for an interrupted command.
                    std::process::exit(130);
                });
            });
            lock().push(path.to_path_buf());
            Pending(path.to_path_buf())
        }
    }

    impl Drop for Pending {
        fn drop(&mut self) {
            let mut pending = lock();
            if let Some(i) = pending.iter().position(|p| *p == self.0) {
                pending.swap_remove(i);
            }
        }
    }

    fn lock() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
        // A panic while holding the lock leaves a valid list.
        PENDING.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// Runs `write` on `path` atomically (see [`write_atomically`]), or on standard output when
/// `path` is `None`.
pub fn write_output<T>(
    path: Option<&Path>,
    write: impl FnOnce(&mut dyn Write) -> Result<T>,
) -> Result<T> {
    match path {
        Some(path) => write_atomically(path, write),
        None => {
            let stdout = io::stdout();
            let mut out = BufWriter::with_capacity(1 << 16, stdout.lock());
            let value = write(&mut out)?;
            out.flush().context("cannot write to standard output")?;
            Ok(value)
        }
    }
}

/// Appends `x` to `buf` as the shortest decimal text that reads back as the same `f64`.
///
/// Plain notation for magnitudes in `[1e-5, 1e16)` (and 0), scientific otherwise: Rust's `{}`
/// never switches to an exponent, which would spell 1e-300 with 300 zeros.
pub fn push_f64(buf: &mut String, x: f64) {
    use std::fmt::Write as _;
    let a = x.abs();
    // Writing into a String cannot fail.
    let _ = if a == 0.0 || (1e-5..1e16).contains(&a) || !a.is_finite() {
        write!(buf, "{x}")
    } else {
        write!(buf, "{x:e}")
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    fn format_f64(x: f64) -> String {
        let mut s = String::new();
        push_f64(&mut s, x);
        s
    }

    #[test]
    fn numbers_round_trip_in_short_form() {
        for x in [
            0.0, 1.0, 0.1, 123.456, 1e-5, 9.99e-6, 1e-300, 3.5e20, 1e16, -2.5e-7,
        ] {
            let s = format_f64(x);
            assert_eq!(s.parse::<f64>().unwrap(), x, "{s}");
            assert!(s.len() < 26, "{s}");
        }
        assert_eq!(format_f64(0.25), "0.25");
        assert_eq!(format_f64(1e-300), "1e-300");
    }

    #[test]
    fn atomic_write_leaves_nothing_on_error() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.csv");
        let r: Result<()> = write_atomically(&path, |w| {
            w.write_all(b"partial")?;
            anyhow::bail!("boom")
        });
        assert!(r.is_err());
        assert!(!path.exists());
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);

        write_atomically(&path, |w| Ok(w.write_all(b"done")?)).unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"done");
    }

    /// Whether `path` exists and is neither a regular file nor a folder: a device such as
    /// `/dev/null`, or a named pipe.
    fn is_special_file(path: &Path) -> bool {
        std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir())
    }

    #[cfg(unix)]
    #[test]
    fn special_files_are_written_in_place_not_replaced() {
        // A named pipe stands in for /dev/null (which a regression would destroy).
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("pipe");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if !made.is_ok_and(|s| s.success()) {
            eprintln!("mkfifo unavailable: skipped");
            return;
        }
        assert!(is_special_file(&fifo));
        let reader = {
            let fifo = fifo.clone();
            std::thread::spawn(move || std::fs::read(fifo).unwrap())
        };
        write_atomically(&fifo, |w| Ok(w.write_all(b"through")?)).unwrap();
        assert_eq!(reader.join().unwrap(), b"through");
        assert!(is_special_file(&fifo), "the pipe must stay a pipe");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
        assert!(is_special_file(Path::new("/dev/null")));
        assert!(!is_special_file(Path::new("Cargo.toml")));
        assert!(!is_special_file(Path::new("src")));
        assert!(!is_special_file(Path::new("no-such-file")));
    }
}
