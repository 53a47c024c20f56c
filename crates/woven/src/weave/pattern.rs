//! The binary weave matrix, its named constructors and its weft fraction (Eq. (23); docs/spec.md §2.7).

use crate::error::{Error, Result};
use std::fmt;
use std::path::Path;
use std::str::FromStr;

/// The most rows (picks) or columns (ends) a [`Pattern`] may have.
///
/// A guard against accidental huge allocations (a typo such as `satin-50000` would otherwise ask
/// for 2.5·10⁹ cells); real drafts, even whole-cloth WIF files, stay well below it.
pub const MAX_THREADS: usize = 4096;

/// The longest WIF file [`Pattern::from_wif_path`] reads, in bytes (16 MiB): a full
/// [`MAX_THREADS`]-square draft with one shaft a thread is under 100 KiB a section; the limit
/// stops an endless stream (`/dev/zero`, a pipe) from filling memory.
pub const MAX_WIF_BYTES: u64 = 16 << 20;

/// The names [`Pattern::from_name`] understands, for error messages.
const VALID_NAMES: &str =
    "one of `plain`, `twill-N/M` (N, M ≥ 1), `satin-N` or `sateen-N` (N ≥ 5, N ≠ 6)";

/// A weave pattern: one repeat of a periodic binary matrix, `true` where the weft floats on top.
///
/// Rows are weft picks (successive rows advance along the warp direction `y`); columns are warp
/// ends (successive columns advance along the weft direction `x`); see the [module
/// docs](crate::weave) for the layout and the parameter table. The mean of the matrix is the
/// visible weft fraction `γ` of Eq. (23) (docs/spec.md §2.7).
///
/// Every index wraps around: the pattern tiles the plane. Two patterns compare equal with `==`
/// only when their matrices are identical; [`Pattern::is_shift_of`] compares the cloth they
/// weave, up to a translation.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Pattern {
    /// Number of picks (rows), `1..=MAX_THREADS`.
    rows: usize,
    /// Number of ends (columns), `1..=MAX_THREADS`.
    cols: usize,
    /// Row-major cells, `true` where the weft floats on top.
    cells: Vec<bool>,
}

impl Pattern {
    /// Builds a `rows × cols` pattern from a cell function `weft(row, col)`.
    ///
    /// The caller has checked both sizes against [`MAX_THREADS`].
    pub(crate) fn from_fn(
        rows: usize,
        cols: usize,
        weft: impl Fn(usize, usize) -> bool,
    ) -> Pattern {
        debug_assert!((1..=MAX_THREADS).contains(&rows) && (1..=MAX_THREADS).contains(&cols));
        let mut cells = Vec::with_capacity(rows * cols);
        for r in 0..rows {
            for c in 0..cols {
                cells.push(weft(r, c));
            }
        }
        Pattern { rows, cols, cells }
    }

    /// The plain weave: weft and warp alternate in both directions, `γ = 1/2`.
    ///
    /// The 2 × 2 repeat `.#` / `#.` (the same as `twill-1/1`).
    ///
    /// # Errors
    /// None in practice; the `Result` keeps all constructors alike.
    ///
    /// # Examples
    /// ```
    /// let plain = woven::weave::Pattern::plain()?;
    /// assert_eq!(plain.weft_fraction(), 0.5);
    /// assert_eq!(plain.to_string(), ".#\n#.");
    /// # Ok::<(), woven::Error>(())
    /// ```
    pub fn plain() -> Result<Pattern> {
        Pattern::twill(1, 1)
    }

