//! RGL's measured `.bsdf` files (Dupuy & Jakob 2018): Mitsuba's little-endian "tensor file".
//!
//! Layout: the 12 bytes `tensor_file\0`, a version (two `u8`, 1.0), a `u32` field count, then per
//! field its name (`u16` length + bytes), its rank (`u16`), its type (`u8`: 1 u8, 2 i8, 3 u16,
//! 4 i16, 5 u32, 6 i32, 7 u64, 8 i64, 9 f16, 10 f32, 11 f64), the byte offset of its data (`u64`)
//! and its shape (`u64` per dimension). [`TensorFile::parse`] reads and checks all of it: every
//! field's data lies inside the file.
//!
//! **Evaluation** ([`RglBsdf::eval`]) follows the paper's parameterisation as RGL's reference
//! loader implements it: with the half vector `m`, the light's `u_wi = (√(2θi/π), (φi + π)/2π)`
//! and `u_m = (√(2θm/π), frac((φm − φi + π)/2π))` (isotropic files), the point `u_m` is mapped
//! back through the warp of the visible-normal distribution (`vndf`, a marginal-conditional
//! bilinear warp, multilinear over the tabulated incidences) to the unit square where `rgb` is
//! tabulated, and `f · cos θo = rgb · ndf(u_m) / (4 σ(u_wi))`. [`read`] evaluates a file on the
//! grid of the `*.grid.csv` files (θi, θo ∈ {0, 5, …, 80}°, φo − φi ∈ {0, 15, …, 180}°), dividing
//! by `cos θo` and clipping negative channels (out-of-gamut spectra) at 0 as RGL's loader does,
//! so a `.bsdf` loads as the same dataset as its grid.

use super::rows::format_error;
use super::{DataError, Dataset};
use std::path::Path;
use woven::Vec3;

/// The first bytes of a tensor file.
pub const MAGIC: &[u8] = b"tensor_file\0";

/// One field of a tensor file: its name, element type, shape and where its data lies.
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    /// The field's name (`theta_i`, `rgb`, `vndf`, …).
    pub name: String,
    /// The element type code (1 u8 … 11 f64, see the module docs).
    pub dtype: u8,
    /// The size of one element, bytes.
    pub element_bytes: usize,
    /// The shape, outermost dimension first.
    pub shape: Vec<u64>,
    /// The byte offset of the data in the file.
    pub offset: u64,
}

impl Field {
    /// The number of elements (the product of the shape).
    pub fn len(&self) -> u64 {
        self.shape.iter().product()
    }

    /// Whether the field has no elements.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// The directory of a tensor file: its fields, in file order.
#[derive(Clone, Debug, PartialEq)]
pub struct TensorFile {
    /// The fields.
    pub fields: Vec<Field>,
}

/// A little-endian cursor that fails instead of reading past the end.
struct Cursor<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl Cursor<'_> {
    fn take(&mut self, n: usize) -> Option<&[u8]> {
        let end = self.at.checked_add(n)?;
        let out = self.bytes.get(self.at..end)?;
        self.at = end;
        Some(out)
    }
    fn u8(&mut self) -> Option<u8> {
        self.take(1).map(|b| b[0])
    }
    fn u16(&mut self) -> Option<u16> {
        self.take(2).map(|b| u16::from_le_bytes([b[0], b[1]]))
    }
    fn u32(&mut self) -> Option<u32> {
        self.take(4)
            .and_then(|b| b.try_into().ok())
            .map(u32::from_le_bytes)
    }
    fn u64(&mut self) -> Option<u64> {
        self.take(8)
            .and_then(|b| b.try_into().ok())
            .map(u64::from_le_bytes)
    }
}

/// The size of one element of type `dtype`, bytes.
fn element_bytes(dtype: u8) -> Option<usize> {
    Some(match dtype {
        1 | 2 => 1,
        3 | 4 | 9 => 2,
        5 | 6 | 10 => 4,
        7 | 8 | 11 => 8,
        _ => return None,
    })
}

