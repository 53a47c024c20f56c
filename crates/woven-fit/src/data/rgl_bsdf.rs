//! RGL's measured `.bsdf` files (Dupuy & Jakob 2018): Mitsuba's little-endian "tensor file".
//!
//! Layout: the 12 bytes `tensor_file\0`, a version (two `u8`, 1.0), a `u32` field count, then per
//! field its name (`u16` length + bytes), its rank (`u16`), its type (`u8`: 1 u8, 2 i8, 3 u16,
//! 4 i16, 5 u32, 6 i32, 7 u64, 8 i64, 9 f16, 10 f32, 11 f64), the byte offset of its data (`u64`)
//! and its shape (`u64` per dimension). [`TensorFile::parse`] reads and checks all of it: every
//! field's data lies inside the file.
//!
//! **Not implemented: evaluating the BRDF of a `.bsdf` file.** That needs RGL's adaptive
//! parameterisation (inverting the warp of the visible-normal distribution, bilinear over the
//! grid, interpolated over the tabulated incidences). The repository carries instead the same
//! measurements evaluated by RGL's reference loader on a dense grid (`data/rgl/*.grid.csv`, read
//! by [`super::grid`]), so [`read`] refuses a `.bsdf` with a pointer to its grid.

use super::rows::format_error;
use super::{DataError, Dataset};
use std::path::Path;

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

/// Reads a `.bsdf` file: checks it ([`TensorFile::parse`]), then refuses it, since evaluating it
/// is not implemented (see the module docs), naming the grid file to use instead.
///
/// # Errors
/// Always: [`DataError::Format`].
pub fn read(path: &Path, bytes: &[u8]) -> Result<Dataset, DataError> {
    let file = TensorFile::parse(path, bytes)?;
    let what = file
        .description(bytes)
        .map(|d| format!(" ({})", super::rows::shorten(&d)))
        .unwrap_or_default();
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    Err(format_error(
        path,
        format!(
            "an RGL measured BSDF{what}: evaluating .bsdf files is not implemented; load its \
             grid, {stem}.grid.csv (RGL's reference loader evaluated on a dense grid; data/rgl/)"
        ),
    ))
}
