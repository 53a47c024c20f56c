//! Input and output plumbing shared by the commands: atomic output files, stdin/stdout, and the
//! formatting of numbers in CSV output.

use anyhow::{Context, Result};
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

/// Writes a file so that it either appears complete or not at all.
///
/// `write` fills a temporary file created next to `path` (same directory, so the final rename
/// stays on one file system); only when it returns `Ok` is the file flushed, synced and renamed
/// onto `path`. On any error the temporary file is deleted and an existing `path` is untouched.
///
/// A `path` that exists but is no regular file (`/dev/null`, a named pipe) is written in place:
/// renaming over it would replace the device with a file.
pub fn write_atomically<T>(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> Result<T>,
) -> Result<T> {
    if is_special_file(path) {
        let file = std::fs::OpenOptions::new()
            .write(true)
            .open(path)
            .with_context(|| format!("cannot open `{}` for writing", path.display()))?;
        let mut out = BufWriter::with_capacity(1 << 16, file);
        let value = write(&mut out)?;
        out.flush()
            .with_context(|| format!("cannot write `{}`", path.display()))?;
        return Ok(value);
    }
    let dir = match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    };
    if path.file_name().is_none() {
        anyhow::bail!("output path `{}` does not name a file", path.display());
    }
    let mut builder = tempfile::Builder::new();
    builder.prefix(".woven-").suffix(".tmp");
    // Output files are ordinary documents: readable by others, like a file `>` would create
    // (tempfile's default, 0600, is meant for secrets).
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o644));
    }
    let tmp = builder.tempfile_in(dir).with_context(|| {
        format!(
            "cannot create a temporary file in `{}` for `{}`",
            dir.display(),
            path.display()
        )
    })?;
    let mut out = BufWriter::with_capacity(1 << 16, tmp);
    let value = write(&mut out)?;
    let tmp = out
        .into_inner()
        .map_err(|e| e.into_error())
        .with_context(|| format!("cannot write `{}`", path.display()))?;
    tmp.as_file()
        .sync_all()
        .with_context(|| format!("cannot write `{}`", path.display()))?;
    tmp.persist(path)
        .map_err(|e| e.error)
        .with_context(|| format!("cannot create `{}`", path.display()))?;
    Ok(value)
}

/// Whether `path` exists and is neither a regular file nor a folder: a device such as
/// `/dev/null`, or a named pipe.
pub fn is_special_file(path: &Path) -> bool {
    std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir())
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