impl TensorFile {
    /// Reads the directory of the tensor file in `bytes` (the contents of `path`).
    ///
    /// # Errors
    /// [`DataError::Format`] for a wrong magic or version, a truncated directory, an unknown
    /// element type, or a field whose data runs past the end of the file.
    pub fn parse(path: &Path, bytes: &[u8]) -> Result<TensorFile, DataError> {
        let bad = |what: String| format_error(path, format!("not a valid RGL tensor file: {what}"));
        if !bytes.starts_with(MAGIC) {
            return Err(bad("it does not start with `tensor_file`".into()));
        }
        let mut c = Cursor {
            bytes,
            at: MAGIC.len(),
        };
        let truncated = || bad("the field directory is truncated".into());
        let (major, minor) = (c.u8().ok_or_else(truncated)?, c.u8().ok_or_else(truncated)?);
        if (major, minor) != (1, 0) {
            return Err(bad(format!("version {major}.{minor}, expected 1.0")));
        }
        let n = c.u32().ok_or_else(truncated)?;
        let mut fields = Vec::new();
        for _ in 0..n {
            let len = c.u16().ok_or_else(truncated)? as usize;
            let name = String::from_utf8_lossy(c.take(len).ok_or_else(truncated)?).into_owned();
            let ndim = c.u16().ok_or_else(truncated)?;
            let dtype = c.u8().ok_or_else(truncated)?;
            let offset = c.u64().ok_or_else(truncated)?;
            let mut shape = Vec::new();
            for _ in 0..ndim {
                shape.push(c.u64().ok_or_else(truncated)?);
            }
            let element = element_bytes(dtype)
                .ok_or_else(|| bad(format!("field `{name}` has unknown element type {dtype}")))?;
            let size = shape
                .iter()
                .try_fold(element as u64, |acc, &d| acc.checked_mul(d));
            let fits = size
                .and_then(|s| offset.checked_add(s))
                .is_some_and(|end| end <= bytes.len() as u64);
            if !fits {
                return Err(bad(format!(
                    "the data of field `{name}` (shape {shape:?}, offset {offset}) runs past the \
                     end of the file ({} bytes)",
                    bytes.len()
                )));
            }
            fields.push(Field {
                name,
                dtype,
                element_bytes: element,
                shape,
                offset,
            });
        }
        Ok(TensorFile { fields })
    }

    /// The field called `name`.
    pub fn field(&self, name: &str) -> Option<&Field> {
        self.fields.iter().find(|f| f.name == name)
    }

    /// The elements of an `f32` field, as `f64`.
    pub fn f32s(&self, bytes: &[u8], name: &str) -> Option<Vec<f64>> {
        let f = self.field(name)?;
        if f.dtype != 10 {
            return None;
        }
        let start = usize::try_from(f.offset).ok()?;
        let n = usize::try_from(f.len()).ok()?;
        let data = bytes.get(start..start.checked_add(n.checked_mul(4)?)?)?;
        Some(
            data.chunks_exact(4)
                .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64)
                .collect(),
        )
    }

    /// The `description` field as text, when the file has one.
    pub fn description(&self, bytes: &[u8]) -> Option<String> {
        let f = self.field("description")?;
        let start = usize::try_from(f.offset).ok()?;
        let data = bytes.get(start..start.checked_add(usize::try_from(f.len()).ok()?)?)?;
        Some(
            String::from_utf8_lossy(data)
                .trim_end_matches('\0')
                .to_string(),
        )
    }
}

/// A tabulated function on the unit square (`nx × ny` nodes, bilinear), one slice per combination
/// of parameter values (multilinear between them): RGL's `Marginal2D`. With `cdf`, the slices are
/// normalised to integrate to 1 and carry the conditional and marginal CDFs that
/// [`Table2D::invert`] needs.
struct Table2D {
    nx: usize,
    ny: usize,
    /// The parameters' node values, outermost first.
    params: Vec<Vec<f64>>,
    /// Each parameter's stride in slices (0 for a single value).
    strides: Vec<usize>,
    data: Vec<f64>,
    /// Per slice, per row: the CDF along x (`nx` values).
    conditional: Vec<f64>,
    /// Per slice: the CDF along y (`ny` values).
    marginal: Vec<f64>,
}

/// The interval `[i, i + 1]` of sorted `values` that holds `x`, clamped to the ends (RGL's
/// `find_interval`): the last `i ≤ n − 2` with `values[i] ≤ x`, or 0.
fn find_interval(values: &[f64], x: f64) -> usize {
    let n = values.len();
    if n < 2 {
        return 0;
    }
    let mut i = 0;
    while i + 2 < n && values[i + 1] <= x {
        i += 1;
    }
    i
}