    /// The twill `over/under`: each warp end passes **over** `over` picks and under `under`,
    /// and each pick repeats the previous one shifted by one end (a diagonal of slope one).
    ///
    /// `twill-2/1` is warp-faced with `γ = 1/3`; in general `γ = under / (over + under)`. The
    /// repeat is `n × n` with `n = over + under`, and the warp lies on top at `(row, col)` when
    /// `(col − row) mod n < over`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `weave.twill.over` or `weave.twill.under` when either is
    /// 0, or `weave.twill` when `over + under` exceeds [`MAX_THREADS`].
    ///
    /// # Examples
    /// ```
    /// let twill = woven::weave::Pattern::twill(2, 1)?;
    /// assert!((twill.weft_fraction() - 1.0 / 3.0).abs() < 1e-15);
    /// assert_eq!(twill.to_string(), "..#\n#..\n.#.");
    /// # Ok::<(), woven::Error>(())
    /// ```
    pub fn twill(over: usize, under: usize) -> Result<Pattern> {
        if over == 0 {
            return Err(Error::invalid("weave.twill.over", over, "an integer ≥ 1"));
        }
        if under == 0 {
            return Err(Error::invalid("weave.twill.under", under, "an integer ≥ 1"));
        }
        let n = match over.checked_add(under) {
            Some(n) if n <= MAX_THREADS => n,
            _ => {
                return Err(Error::invalid(
                    "weave.twill",
                    format!("{over}/{under}"),
                    format!("over + under ≤ {MAX_THREADS}"),
                ))
            }
        };
        // Warp on top for `over` consecutive ends starting at the diagonal `col = row`.
        Ok(Pattern::from_fn(n, n, |r, c| (c + n - r) % n >= over))
    }

    /// The warp-faced `n`-harness satin: the weft shows at exactly one cell per row and per
    /// column, `γ = 1/n`.
    ///
    /// Pick `r` shows its weft at end `(s · r) mod n`, with the usual step `s`: the smallest
    /// integer with `1 < s < n − 1` that is coprime with `n` (5 → 2, 7 → 2, 8 → 3, 10 → 3,
    /// 12 → 5). So no two weft floats of neighbouring picks touch, not even across the wrap.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `weave.satin.n` when `n < 5` or `n = 6` (no such step
    /// exists: no regular satin), or `n >` [`MAX_THREADS`].
    ///
    /// # Examples
    /// ```
    /// let satin = woven::weave::Pattern::satin(5)?;
    /// assert_eq!(satin.weft_fraction(), 0.2);
    /// assert!(woven::weave::Pattern::satin(6).is_err());
    /// # Ok::<(), woven::Error>(())
    /// ```
    pub fn satin(n: usize) -> Result<Pattern> {
        let step = satin_step("weave.satin.n", n)?;
        Ok(Pattern::from_fn(n, n, |r, c| c == (step * r) % n))
    }

    /// The weft-faced `n`-harness sateen: the complement of [`Pattern::satin`], `γ = (n − 1)/n`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `weave.sateen.n` when `n < 5`, `n = 6` or
    /// `n >` [`MAX_THREADS`].
    ///
    /// # Examples
    /// ```
    /// let sateen = woven::weave::Pattern::sateen(5)?;
    /// assert_eq!(sateen.weft_fraction(), 0.8);
    /// # Ok::<(), woven::Error>(())
    /// ```
    pub fn sateen(n: usize) -> Result<Pattern> {
        let step = satin_step("weave.sateen.n", n)?;
        Ok(Pattern::from_fn(n, n, |r, c| c != (step * r) % n))
    }

    /// A pattern from its rows: `matrix[row][col]` is `1` where the weft floats on top and `0`
    /// where the warp does. Rows are picks (along `y`), columns are ends (along `x`).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `weave.pattern` when the matrix is empty, ragged (the
    /// first row whose length differs is named), holds a value other than 0 or 1 (its row and
    /// column are named, counted from 0), or has more than [`MAX_THREADS`] rows or columns.
    ///
    /// # Examples
    /// ```
    /// let basket = woven::weave::Pattern::from_matrix(vec![
    ///     vec![0, 0, 1, 1],
    ///     vec![0, 0, 1, 1],
    ///     vec![1, 1, 0, 0],
    ///     vec![1, 1, 0, 0],
    /// ])?;
    /// assert_eq!(basket.weft_fraction(), 0.5);
    /// # Ok::<(), woven::Error>(())
    /// ```
    pub fn from_matrix(matrix: Vec<Vec<u8>>) -> Result<Pattern> {
        const NAME: &str = "weave.pattern";
        let rows = matrix.len();
        let cols = matrix.first().map_or(0, Vec::len);
        if rows == 0 || cols == 0 {
            return Err(Error::invalid(
                NAME,
                format!("a {rows} × {cols} matrix"),
                "a non-empty matrix of 0 and 1",
            ));
        }
        if rows > MAX_THREADS || cols > MAX_THREADS {
            return Err(Error::invalid(
                NAME,
                format!("a {rows} × {cols} matrix"),
                format!("at most {MAX_THREADS} rows and columns"),
            ));
        }
        let mut cells = Vec::with_capacity(rows * cols);
        for (r, row) in matrix.iter().enumerate() {
            if row.len() != cols {
                return Err(Error::invalid(
                    NAME,
                    format!("row {r} with {} columns", row.len()),
                    format!("a rectangular matrix: every row with {cols} columns, as row 0"),
                ));
            }
            for (c, &x) in row.iter().enumerate() {
                match x {
                    0 => cells.push(false),
                    1 => cells.push(true),
                    _ => {
                        return Err(Error::invalid(
                            NAME,
                            format!("{x} at row {r}, column {c}"),
                            "0 (warp on top) or 1 (weft on top)",
                        ))
                    }
                }
            }
        }
        Ok(Pattern { rows, cols, cells })
    }

