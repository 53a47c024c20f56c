//! The microcylinder fabric file (TOML): parse → check → build, as material files are read
//! (docs/microcylinder.md §8). Angles in the file are degrees, as in the paper's Table II.
//!
//! ```toml
//! model = "microcylinder"
//! name = "my linen"
//!
//! [[thread]]            # thread 1, along x (the weft)
//! eta = 1.46
//! albedo = [0.06, 0.24, 0.3]
//! kd = 0.3
//! gamma_s_deg = 12.0
//! gamma_v_deg = 24.0
//! coverage = 0.33
//! tangent_offsets_deg = [-25.0, 25.0]
//! tangent_lengths = [1.0]
//!
//! [[thread]]            # thread 2, along y
//! # … the same keys
//! ```

use super::curve::TangentCurve;
use super::thread::Thread;
use super::Microcylinder;
use crate::color::Rgb;
use crate::error::{Error, Result};
use crate::material::MAX_FILE_BYTES;
use serde::Deserialize;
use std::path::Path;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFabric {
    model: String,
    name: Option<String>,
    thread: Vec<RawThread>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawThread {
    eta: f64,
    albedo: [f64; 3],
    kd: f64,
    gamma_s_deg: f64,
    gamma_v_deg: f64,
    coverage: f64,
    tangent_offsets_deg: Vec<f64>,
    #[serde(default)]
    tangent_lengths: Vec<f64>,
}

impl RawThread {
    /// Checks the curve (naming the thread) and converts to radians.
    fn into_thread(self, index: usize) -> Result<Thread> {
        let offsets: Vec<f64> = self
            .tangent_offsets_deg
            .iter()
            .map(|d| d.to_radians())
            .collect();
        let tangents = TangentCurve::new(&offsets, &self.tangent_lengths).map_err(|e| match e {
            Error::InvalidParameter {
                name,
                value,
                expected,
            } => Error::InvalidParameter {
                name: format!("thread[{index}].{}", name.replace("offsets", "offsets_deg")),
                value,
                expected,
            },
            other => other,
        })?;
        Ok(Thread {
            eta: self.eta,
            albedo: Rgb(self.albedo),
            kd: self.kd,
            gamma_s: self.gamma_s_deg.to_radians(),
            gamma_v: self.gamma_v_deg.to_radians(),
            coverage: self.coverage,
            tangents,
        })
    }
}

impl Microcylinder {
    /// A fabric from the text of a microcylinder file (`origin` names it in errors).
    ///
    /// # Errors
    /// [`Error::Parse`] for text that is not such a file; [`Error::InvalidParameter`] naming the
    /// parameter (`thread[1].kd`, `thread`, `model`) otherwise.
    ///
    /// ```
    /// use woven::microcylinder::Microcylinder;
    /// let thread = "[[thread]]\neta = 1.46\nalbedo = [0.06, 0.24, 0.3]\nkd = 0.3\n\
    ///     gamma_s_deg = 12.0\ngamma_v_deg = 24.0\ncoverage = 0.33\n\
    ///     tangent_offsets_deg = [-25.0, 25.0]\ntangent_lengths = [1.0]\n";
    /// let text = format!("model = \"microcylinder\"\nname = \"linen\"\n{thread}{thread}");
    /// let cloth = Microcylinder::from_toml_str(&text, "<doc>")?;
    /// assert_eq!(cloth.name, "linen");
    /// let bad = text.replacen("kd = 0.3", "kd = 3.0", 1);
    /// let e = Microcylinder::from_toml_str(&bad, "<doc>").unwrap_err();
    /// assert!(e.to_string().contains("thread[0].kd"));
    /// # Ok::<(), woven::Error>(())
    /// ```
    pub fn from_toml_str(text: &str, origin: &str) -> Result<Microcylinder> {
        let (name, threads) = Self::threads_from_toml_str(text, origin)?;
        Microcylinder::new(name, threads)
    }

    /// The name (the file's `name`, else `origin`) and the two threads of a microcylinder
    /// file's text, checked as [`from_toml_str`](Self::from_toml_str) checks them but not built:
    /// no energy guard is measured (seconds), for a caller that only needs the numbers (a fit's
    /// starting point).
    ///
    /// # Errors
    /// As [`from_toml_str`](Self::from_toml_str), except the coverages' sum, which is checked
    /// when the threads are built ([`Microcylinder::new`]).
    pub fn threads_from_toml_str(text: &str, origin: &str) -> Result<(String, [Thread; 2])> {
        let raw: RawFabric = toml::from_str(text).map_err(|e| Error::Parse {
            path: origin.to_string(),
            message: e.to_string().trim_end().to_string(),
        })?;
        if raw.model != "microcylinder" {
            return Err(Error::invalid(
                "model",
                format!("{:?}", raw.model),
                "\"microcylinder\"",
            ));
        }
        if raw.thread.len() != 2 {
            return Err(Error::invalid(
                "thread",
                format!("{} [[thread]] tables", raw.thread.len()),
                "exactly 2 [[thread]] tables (along x, then along y)",
            ));
        }
        let mut it = raw.thread.into_iter();
        let (t0, t1) = (it.next(), it.next());
        let threads = [
            t0.map(|t| t.into_thread(0)).transpose()?,
            t1.map(|t| t.into_thread(1)).transpose()?,
        ];
        let [Some(a), Some(b)] = threads else {
            unreachable!("two threads were counted above")
        };
        a.validate(0)?;
        b.validate(1)?;
        Ok((raw.name.unwrap_or_else(|| origin.to_string()), [a, b]))
    }

    /// As [`threads_from_toml_str`](Self::threads_from_toml_str) for a file (at most
    /// [`MAX_FILE_BYTES`]).
    ///
    /// # Errors
    /// [`Error::Io`] if it cannot be read; otherwise as
    /// [`threads_from_toml_str`](Self::threads_from_toml_str).
    pub fn threads_from_path(path: impl AsRef<Path>) -> Result<(String, [Thread; 2])> {
        let path = path.as_ref();
        let text = crate::fsutil::read_text_capped(path, MAX_FILE_BYTES, "a microcylinder file")?;
        Self::threads_from_toml_str(&text, &path.display().to_string())
    }

    /// The fabric as a microcylinder file that [`from_toml_str`](Self::from_toml_str) reads
    /// back as the same fabric ([`fabric_toml`]).
    pub fn to_toml_string(&self) -> String {
        fabric_toml(&self.name, &self.threads)
    }

    /// Reads a microcylinder file (at most [`MAX_FILE_BYTES`]).
    ///
    /// # Errors
    /// [`Error::Io`] if it cannot be read; otherwise as [`from_toml_str`](Self::from_toml_str).
    pub fn from_path(path: impl AsRef<Path>) -> Result<Microcylinder> {
        let path = path.as_ref();
        let text = crate::fsutil::read_text_capped(path, MAX_FILE_BYTES, "a microcylinder file")?;
        Self::from_toml_str(&text, &path.display().to_string())
    }
}

/// A fabric of `name` and two threads as the text of a microcylinder file (angles in degrees, as
/// the file has them; every number to its last digit, so that it reads back as the same threads,
/// up to the rounding of the conversion from radians).
///
/// ```
/// use woven::microcylinder::{fabric_toml, Microcylinder};
/// let threads = Microcylinder::preset_threads("microcylinder-silk-shot")?;
/// let text = fabric_toml("shot", &threads);
/// let (name, back) = Microcylinder::threads_from_toml_str(&text, "<doc>")?;
/// assert_eq!(name, "shot");
/// assert!((back[0].gamma_s - threads[0].gamma_s).abs() < 1e-15);
/// assert_eq!(back[1].tangents.offsets(), threads[1].tangents.offsets());
/// # Ok::<(), woven::Error>(())
/// ```
pub fn fabric_toml(name: &str, threads: &[Thread; 2]) -> String {
    use std::fmt::Write as _;
    let list = |v: &[f64]| {
        let items: Vec<String> = v.iter().map(|x| format!("{x:?}")).collect();
        format!("[{}]", items.join(", "))
    };
    let mut s = format!(
        "model = \"microcylinder\"\nname = {}\n",
        toml::Value::String(name.to_string())
    );
    for (k, t) in threads.iter().enumerate() {
        let along = if k == 0 {
            "x (the weft)"
        } else {
            "y (the warp)"
        };
        let offsets: Vec<f64> = t.tangents.offsets().iter().map(|&a| degrees(a)).collect();
        let _ = write!(
            s,
            "\n[[thread]]            # thread {}, along {along}\n\
             eta = {:?}\nalbedo = {}\nkd = {:?}\ngamma_s_deg = {:?}\ngamma_v_deg = {:?}\n\
             coverage = {:?}\ntangent_offsets_deg = {}\ntangent_lengths = {}\n",
            k + 1,
            t.eta,
            list(&t.albedo.0),
            t.kd,
            degrees(t.gamma_s),
            degrees(t.gamma_v),
            t.coverage,
            list(&offsets),
            list(t.tangents.lengths()),
        );
    }
    s
}

/// Radians in degrees, the conversion's rounding noise removed (`25.000000000000004` → `25.0`)
/// where the value is a whole number of 10⁻⁹ degrees to within 10⁻¹⁴ of itself (a few units in
/// the last place).
fn degrees(radians: f64) -> f64 {
    let d = radians.to_degrees();
    let r = (d * 1e9).round() / 1e9;
    if (r - d).abs() <= 1e-14 * d.abs().max(1.0) {
        r
    } else {
        d
    }
}
