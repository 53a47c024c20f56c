//! A folder of built tables, so that a renderer (or any front end) builds each table once.
//!
//! A table is keyed by what decides its values: the material (self-contained, so a WIF pattern
//! counts by its content), the wavelength, the grid options (not the thread count) and the file
//! format version. The key names the file, `NAME-KEY.wtab`, in the cache folder
//! ([`Cache::default_dir`]: `$XDG_CACHE_HOME/woven`, else `~/.cache/woven`).
//!
//! A cached file is never trusted: it is loaded with every check of [`Table::load`] (checksum,
//! header), and its recorded material, wavelength and grid must be the ones asked for. A damaged,
//! foreign or stale file is a [`Lookup::Miss`] with the reason, and the caller rebuilds it;
//! [`Cache::store`] writes atomically (a temporary file, then a rename), so two processes filling
//! the same entry never leave a half file.

use super::{grid_of, Table, TableOptions};
use crate::error::{Error, Result};
use crate::material::Material;
use crate::progress::Progress;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A folder of cached tables.
#[derive(Clone, Debug)]
pub struct Cache {
    dir: PathBuf,
}

/// What [`Cache::lookup`] found.
#[derive(Debug)]
pub enum Lookup {
    /// A valid table for the request, from `path`.
    Hit {
        /// The table.
        table: Box<Table>,
        /// Where it was read from.
        path: PathBuf,
    },
    /// No valid table: build one and [`store`](Cache::store) it at `path`.
    Miss {
        /// Where the table belongs.
        path: PathBuf,
        /// Why a file there was not used (`None`: there was none).
        reason: Option<String>,
    },
}

impl Cache {
    /// A cache in `dir` (created when a table is first stored).
    pub fn new(dir: impl Into<PathBuf>) -> Cache {
        Cache { dir: dir.into() }
    }

    /// The user's cache folder for woven: `$XDG_CACHE_HOME/woven` when `XDG_CACHE_HOME` is an
    /// absolute path, else `$HOME/.cache/woven`; `None` when neither is set.
    pub fn default_dir() -> Option<PathBuf> {
        let absolute = |name: &str| {
            std::env::var_os(name)
                .map(PathBuf::from)
                .filter(|p| p.is_absolute())
        };
        absolute("XDG_CACHE_HOME")
            .map(|d| d.join("woven"))
            .or_else(|| absolute("HOME").map(|h| h.join(".cache").join("woven")))
    }

    /// The cache in [`default_dir`](Self::default_dir).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] when neither `XDG_CACHE_HOME` nor `HOME` is set.
    pub fn user() -> Result<Cache> {
        Cache::default_dir().map(Cache::new).ok_or_else(|| {
            Error::invalid(
                "cache folder",
                "(none)",
                "XDG_CACHE_HOME or HOME set to an absolute path (or skip the cache)",
            )
        })
    }