impl Table2D {
    /// A table of `data` (slices × `ny` × `nx`), parameters `params` (outermost first).
    fn new(nx: usize, ny: usize, data: Vec<f64>, params: Vec<Vec<f64>>, cdf: bool) -> Table2D {
        let mut strides = vec![0; params.len()];
        let mut slices = 1;
        for d in (0..params.len()).rev() {
            strides[d] = if params[d].len() > 1 { slices } else { 0 };
            slices *= params[d].len();
        }
        let mut t = Table2D {
            nx,
            ny,
            params,
            strides,
            data,
            conditional: Vec::new(),
            marginal: Vec::new(),
        };
        if cdf {
            let n = nx * ny;
            t.conditional = vec![0.0; slices * n];
            t.marginal = vec![0.0; slices * ny];
            for s in 0..slices {
                let data = &mut t.data[s * n..(s + 1) * n];
                let cond = &mut t.conditional[s * n..(s + 1) * n];
                let marg = &mut t.marginal[s * ny..(s + 1) * ny];
                for y in 0..ny {
                    for x in 0..nx - 1 {
                        let i = y * nx + x;
                        cond[i + 1] = cond[i] + 0.5 * (data[i] + data[i + 1]);
                    }
                }
                for y in 0..ny - 1 {
                    marg[y + 1] = marg[y] + 0.5 * (cond[(y + 1) * nx - 1] + cond[(y + 2) * nx - 1]);
                }
                // An all-zero slice stays zero rather than becoming NaN.
                let total = marg[ny - 1];
                let norm = if total > 0.0 { 1.0 / total } else { 0.0 };
                for v in cond
                    .iter_mut()
                    .chain(marg.iter_mut())
                    .chain(data.iter_mut())
                {
                    *v *= norm;
                }
            }
        }
        t
    }

    /// The first slice and the interpolation weights `(w0, w1)` per parameter at `param`.
    fn weights(&self, param: &[f64]) -> (usize, Vec<(f64, f64)>) {
        let mut slice = 0;
        let mut w = Vec::with_capacity(self.params.len());
        for (d, values) in self.params.iter().enumerate() {
            if values.len() < 2 {
                w.push((1.0, 0.0));
                continue;
            }
            let i = find_interval(values, param[d]);
            let (p0, p1) = (values[i], values[i + 1]);
            // Repeated node values: take the lower node.
            let t = if p1 > p0 {
                ((param[d] - p0) / (p1 - p0)).clamp(0.0, 1.0)
            } else {
                0.0
            };
            w.push((1.0 - t, t));
            slice += self.strides[d] * i;
        }
        (slice, w)
    }

    /// `array[index]` interpolated over the parameters (`size` = the length of one slice).
    fn lookup(&self, array: &[f64], index: usize, size: usize, w: &[(f64, f64)]) -> f64 {
        let dims = w.len();
        let mut sum = 0.0;
        for corner in 0..1usize << dims {
            let mut weight = 1.0;
            let mut i = index;
            for (d, &(w0, w1)) in w.iter().enumerate() {
                if corner >> d & 1 == 1 {
                    weight *= w1;
                    i += self.strides[d] * size;
                } else {
                    weight *= w0;
                }
            }
            if weight != 0.0 {
                sum += weight * array.get(i).copied().unwrap_or(0.0);
            }
        }
        sum
    }

    /// The bilinear cell of `pos` (in the unit square): its lower corner and the offsets in it.
    fn cell(&self, pos: [f64; 2]) -> ([usize; 2], [f64; 2]) {
        let scaled = [pos[0] * (self.nx - 1) as f64, pos[1] * (self.ny - 1) as f64];
        let ix = (scaled[0].max(0.0) as usize).min(self.nx - 2);
        let iy = (scaled[1].max(0.0) as usize).min(self.ny - 2);
        ([ix, iy], [scaled[0] - ix as f64, scaled[1] - iy as f64])
    }

    /// The tabulated function at `pos`, bilinear (as stored: unnormalised tables are the raw
    /// data).
    fn eval(&self, pos: [f64; 2], param: &[f64]) -> f64 {
        let (slice, w) = self.weights(param);
        let ([ix, iy], [fx, fy]) = self.cell(pos);
        let size = self.nx * self.ny;
        let i = ix + iy * self.nx + slice * size;
        let v = |k: usize| self.lookup(&self.data, i + k, size, &w);
        let (v00, v10, v01, v11) = (v(0), v(1), v(self.nx), v(self.nx + 1));
        (1.0 - fy) * ((1.0 - fx) * v00 + fx * v10) + fy * ((1.0 - fx) * v01 + fx * v11)
    }