    /// A named weave: `plain`, `twill-N/M` (see [`Pattern::twill`]), `satin-N` or `sateen-N`.
    ///
    /// Surrounding whitespace and letter case are ignored. [`Pattern::name`] gives the name back.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `weave.pattern` and listing the valid forms when the
    /// name is not one of them; the constructors' errors when the numbers are out of range.
    ///
    /// # Examples
    /// ```
    /// use woven::weave::Pattern;
    /// let satin = Pattern::from_name("satin-5")?;
    /// assert_eq!(satin.weft_fraction(), 0.2);
    /// assert_eq!(satin.name().as_deref(), Some("satin-5"));
    /// assert!(Pattern::from_name("satin5").is_err());
    /// # Ok::<(), woven::Error>(())
    /// ```
    pub fn from_name(name: &str) -> Result<Pattern> {
        let bad = || Error::invalid("weave.pattern", format!("{name:?}"), VALID_NAMES);
        let number = |s: &str| -> Result<usize> {
            // Digits only: `usize::from_str` would also take a sign (`satin-+5`).
            if s.is_empty() || !s.bytes().all(|b| b.is_ascii_digit()) {
                return Err(bad());
            }
            s.parse().map_err(|_| bad())
        };
        let lower = name.trim().to_ascii_lowercase();
        if lower == "plain" {
            Pattern::plain()
        } else if let Some(rest) = lower.strip_prefix("twill-") {
            let (over, under) = rest.split_once('/').ok_or_else(bad)?;
            Pattern::twill(number(over)?, number(under)?)
        } else if let Some(n) = lower.strip_prefix("satin-") {
            Pattern::satin(number(n)?)
        } else if let Some(n) = lower.strip_prefix("sateen-") {
            Pattern::sateen(number(n)?)
        } else {
            Err(bad())
        }
    }