    /// The folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Where the table of `material` at `wavelength_nm` with `options` is kept.
    pub fn path(&self, material: &Material, wavelength_nm: f64, options: &TableOptions) -> PathBuf {
        let name: String = material
            .name
            .as_deref()
            .unwrap_or("material")
            .chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                    c
                } else {
                    '_'
                }
            })
            .take(40)
            .collect();
        let key = key(material, wavelength_nm, options);
        self.dir.join(format!("{name}-{key}.wtab"))
    }

    /// Looks the table up, checking that the file is intact and is the table asked for.
    pub fn lookup(
        &self,
        material: &Material,
        wavelength_nm: f64,
        options: &TableOptions,
    ) -> Lookup {
        let path = self.path(material, wavelength_nm, options);
        match std::fs::metadata(&path) {
            Err(_) => return Lookup::Miss { path, reason: None },
            // A folder, a device or a pipe in the table's place is not read (a pipe would block).
            Ok(meta) if !meta.is_file() => {
                let reason = format!("{}: not a regular file", path.display());
                return Lookup::Miss {
                    path,
                    reason: Some(reason),
                };
            }
            Ok(_) => {}
        }
        let reason = match Table::load(&path) {
            Err(e) => e.to_string(),
            Ok(table) => match mismatch(&table, material, wavelength_nm, options) {
                None => {
                    return Lookup::Hit {
                        table: Box::new(table),
                        path,
                    }
                }
                Some(m) => format!("{}: {m}", path.display()),
            },
        };
        Lookup::Miss {
            path,
            reason: Some(reason),
        }
    }

    /// Stores `table` at `path` (from [`Lookup::Miss`]), creating the folder, atomically.
    ///
    /// # Errors
    /// [`Error::Io`] naming the folder or the file; also when something other than a regular
    /// file is in the table's place (a pipe would block the write, a device swallow it).
    pub fn store(&self, path: &Path, table: &Table) -> Result<()> {
        std::fs::create_dir_all(&self.dir).map_err(|source| Error::Io {
            path: self.dir.clone(),
            source,
        })?;
        if std::fs::metadata(path).is_ok_and(|m| !m.is_file()) {
            return Err(Error::Io {
                path: path.to_path_buf(),
                source: std::io::Error::new(
                    std::io::ErrorKind::InvalidInput,
                    "not a regular file: the cache writes only its own files",
                ),
            });
        }
        table.save(path)
    }

    /// The table from the cache, or built (`build`) and stored; `notice` hears of a build before
    /// it starts (with the reason an existing file was not used) and of a store that failed (the
    /// table is still returned: a read-only cache only costs time).
    ///
    /// # Errors
    /// Whatever `build` returns.
    pub fn load_or_build(
        &self,
        material: &Material,
        wavelength_nm: f64,
        options: &TableOptions,
        build: impl FnOnce() -> Result<Table>,
        notice: &dyn Fn(Notice<'_>),
    ) -> Result<Table> {
        match self.lookup(material, wavelength_nm, options) {
            Lookup::Hit { table, path } => {
                notice(Notice::Loaded { path: &path });
                Ok(*table)
            }
            Lookup::Miss { path, reason } => {
                notice(Notice::Building {
                    path: &path,
                    reason: reason.as_deref(),
                });
                let table = build()?;
                if let Err(e) = self.store(&path, &table) {
                    notice(Notice::NotStored { error: &e });
                }
                Ok(table)
            }
        }
    }
}

/// What [`Cache::load_or_build`] tells its caller.
#[derive(Debug)]
pub enum Notice<'a> {
    /// The table was read from `path`.
    Loaded {
        /// The file.
        path: &'a Path,
    },
    /// The table is being built, to be stored at `path`; `reason` says why a file there was not
    /// used.
    Building {
        /// The file it will be stored in.
        path: &'a Path,
        /// Why an existing file was refused.
        reason: Option<&'a str>,
    },
    /// The built table could not be stored.
    NotStored {
        /// Why.
        error: &'a Error,
    },
}

/// The tables a front end has had so far, by material, wavelength and grid (materials that share
/// a yarn share its table), over an optional [`Cache`] folder: the one place that knows how a
/// table is had. A crowned table ([`TableOptions::crown_deg`] > 0) is built from the plain table
/// of the same grid (itself had the same way); any other from the material's exact model.
#[derive(Default)]
pub struct Tables {
    memory: HashMap<String, Arc<Table>>,
    disk: Option<Cache>,
    note: Option<Note>,
}

/// A listener for [`Tables`]' notes, in words.
type Note = Box<dyn Fn(&str) + Send + Sync>;

impl std::fmt::Debug for Tables {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Tables")
            .field("tables", &self.memory.len())
            .field("disk", &self.disk)
            .finish_non_exhaustive()
    }
}

impl Tables {
    /// Tables also kept in `disk` (e.g. [`Cache::user`]): a table built once is loaded on later
    /// runs; a damaged or foreign file is rebuilt.
    pub fn with_disk(disk: Cache) -> Tables {
        Tables {
            disk: Some(disk),
            ..Tables::default()
        }
    }