    /// The inverse of the warp the table's distribution defines: the point of the unit square
    /// that the sample `u` came from.
    fn invert(&self, u: [f64; 2], param: &[f64]) -> [f64; 2] {
        let (slice, w) = self.weights(param);
        let ([ix, iy], [mut sx, mut sy]) = self.cell(u);
        let size = self.nx * self.ny;
        let offset = ix + iy * self.nx + slice * size;
        let v = |a: &[f64], k: usize| self.lookup(a, offset + k, size, &w);
        let (v00, v10, v01, v11) = (
            v(&self.data, 0),
            v(&self.data, 1),
            v(&self.data, self.nx),
            v(&self.data, self.nx + 1),
        );
        // Along x: the integral of the bilinear density up to sx, plus the row's CDF.
        let c0 = (1.0 - sy) * v00 + sy * v01;
        let c1 = (1.0 - sy) * v10 + sy * v11;
        sx *= c0 + 0.5 * sx * (c1 - c0);
        let (k0, k1) = (v(&self.conditional, 0), v(&self.conditional, self.nx));
        sx += (1.0 - sy) * k0 + sy * k1;
        let row = iy * self.nx + slice * size;
        let r = |k: usize| self.lookup(&self.conditional, row + k, size, &w);
        let (r0, r1) = (r(self.nx - 1), r(2 * self.nx - 1));
        let norm = (1.0 - sy) * r0 + sy * r1;
        sx = if norm > 0.0 { sx / norm } else { 0.0 };
        // Along y: the same with the marginal CDF.
        sy *= r0 + 0.5 * sy * (r1 - r0);
        sy += self.lookup(&self.marginal, iy + slice * self.ny, self.ny, &w);
        [sx, sy]
    }
}

/// An RGL measured BRDF, ready to evaluate.
pub struct RglBsdf {
    /// The file's description.
    pub description: String,
    ndf: Table2D,
    sigma: Table2D,
    vndf: Table2D,
    rgb: Table2D,
}

impl std::fmt::Debug for RglBsdf {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RglBsdf")
            .field("description", &self.description)
            .finish_non_exhaustive()
    }
}

impl RglBsdf {
    /// Reads an RGL `.bsdf` (RGB) file's tables from `bytes` (the contents of `path`).
    ///
    /// # Errors
    /// [`DataError::Format`] for a malformed tensor file, a missing field, a field of the wrong
    /// type or shape, an anisotropic or spectral file (not supported).
    pub fn parse(path: &Path, bytes: &[u8]) -> Result<RglBsdf, DataError> {
        let file = TensorFile::parse(path, bytes)?;
        let bad = |what: String| format_error(path, format!("not an RGL RGB BSDF: {what}"));
        let field = |name: &str, ndim: usize| -> Result<(Vec<u64>, Vec<f64>), DataError> {
            let f = file
                .field(name)
                .ok_or_else(|| bad(format!("no field `{name}`")))?;
            if f.shape.len() != ndim {
                return Err(bad(format!(
                    "field `{name}` has {} dimensions, expected {ndim}",
                    f.shape.len()
                )));
            }
            let data = file
                .f32s(bytes, name)
                .ok_or_else(|| bad(format!("field `{name}` is not f32")))?;
            if data.iter().any(|v| !v.is_finite()) {
                return Err(bad(format!("field `{name}` holds a non-finite value")));
            }
            Ok((f.shape.clone(), data))
        };
        if file.field("spectra").is_some() && file.field("rgb").is_none() {
            return Err(bad(
                "a spectral file (`spectra`): only RGB files are supported".into(),
            ));
        }
        let (_, theta_i) = field("theta_i", 1)?;
        let (_, phi_i) = field("phi_i", 1)?;
        if phi_i.len() > 2 {
            return Err(bad("an anisotropic file (several φi): not supported".into()));
        }
        let (ndf_shape, ndf) = field("ndf", 2)?;
        let (sigma_shape, sigma) = field("sigma", 2)?;
        let (vndf_shape, vndf) = field("vndf", 4)?;
        let (rgb_shape, rgb) = field("rgb", 5)?;
        let (np, nt) = (phi_i.len() as u64, theta_i.len() as u64);
        let at_least_2 = |s: &[u64]| s.iter().rev().take(2).all(|&n| n >= 2);
        let ok = nt >= 1
            && np >= 1
            && at_least_2(&ndf_shape)
            && at_least_2(&sigma_shape)
            && at_least_2(&vndf_shape)
            && at_least_2(&rgb_shape)
            && vndf_shape[..2] == [np, nt]
            && rgb_shape[..3] == [np, nt, 3];
        if !ok {
            return Err(bad(format!(
                "inconsistent shapes: theta_i {nt}, phi_i {np}, ndf {ndf_shape:?}, sigma \
                 {sigma_shape:?}, vndf {vndf_shape:?}, rgb {rgb_shape:?}"
            )));
        }
        let dims = |s: &[u64]| (s[s.len() - 1] as usize, s[s.len() - 2] as usize);
        let (nx, ny) = dims(&ndf_shape);
        let ndf = Table2D::new(nx, ny, ndf, vec![], false);
        let (nx, ny) = dims(&sigma_shape);
        let sigma = Table2D::new(nx, ny, sigma, vec![], false);
        let (nx, ny) = dims(&vndf_shape);
        let vndf = Table2D::new(nx, ny, vndf, vec![phi_i.clone(), theta_i.clone()], true);
        let (nx, ny) = dims(&rgb_shape);
        let rgb = Table2D::new(
            nx,
            ny,
            rgb,
            vec![phi_i, theta_i, vec![0.0, 1.0, 2.0]],
            false,
        );
        Ok(RglBsdf {
            description: file.description(bytes).unwrap_or_default(),
            ndf,
            sigma,
            vndf,
            rgb,
        })
    }