    /// A pattern from the text of a Weaving Information File (WIF 1.1).
    ///
    /// `origin` names the text in error messages (a path, or `<string>`). The matrix is kept as
    /// drafted (all ends × all picks), not reduced; see [`Pattern::minimal_repeat`].
    ///
    /// What is read:
    /// - sections `[WIF]` (required, marks the format), `[WEAVING]`, `[WARP]`, `[WEFT]`,
    ///   `[THREADING]` (required), `[TIEUP]` and `[TREADLING]` or else `[LIFTPLAN]` (a lift
    ///   plan beside both is an error: one of them would go unread); other sections
    ///   (`[CONTENTS]`, colours, text, …) are skipped;
    /// - keys are case-insensitive; `;` starts a comment, to the end of the line; two keys of a
    ///   section that name the same number (`1=` and `01=`) are an error;
    /// - `[THREADING] 1=3`: end 1 is on shaft 3 (a list `1=3,4` is allowed); an end with no entry
    ///   is on no shaft and is never lifted;
    /// - `[TIEUP] 1=1,2`: treadle 1 lifts shafts 1 and 2; `[TREADLING] 1=2` (or `1=2,3`): pick 1
    ///   presses treadle 2; `[LIFTPLAN] 1=1,3`: pick 1 lifts shafts 1 and 3 directly;
    /// - `[WEAVING] Shafts=`, `Treadles=` bound the shaft and treadle numbers when present;
    /// - the number of ends is `[WARP] Threads=`, else the largest end in `[THREADING]`; the
    ///   number of picks is `[WEFT] Threads=`, else the largest pick in `[TREADLING]` or
    ///   `[LIFTPLAN]`;
    /// - a lifted shaft raises its ends, so the **warp** is on top there and the weft
    ///   elsewhere; `[WEAVING] Rising Shed=no` (also `false`, `0`, `off`; default `yes`) means
    ///   the draft marks *sinking* shafts instead, which swaps the two.
    ///
    /// # Errors
    /// [`Error::Parse`] naming `origin`, and the section and line number where there is one, for
    /// a missing section, a malformed line, a non-numeric value, a duplicate key or section
    /// (also under two spellings of one number), a lift plan beside tie-up and treadling, an
    /// index of 0, a shaft, treadle, end or pick out of range, or more than [`MAX_THREADS`] ends
    /// or picks. Text before the first section header is not quoted in the message (the file may
    /// be anything).
    ///
    /// # Examples
    /// ```
    /// let wif = "[WIF]\nVersion=1.1\n\
    ///            [THREADING]\n1=1\n2=2\n\
    ///            [TIEUP]\n1=1\n2=2\n\
    ///            [TREADLING]\n1=1\n2=2\n";
    /// let plain = woven::weave::Pattern::from_wif_str(wif, "<string>")?;
    /// assert_eq!(plain.to_string(), ".#\n#.");
    /// # Ok::<(), woven::Error>(())
    /// ```
    pub fn from_wif_str(text: &str, origin: &str) -> Result<Pattern> {
        super::wif::parse(text, origin)
    }

    /// A pattern from a WIF file; see [`Pattern::from_wif_str`] for what is read.
    ///
    /// # Errors
    /// [`Error::Io`] when the file cannot be read (or is not UTF-8); [`Error::Parse`] when it is
    /// longer than [`MAX_WIF_BYTES`]; otherwise the errors of [`Pattern::from_wif_str`], naming
    /// the path.
    pub fn from_wif_path(path: impl AsRef<Path>) -> Result<Pattern> {
        let path = path.as_ref();
        let text = crate::fsutil::read_text_capped(path, MAX_WIF_BYTES, "a WIF file")?;
        Pattern::from_wif_str(&text, &path.display().to_string())
    }

    /// Number of rows: weft picks, along the warp direction `y`.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// Number of columns: warp ends, along the weft direction `x`.
    pub fn cols(&self) -> usize {
        self.cols
    }

    /// Whether the weft floats on top at pick `row`, end `col`; both wrap around (the pattern is
    /// periodic), so `is_weft(row + rows(), col)` is `is_weft(row, col)`.
    pub fn is_weft(&self, row: usize, col: usize) -> bool {
        self.cells[(row % self.rows) * self.cols + col % self.cols]
    }

    /// Whether the weft floats on top at texture coordinate `(u, v)`, measured in pattern
    /// repeats: `u` along the weft direction `x` (columns), `v` along the warp direction `y`
    /// (rows). Any real numbers; the pattern repeats with period 1 in both.
    ///
    /// Cell `(row, col)` covers `u ∈ [col, col + 1) / cols()` and `v ∈ [row, row + 1) / rows()`.
    /// Meant for renderers, so it never fails: `u` and `v` must be finite (checked in debug
    /// builds); a non-finite value maps to some cell.
    ///
    /// # Examples
    /// ```
    /// let plain = woven::weave::Pattern::plain()?;
    /// assert!(!plain.weft_at_uv(0.25, 0.25)); // cell (0, 0): warp
    /// assert!(plain.weft_at_uv(0.75, 0.25)); // cell (0, 1): weft
    /// assert!(plain.weft_at_uv(-0.25, 3.25)); // the same cell, one repeat left and three up
    /// # Ok::<(), woven::Error>(())
    /// ```
    pub fn weft_at_uv(&self, u: f64, v: f64) -> bool {
        debug_assert!(u.is_finite() && v.is_finite(), "weft_at_uv({u}, {v})");
        self.is_weft(cell_index(v, self.rows), cell_index(u, self.cols))
    }

