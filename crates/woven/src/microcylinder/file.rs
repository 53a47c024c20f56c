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
        Microcylinder::new(raw.name.unwrap_or_else(|| origin.to_string()), [a, b])
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