    /// `f(wi, wo) · cos θo` per channel (what RGL's loader returns), unit vectors in the local
    /// frame; zero when either direction is at or below the horizon. Channels may be negative
    /// (out-of-gamut spectra).
    pub fn eval_cos(&self, wi: Vec3, wo: Vec3) -> [f64; 3] {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return [0.0; 3];
        }
        let sum = wi + wo;
        let m = sum * (1.0 / sum.length());
        let theta_i = wi.z.clamp(-1.0, 1.0).acos();
        let phi_i = wi.y.atan2(wi.x);
        let theta_m = m.z.clamp(-1.0, 1.0).acos();
        let phi_m = m.y.atan2(m.x);
        let to_u = |theta: f64| (theta * 2.0 / std::f64::consts::PI).sqrt();
        let to_v = |phi: f64| (phi + std::f64::consts::PI) / (2.0 * std::f64::consts::PI);
        let u_wi = [to_u(theta_i), to_v(phi_i)];
        let v_m = to_v(phi_m - phi_i);
        let u_m = [to_u(theta_m), v_m - v_m.floor()];
        let params = [phi_i, theta_i];
        let sample = self.vndf.invert(u_m, &params);
        let scale = self.ndf.eval(u_m, &[]) / (4.0 * self.sigma.eval(u_wi, &[]));
        let mut out = [0.0; 3];
        for (c, o) in out.iter_mut().enumerate() {
            *o = self.rgb.eval(sample, &[phi_i, theta_i, c as f64]) * scale;
        }
        out
    }

    /// The BRDF `f(wi, wo)` per channel, sr⁻¹ (without the cosine), negative channels clipped
    /// at 0 as RGL's loader does.
    pub fn eval(&self, wi: Vec3, wo: Vec3) -> [f64; 3] {
        let c = self.eval_cos(wi, wo);
        if wo.z <= 0.0 {
            return [0.0; 3];
        }
        c.map(|v| (v / wo.z).max(0.0))
    }
}

/// Reads a `.bsdf` file ([`RglBsdf::parse`]) and evaluates it on the grid of the `*.grid.csv`
/// files: θi, θo ∈ {0, 5, …, 80}°, φo − φi ∈ {0, 15, …, 180}° (θi outermost, the relative
/// azimuth innermost), the light at φi = 0. Absolute, RGB; named after the file's stem.
///
/// # Errors
/// As [`RglBsdf::parse`]; [`DataError::Format`] if an evaluation is not finite.
pub fn read(path: &Path, bytes: &[u8]) -> Result<Dataset, DataError> {
    let brdf = RglBsdf::parse(path, bytes)?;
    super::rows::on_grid(path, super::rows::stem(path), |wi, wo| brdf.eval(wi, wo))
}