    /// The cell under the point `(x, y)` measured in cells — `x = u n_u` along the weft (columns),
    /// `y = v n_v` along the warp (rows), for a surface with `[n_u, n_v]` cells per unit of its
    /// uv — and the point's place inside it. The one place a point is located in a pattern: the
    /// renderer, the Python package and the Mitsuba plugin all call it
    /// ([`surface`](crate::surface)).
    ///
    /// Any finite reals (the pattern tiles the plane); a non-finite coordinate maps to some
    /// cell, with its place `NaN`.
    ///
    /// # Examples
    /// ```
    /// let twill = woven::weave::Pattern::from_name("twill-2/1")?;
    /// let at = twill.cell_at(4.25, -0.5);
    /// assert_eq!((at.row, at.col), (2, 1)); // y = −0.5 lies in the last row; x = 4.25 in column 1
    /// assert_eq!((at.x, at.y), (0.25, 0.5));
    /// assert_eq!(at.weft, twill.is_weft(2, 1));
    /// # Ok::<(), woven::Error>(())
    /// ```
    #[inline]
    pub fn cell_at(&self, x: f64, y: f64) -> CellPoint {
        let (row, col) = (
            wrap_cell(y.floor(), self.rows),
            wrap_cell(x.floor(), self.cols),
        );
        CellPoint {
            row,
            col,
            x: x - x.floor(),
            y: y - y.floor(),
            weft: self.cells[row * self.cols + col],
        }
    }

    /// Per cell (row-major, `rows() × cols()`), its place in the float of the yarn on top there:
    /// along the row for the weft, along the column for the warp. A yarn that never goes under
    /// (a row all weft, a column all warp) has no ends: [`FloatPlace::len`] 0 there.
    pub fn floats(&self) -> Vec<FloatPlace> {
        let (rows, cols) = (self.rows, self.cols);
        let mut out = vec![FloatPlace::default(); rows * cols];
        for r in 0..rows {
            let line: Vec<bool> = (0..cols).map(|c| self.is_weft(r, c)).collect();
            for (c, run) in runs(&line).into_iter().enumerate() {
                if line[c] {
                    out[r * cols + c] = run;
                }
            }
        }
        for c in 0..cols {
            let line: Vec<bool> = (0..rows).map(|r| !self.is_weft(r, c)).collect();
            for (r, run) in runs(&line).into_iter().enumerate() {
                if line[r] {
                    out[r * cols + c] = run;
                }
            }
        }
        out
    }

    /// The visible weft fraction `γ` of Eq. (23): the mean of the matrix, in `[0, 1]`.
    ///
    /// Implements the weft fraction of Eq. (23) of the paper; docs/spec.md §2.7.
    pub fn weft_fraction(&self) -> f64 {
        let weft = self.cells.iter().filter(|&&w| w).count();
        weft as f64 / self.cells.len() as f64
    }

    /// The matrix as rows of `0` (warp on top) and `1` (weft on top); the inverse of
    /// [`Pattern::from_matrix`].
    pub fn to_matrix(&self) -> Vec<Vec<u8>> {
        self.cells
            .chunks(self.cols)
            .map(|row| row.iter().map(|&w| u8::from(w)).collect())
            .collect()
    }

    /// The same cloth seen from the back: warp and weft swap faces, `γ → 1 − γ`.
    pub fn complement(&self) -> Pattern {
        Pattern {
            rows: self.rows,
            cols: self.cols,
            cells: self.cells.iter().map(|&w| !w).collect(),
        }
    }