    /// `note` hears, in words, why a cached file was not used (it is rebuilt) and why a built
    /// table (or a surface's ratio table) could not be stored (the work goes on).
    pub fn with_notes(mut self, note: impl Fn(&str) + Send + Sync + 'static) -> Tables {
        self.note = Some(Box::new(note));
        self
    }

    /// The folder tables are kept in, if any.
    pub fn disk(&self) -> Option<&Cache> {
        self.disk.as_ref()
    }

    /// Tells the notes' listener, if any.
    pub fn note(&self, message: &str) {
        if let Some(note) = &self.note {
            note(message);
        }
    }

    /// Holds `table` as the table of `material` at `wavelength_nm` on `options` (for this
    /// session only: it is not stored on disk): a table a caller built its own way, from which
    /// crowned tables are then built.
    pub fn insert(
        &mut self,
        material: &Material,
        wavelength_nm: f64,
        options: &TableOptions,
        table: Arc<Table>,
    ) {
        self.memory
            .insert(memory_key(material, wavelength_nm, options), table);
    }

    /// The table of `material` at `wavelength_nm` on `options`: from memory, from disk, or built
    /// (`on_build` is called first, with the file it will be kept in, if any; `progress` gets
    /// `(done, total)` rows).
    ///
    /// # Errors
    /// An invalid material or options.
    pub fn table(
        &mut self,
        material: &Material,
        wavelength_nm: f64,
        options: &TableOptions,
        on_build: &dyn Fn(Option<&Path>),
        progress: &dyn Progress,
    ) -> Result<Arc<Table>> {
        let key = memory_key(material, wavelength_nm, options);
        if let Some(t) = self.memory.get(&key) {
            return Ok(Arc::clone(t));
        }
        let base = if options.crown_deg > 0.0 {
            let plain = TableOptions {
                crown_deg: 0.0,
                ..*options
            };
            Some(self.table(material, wavelength_nm, &plain, on_build, progress)?)
        } else {
            None
        };
        let build = || -> Result<Table> {
            match &base {
                Some(base) => base.crowned_with(options, progress),
                None => Table::build(&material.build(wavelength_nm)?, material, options, progress),
            }
        };
        let table = match &self.disk {
            None => {
                on_build(None);
                build()?
            }
            Some(disk) => {
                disk.load_or_build(material, wavelength_nm, options, build, &|n| match n {
                    Notice::Building { path, reason } => {
                        if let Some(r) = reason {
                            self.note(&format!("not using the cached table ({r})"));
                        }
                        on_build(Some(path));
                    }
                    Notice::NotStored { error } => {
                        self.note(&format!("the table could not be cached ({error})"));
                    }
                    Notice::Loaded { .. } => {}
                })?
            }
        };
        let table = Arc::new(table);
        self.memory.insert(key, Arc::clone(&table));
        Ok(table)
    }
}

/// The in-memory key: everything that decides a table's values, as text.
fn memory_key(material: &Material, wavelength_nm: f64, options: &TableOptions) -> String {
    let grid = TableOptions {
        threads: 0,
        ..*options
    };
    format!(
        "{grid:?}\n{}\n{}",
        wavelength_nm.to_bits(),
        material.to_self_contained_toml_string()
    )
}

/// The cache key: a 64-bit FNV-1a hash, in hex, of everything that decides a table's values.
fn key(material: &Material, wavelength_nm: f64, options: &TableOptions) -> String {
    let grid = TableOptions {
        threads: 0,
        ..*options
    };
    let text = format!(
        "woven table format {} build {}\n{:?}\n{}\n{}",
        super::format::VERSION,
        super::build::REVISION,
        grid,
        wavelength_nm.to_bits(),
        material.to_self_contained_toml_string()
    );
    format!("{:016x}", fnv1a(FNV_BASIS, text.as_bytes()))
}

/// FNV-1a's offset basis: the hash of nothing (every cache key's start).
pub(crate) const FNV_BASIS: u64 = 0xcbf2_9ce4_8422_2325;