    /// The smallest rectangular tile that repeats to this pattern: its top-left `p × q` corner,
    /// where `p` is the smallest row period and `q` the smallest column period.
    ///
    /// A drafted WIF file often holds several repeats (a 4 × 4 plain weave); this gives the
    /// 2 × 2 one. The periods divide `rows()` and `cols()` (a period of a periodic sequence
    /// that does not divide its length would make the gcd a smaller period).
    ///
    /// # Examples
    /// ```
    /// use woven::weave::Pattern;
    /// let drafted = Pattern::from_matrix(vec![vec![0, 1, 0, 1], vec![1, 0, 1, 0]])?;
    /// assert_eq!(drafted.minimal_repeat(), Pattern::plain()?);
    /// # Ok::<(), woven::Error>(())
    /// ```
    pub fn minimal_repeat(&self) -> Pattern {
        let row_period = smallest_period(self.rows, |d| {
            (0..self.rows)
                .all(|r| (0..self.cols).all(|c| self.is_weft(r, c) == self.is_weft(r + d, c)))
        });
        let col_period = smallest_period(self.cols, |d| {
            (0..self.rows)
                .all(|r| (0..self.cols).all(|c| self.is_weft(r, c) == self.is_weft(r, c + d)))
        });
        Pattern::from_fn(row_period, col_period, |r, c| self.is_weft(r, c))
    }

    /// Whether both patterns weave the same cloth up to a translation: as periodic tilings, one
    /// equals the other shifted by some whole number of picks and ends.
    ///
    /// Repeats drafted at different sizes (a 4 × 4 plain weave and the 2 × 2 one) are the same
    /// cloth; a mirror image is not.
    pub fn is_shift_of(&self, other: &Pattern) -> bool {
        let a = self.minimal_repeat();
        let b = other.minimal_repeat();
        if a.rows != b.rows || a.cols != b.cols {
            return false;
        }
        (0..b.rows).any(|dr| {
            (0..b.cols).any(|dc| {
                (0..a.rows)
                    .all(|r| (0..a.cols).all(|c| a.is_weft(r, c) == b.is_weft(r + dr, c + dc)))
            })
        })
    }

    /// The name of this weave if it is, up to a translation, one that [`Pattern::from_name`]
    /// builds: `plain`, `twill-N/M`, `satin-N` or `sateen-N` (`twill-1/1` is `plain`).
    ///
    /// Otherwise `None` (e.g. a basket weave, a mirrored twill, or a satin with another step).
    pub fn name(&self) -> Option<String> {
        let tile = self.minimal_repeat();
        let n = tile.rows;
        if tile.cols != n {
            // Every named weave has a square repeat.
            return None;
        }
        let weft = tile.cells.iter().filter(|&&w| w).count();
        let matches = |name: String| -> Option<String> {
            let named = Pattern::from_name(&name).ok()?;
            tile.is_shift_of(&named).then_some(name)
        };
        // The weft count singles out the candidates: a twill has `under · n` weft cells, a
        // satin `n` and a sateen `n² − n`.
        if n == 2 {
            return matches("plain".to_owned());
        }
        if weft % n == 0 && weft > 0 && weft < n * n {
            let under = weft / n;
            if let Some(name) = matches(format!("twill-{}/{under}", n - under)) {
                return Some(name);
            }
        }
        if weft == n {
            if let Some(name) = matches(format!("satin-{n}")) {
                return Some(name);
            }
        }
        if weft == n * n - n {
            if let Some(name) = matches(format!("sateen-{n}")) {
                return Some(name);
            }
        }
        None
    }
}

impl fmt::Display for Pattern {
    /// Rows of `#` (weft on top) and `.` (warp on top), row 0 first, separated by newlines
    /// (none after the last row).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (r, row) in self.cells.chunks(self.cols).enumerate() {
            if r > 0 {
                f.write_str("\n")?;
            }
            for &w in row {
                f.write_str(if w { "#" } else { "." })?;
            }
        }
        Ok(())
    }
}

impl FromStr for Pattern {
    type Err = Error;

    /// [`Pattern::from_name`].
    fn from_str(name: &str) -> Result<Pattern> {
        Pattern::from_name(name)
    }
}

/// The satin step for `n` harnesses: the smallest `s` with `1 < s < n − 1` and `gcd(s, n) = 1`.
///
/// `name` is the parameter reported on failure (`n < 5`, `n = 6`, `n > MAX_THREADS`).
fn satin_step(name: &str, n: usize) -> Result<usize> {
    let expected = format!(
        "a harness count n ≥ 5, n ≠ 6 and n ≤ {MAX_THREADS} \
         (no regular satin exists for n < 5 or n = 6)"
    );
    if n > MAX_THREADS {
        return Err(Error::invalid(name, n, expected));
    }
    (2..n.saturating_sub(1))
        .find(|&s| gcd(s, n) == 1)
        .ok_or_else(|| Error::invalid(name, n, expected))
}

/// Greatest common divisor (Euclid).
fn gcd(mut a: usize, mut b: usize) -> usize {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// The smallest divisor `d` of `len` for which `is_period(d)` holds (`len` itself always does).
fn smallest_period(len: usize, is_period: impl Fn(usize) -> bool) -> usize {
    (1..len)
        .filter(|d| len % d == 0)
        .find(|&d| is_period(d))
        .unwrap_or(len)
}

/// The cell `floor(t · n) mod n` holding texture coordinate `t` (in repeats) of an axis with `n`
/// cells.
/// A point located in a pattern by [`Pattern::cell_at`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CellPoint {
    /// The cell's row (pick), `0..rows()`.
    pub row: usize,
    /// The cell's column (end), `0..cols()`.
    pub col: usize,
    /// The point's place across the cell along `x` (the weft's axis), in `[0, 1)`.
    pub x: f64,
    /// The point's place across the cell along `y` (the warp's axis), in `[0, 1)`.
    pub y: f64,
    /// Whether the weft floats on top in the cell.
    pub weft: bool,
}

/// A cell's place in the float of the yarn on top of it ([`Pattern::floats`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FloatPlace {
    /// Cells of the same float before this one (along the yarn's axis).
    pub before: u16,
    /// The float's length in cells; 0 where the yarn never goes under (a float without ends).
    pub len: u16,
}

/// The runs of equal values along a periodic line: per element its place in its run; all
/// `len = 0` when the whole line is one value (a run without ends).
fn runs(values: &[bool]) -> Vec<FloatPlace> {
    let n = values.len();
    let mut out = vec![FloatPlace::default(); n];
    // A run's first element: its predecessor differs.
    let Some(s) = (0..n).find(|&i| values[i] != values[(i + n - 1) % n]) else {
        return out;
    };
    let mut j = 0;
    while j < n {
        let first = values[(s + j) % n];
        let mut len = 1;
        while j + len < n && values[(s + j + len) % n] == first {
            len += 1;
        }
        for k in 0..len {
            // At most MAX_THREADS (4096) cells a line: both fit in u16.
            out[(s + j + k) % n] = FloatPlace {
                before: k as u16,
                len: len as u16,
            };
        }
        j += len;
    }
    out
}

fn cell_index(t: f64, n: usize) -> usize {
    wrap_cell((t * n as f64).floor(), n)
}