/// The 64-bit FNV-1a hash `h` extended by `bytes` (a cache file's key).
pub(crate) fn fnv1a(h: u64, bytes: &[u8]) -> u64 {
    bytes.iter().fold(h, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// Why a loaded `table` is not the one asked for (a hash collision or an edited file), if it is
/// not.
fn mismatch(
    table: &Table,
    material: &Material,
    wavelength_nm: f64,
    options: &TableOptions,
) -> Option<String> {
    let want = material.to_self_contained_toml_string();
    if table
        .material()
        .map(Material::to_self_contained_toml_string)
        != Some(want)
    {
        return Some("it holds another material".into());
    }
    if table.wavelength_nm() != wavelength_nm {
        return Some(format!(
            "it holds wavelength {} nm, not {wavelength_nm} nm",
            table.wavelength_nm()
        ));
    }
    if table.crown_deg() != options.crown_deg {
        return Some(format!(
            "it is crowned at {}°, not {}°",
            table.crown_deg(),
            options.crown_deg
        ));
    }
    let grid = grid_of(table.symmetry(), options);
    if table.dims() != grid
        || (table.theta_max_deg() - options.theta_max_deg).abs() > 1e-9
        || table.is_dyeable() != options.colour
    {
        return Some(format!(
            "it holds grid {:?} (theta_max {}°, colour {}), not {grid:?} ({}°, colour {})",
            table.dims(),
            table.theta_max_deg(),
            table.is_dyeable(),
            options.theta_max_deg,
            options.colour
        ));
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tiny() -> TableOptions {
        TableOptions {
            n_theta: 6,
            n_phi: 3,
            n_h: 9,
            n_h_isotropic: 9,
            azimuth_nodes: 16,
            ..TableOptions::default()
        }
    }

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("woven-cache-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        dir
    }

    /// A build whose progress asks to stop returns [`Error::Cancelled`] within a row per worker,
    /// and keeps nothing, plain or crowned (the crown pass hears the same question); asked again
    /// without the stop, the same call builds the table.
    #[test]
    fn a_cancelled_build_stops_within_rows_and_caches_nothing() {
        use std::sync::atomic::{AtomicUsize, Ordering::SeqCst};
        let dir = scratch("cancelled");
        let m = Material::preset("silk-crepe-de-chine")
            .unwrap()
            .yarn_family();
        let plain = tiny();
        let crowned = TableOptions {
            crown_deg: crate::relief::CROWN_DEG,
            ..plain
        };
        let files = || std::fs::read_dir(&dir).map_or(0, |d| d.count());
        let mut tables = Tables::with_disk(Cache::new(&dir));
        for asks in [0, 3] {
            let (rows, asked) = (AtomicUsize::new(0), AtomicUsize::new(0));
            let stop_after = crate::progress::Hooks {
                update: |_: usize, _: usize| {
                    rows.fetch_add(1, SeqCst);
                },
                cancelled: || asked.fetch_add(1, SeqCst) >= asks,
            };
            let got = tables.table(&m, 550.0, &plain, &|_| {}, &stop_after);
            assert!(matches!(got, Err(Error::Cancelled)), "{asks} asks: {got:?}");
            let done = rows.load(SeqCst);
            assert!(
                done <= asks + rayon::current_num_threads(),
                "{asks} asks: {done} rows"
            );
            assert_eq!(files(), 0, "{asks} asks: a cancelled build left a file");
        }
        // The crowned table from a plain one already kept: its crown pass stops.
        let never = |_: usize, _: usize| {};
        tables.table(&m, 550.0, &plain, &|_| {}, &never).unwrap();
        assert_eq!(files(), 1);
        let stop = crate::progress::Hooks {
            update: never,
            cancelled: || true,
        };
        let got = tables.table(&m, 550.0, &crowned, &|_| {}, &stop);
        assert!(matches!(got, Err(Error::Cancelled)), "crowned: {got:?}");
        assert_eq!(files(), 1, "a cancelled crown pass left a file");
        let table = tables.table(&m, 550.0, &crowned, &|_| {}, &never);
        assert!(table.is_ok(), "{table:?}");
        assert_eq!(files(), 2);
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// `Tables`: one table per material and grid in memory; a crowned table built from its yarn's
    /// plain table (the same values as `Table::build` with the crown); both kept on disk, so a
    /// second session builds nothing; a damaged file is rebuilt and the notes say why.
    #[test]
    fn tables_share_build_crowned_tables_from_plain_ones_and_keep_both() {
        let dir = scratch("tables");
        let m = Material::preset("silk-crepe-de-chine")
            .unwrap()
            .yarn_family();
        let plain = tiny();
        let crowned = TableOptions {
            crown_deg: crate::relief::CROWN_DEG,
            colour: true,
            ..plain
        };
        let builds = std::sync::atomic::AtomicUsize::new(0);
        let on_build = |_: Option<&Path>| {
            builds.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        };
        let quiet = |_: usize, _: usize| {};
        let heard = Arc::new(std::sync::Mutex::new(Vec::<String>::new()));
        let sink = Arc::clone(&heard);
        let mut tables = Tables::with_disk(Cache::new(&dir))
            .with_notes(move |m| sink.lock().unwrap().push(m.into()));
        let c = tables
            .table(&m, 550.0, &crowned, &on_build, &quiet)
            .unwrap();
        // The crowned table and its plain base: two builds, two files.
        assert_eq!(builds.load(std::sync::atomic::Ordering::Relaxed), 2);
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 2);
        let again = tables
            .table(&m, 550.0, &crowned, &on_build, &quiet)
            .unwrap();
        assert!(
            Arc::ptr_eq(&c, &again),
            "a second request is served from memory"
        );
        let direct = Table::build(&m.build(550.0).unwrap(), &m, &crowned, &|_, _| {}).unwrap();
        assert_eq!(c.values(), direct.values());

        // A new session loads both; a damaged crowned file is rebuilt from the loaded base.
        let path = Cache::new(&dir).path(&m, 550.0, &crowned);
        let mut bytes = std::fs::read(&path).unwrap();
        let at = bytes.len() / 2;
        bytes[at] ^= 0x40;
        std::fs::write(&path, &bytes).unwrap();
        let mut tables = Tables::with_disk(Cache::new(&dir)).with_notes({
            let sink = Arc::clone(&heard);
            move |m| sink.lock().unwrap().push(m.into())
        });
        let reloaded = tables
            .table(&m, 550.0, &crowned, &on_build, &quiet)
            .unwrap();
        assert_eq!(builds.load(std::sync::atomic::Ordering::Relaxed), 3);
        assert_eq!(reloaded.values(), direct.values());
        let notes = heard.lock().unwrap().clone();
        assert!(
            notes.len() == 1 && notes[0].contains("checksum"),
            "{notes:?}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn builds_once_then_loads_and_rebuilds_damaged_entries() {
        let dir = scratch("damage");
        let cache = Cache::new(&dir);
        let m = Material::from_toml_str(
            "name = \"flat rough\"\n[fiber]\neta = 1.5\nroughness = 0.3\n",
            "test",
        )
        .unwrap();
        let options = tiny();
        let builds = std::cell::Cell::new(0);
        let build = || {
            builds.set(builds.get() + 1);
            Table::build(&m.build(550.0).unwrap(), &m, &options, &|_, _| {})
        };
        let quiet = |_: Notice<'_>| {};
        let a = cache
            .load_or_build(&m, 550.0, &options, build, &quiet)
            .unwrap();
        assert_eq!(builds.get(), 1);
        let path = cache.path(&m, 550.0, &options);
        assert!(path.exists(), "{path:?}");
        assert!(path
            .file_name()
            .unwrap()
            .to_str()
            .unwrap()
            .starts_with("flat_rough-"));
        let b = cache
            .load_or_build(&m, 550.0, &options, build, &quiet)
            .unwrap();
        assert_eq!(builds.get(), 1, "a valid entry is loaded");
        assert_eq!(a.values(), b.values());

        // A flipped byte: the checksum refuses it, the entry is rebuilt and replaced.
        let mut bytes = std::fs::read(&path).unwrap();
        let at = bytes.len() / 2;
        bytes[at] ^= 0x40;
        std::fs::write(&path, &bytes).unwrap();
        let reason = match cache.lookup(&m, 550.0, &options) {
            Lookup::Miss { reason, .. } => reason.unwrap(),
            Lookup::Hit { .. } => panic!("a damaged entry was trusted"),
        };
        assert!(reason.contains("checksum"), "{reason}");
        cache
            .load_or_build(&m, 550.0, &options, build, &quiet)
            .unwrap();
        assert_eq!(builds.get(), 2);
        assert!(matches!(
            cache.lookup(&m, 550.0, &options),
            Lookup::Hit { .. }
        ));

        // A valid table of another material at this entry's path is refused too.
        let other = Material::from_toml_str("[fiber]\neta = 1.5\nroughness = 0.2\n", "t").unwrap();
        Table::build(&other.build(550.0).unwrap(), &other, &options, &|_, _| {})
            .unwrap()
            .save(&path)
            .unwrap();
        match cache.lookup(&m, 550.0, &options) {
            Lookup::Miss { reason, .. } => {
                assert!(reason.unwrap().contains("another material"))
            }
            Lookup::Hit { .. } => panic!("a foreign table was trusted"),
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// A folder or a named pipe where a table belongs is neither read nor written (a pipe
    /// with no writer would block both): the table is built and the store refused.
    #[test]
    fn a_special_file_in_a_tables_place_is_not_used() {
        let dir = scratch("special");
        let cache = Cache::new(&dir);
        let m = Material::from_toml_str("[fiber]\neta = 1.5\nroughness = 0.3\n", "t").unwrap();
        let options = tiny();
        let path = cache.path(&m, 550.0, &options);
        std::fs::create_dir_all(&path).unwrap();
        let mut kinds = vec![path.clone()];
        #[cfg(unix)]
        {
            let fifo = dir.join(format!(
                "pipe-{}",
                path.file_name().unwrap().to_str().unwrap()
            ));
            if std::process::Command::new("mkfifo")
                .arg(&fifo)
                .status()
                .is_ok_and(|s| s.success())
            {
                kinds.push(fifo);
            }
        }
        for special in kinds {
            if special != path {
                std::fs::remove_dir_all(&path).unwrap();
                std::fs::rename(&special, &path).unwrap();
            }
            match cache.lookup(&m, 550.0, &options) {
                Lookup::Miss { reason, .. } => {
                    assert!(reason.unwrap().ends_with("not a regular file"))
                }
                Lookup::Hit { .. } => panic!("a special file was read"),
            }
            let stored = std::cell::Cell::new(true);
            let table = cache.load_or_build(
                &m,
                550.0,
                &options,
                || Table::build(&m.build(550.0).unwrap(), &m, &options, &|_, _| {}),
                &|n| {
                    if let Notice::NotStored { .. } = n {
                        stored.set(false);
                    }
                },
            );
            assert!(table.is_ok() && !stored.get());
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn keys_follow_what_decides_the_values() {
        let cache = Cache::new("/nonexistent");
        let m = Material::preset("silk").unwrap();
        let o = tiny();
        let p = cache.path(&m, 550.0, &o);
        assert_eq!(p, cache.path(&m, 550.0, &TableOptions { threads: 3, ..o }));
        assert_ne!(p, cache.path(&m, 551.0, &o));
        assert_ne!(
            p,
            cache.path(&m, 550.0, &TableOptions { colour: true, ..o })
        );
        assert_ne!(p, cache.path(&m, 550.0, &TableOptions { n_h: 11, ..o }));
        let mut dyed = m.clone();
        dyed.fiber.diffuse = 0.3;
        assert_ne!(p, cache.path(&dyed, 550.0, &o));
    }
}