/// The cell `k mod n` (in `0..n`) of an integer-valued `k`. Below 2⁵³ in magnitude (every `k` a
/// cell look-up meets) in integers, where the remainder is exact and the same: `f64::rem_euclid`
/// is a software `fmod`, 4 % of a render's time when every shading point asked it. Beyond, and
/// for NaN (cell 0), the float remainder, its rounding to `n` guarded.
#[inline]
fn wrap_cell(k: f64, n: usize) -> usize {
    if k.abs() < 9_007_199_254_740_992.0 {
        (k as i64).rem_euclid(n as i64) as usize
    } else {
        (k.rem_euclid(n as f64) as usize).min(n - 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The integer wrap is the float one it replaced, `k.rem_euclid(n)` (its rounding to `n`
    /// guarded), for integer-valued `k` on both sides of 2⁵³ and for the non-finite.
    #[test]
    fn cell_wrap_is_rem_euclid() {
        for n in [1usize, 2, 3, 5, 8, 12] {
            let ks = (-300i64..=300).map(|k| k as f64).chain([
                -9_007_199_254_740_991.0,
                9_007_199_254_740_991.0,
                -1e15,
                4.5e15,
            ]);
            let beyond = [
                9_007_199_254_740_992.0,
                -1.5e16,
                1e300,
                -1e300,
                f64::INFINITY,
            ];
            let odd = [f64::NEG_INFINITY, f64::NAN];
            for k in ks.chain(beyond).chain(odd) {
                let float = (k.rem_euclid(n as f64) as usize).min(n - 1);
                assert_eq!(wrap_cell(k, n), float, "k {k} n {n}");
            }
        }
    }

    #[test]
    fn satin_steps_are_the_usual_ones() {
        let steps: Vec<(usize, usize)> = [5, 7, 8, 9, 10, 11, 12, 14, 16]
            .iter()
            .map(|&n| (n, satin_step("n", n).unwrap()))
            .collect();
        assert_eq!(
            steps,
            [
                (5, 2),
                (7, 2),
                (8, 3),
                (9, 2),
                (10, 3),
                (11, 2),
                (12, 5),
                (14, 3),
                (16, 3)
            ]
        );
        for n in [0, 1, 2, 3, 4, 6, MAX_THREADS + 1] {
            assert!(satin_step("n", n).is_err(), "n = {n}");
        }
    }

    #[test]
    fn gcd_and_periods() {
        assert_eq!(gcd(12, 8), 4);
        assert_eq!(gcd(5, 0), 5);
        assert_eq!(gcd(7, 3), 1);
        assert_eq!(smallest_period(12, |d| d % 3 == 0), 3);
        assert_eq!(smallest_period(7, |_| false), 7);
        assert_eq!(smallest_period(1, |_| false), 1);
    }

    #[test]
    fn cell_index_wraps_and_stays_in_range() {
        assert_eq!(cell_index(0.0, 4), 0);
        assert_eq!(cell_index(0.999, 4), 3);
        assert_eq!(cell_index(1.0, 4), 0);
        assert_eq!(cell_index(-1e-300, 4), 3);
        assert_eq!(cell_index(-0.3, 4), 2);
        assert_eq!(cell_index(1e300, 4), 0);
        assert!(cell_index(-1e300, 3) < 3);
        assert!(cell_index(f64::MAX, 7) < 7);
    }

    #[test]
    fn floats_of_a_twill_and_a_satin() {
        // twill-2/1: each weft floats over one warp end, each warp end over two picks.
        let twill = Pattern::from_name("twill-2/1").unwrap();
        let floats = twill.floats();
        for r in 0..3 {
            for c in 0..3 {
                let f = floats[r * 3 + c];
                let expected_len = if twill.is_weft(r, c) { 1 } else { 2 };
                assert_eq!(f.len, expected_len, "cell ({r}, {c})");
                assert!(f.before < f.len);
            }
        }
        // Along each warp float the places count 0, 1 in order of the rows.
        for c in 0..3 {
            let first = (0..3)
                .find(|&r| !twill.is_weft(r, c) && twill.is_weft((r + 2) % 3, c))
                .unwrap();
            assert_eq!(floats[first * 3 + c].before, 0);
            assert_eq!(floats[((first + 1) % 3) * 3 + c].before, 1);
        }
        // A line that is all one value has no ends.
        let all_weft = Pattern::from_matrix(vec![vec![1, 1]]).unwrap();
        assert!(all_weft.floats().iter().all(|f| f.len == 0));
        let satin = Pattern::from_name("satin-5").unwrap();
        let warp_cells = satin.floats().iter().filter(|f| f.len == 4).count();
        assert_eq!(
            warp_cells, 20,
            "each warp end floats over four of five picks"
        );
    }

    #[test]
    fn cell_at_agrees_with_weft_at_uv() {
        let twill = Pattern::from_name("twill-3/1").unwrap();
        let (rows, cols) = (twill.rows() as f64, twill.cols() as f64);
        for i in 0..997 {
            let x = -13.0 + 0.0371 * i as f64;
            let y = 7.3 - 0.0293 * i as f64;
            let at = twill.cell_at(x, y);
            assert_eq!(at.weft, twill.weft_at_uv(x / cols, y / rows), "({x}, {y})");
            assert!((0.0..1.0).contains(&at.x) && (0.0..1.0).contains(&at.y));
            assert!(at.row < twill.rows() && at.col < twill.cols());
        }
    }

    #[test]
    fn twill_layout() {
        let t = Pattern::twill(2, 1).unwrap();
        assert_eq!(
            t.to_matrix(),
            vec![vec![0, 0, 1], vec![1, 0, 0], vec![0, 1, 0]]
        );
        assert!(Pattern::twill(usize::MAX, 1).is_err());
    }
}
