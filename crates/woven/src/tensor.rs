//! The tensor file: named, typed n-dimensional arrays in one file, as Mitsuba 3's `TensorFile`
//! and pbrt-v4's `Tensor` read them: the container of RGL's `.bsdf` files, which woven writes
//! ([`crate::export::rgl`]) and its fitter reads (RGL's measured felts). [`write()`] writes one;
//! [`TensorFile::parse`] reads and checks one's directory.
//!
//! Little-endian throughout:
//!
//! | bytes | content |
//! |---|---|
//! | 12 | `tensor_file` and a NUL |
//! | 2 | version: major 1, minor 0 |
//! | 4 | `u32`: the number of fields |
//! | per field | `u16` name length, the name (UTF-8), `u16` rank, `u8` type code, `u64` offset of the data from the start of the file, then the rank's `u64` extents |
//! | per field | its data, row-major (the last index fastest), starting at a multiple of 8 bytes |
//!
//! The type codes are the readers': 1 `u8`, 2 `i8`, 3 `u16`, 4 `i16`, 5 `u32`, 6 `i32`, 7 `u64`,
//! 8 `i64`, 9 `f16`, 10 `f32`, 11 `f64`. woven writes `u8` and `f32` (all a BRDF file uses).

use crate::error::{Error, Result};
use std::io::{self, Write};
use std::path::Path;

/// The file's first 12 bytes.
pub const MAGIC: &[u8; 12] = b"tensor_file\0";

/// Where each field's data starts: a multiple of this many bytes.
pub const ALIGN: u64 = 8;

/// A field's element type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DType {
    /// Unsigned bytes (code 1).
    U8,
    /// 32-bit floats (code 10).
    F32,
}

impl DType {
    /// The readers' type code.
    pub fn code(self) -> u8 {
        match self {
            DType::U8 => 1,
            DType::F32 => 10,
        }
    }

    /// Bytes per element.
    pub fn size(self) -> usize {
        match self {
            DType::U8 => 1,
            DType::F32 => 4,
        }
    }
}

/// One named array to write.
#[derive(Clone, Debug, PartialEq)]
pub struct Data {
    /// The field's name.
    pub name: String,
    /// The element type.
    pub dtype: DType,
    /// The extents, outermost first.
    pub shape: Vec<u64>,
    /// The elements' bytes, little-endian, row-major.
    pub bytes: Vec<u8>,
}

impl Data {
    /// A byte field (e.g. a text).
    pub fn bytes(name: &str, data: &[u8]) -> Data {
        Data {
            name: name.to_string(),
            dtype: DType::U8,
            shape: vec![data.len() as u64],
            bytes: data.to_vec(),
        }
    }

    /// A float field of `shape`; `data` holds the product of `shape` values.
    ///
    /// # Panics
    /// When `data`'s length is not the product of `shape` (a caller's bug).
    pub fn f32(name: &str, shape: &[usize], data: &[f32]) -> Data {
        assert_eq!(
            shape.iter().product::<usize>(),
            data.len(),
            "field `{name}`: the data do not fill the shape"
        );
        Data {
            name: name.to_string(),
            dtype: DType::F32,
            shape: shape.iter().map(|&n| n as u64).collect(),
            bytes: data.iter().flat_map(|x| x.to_le_bytes()).collect(),
        }
    }

    fn header_len(&self) -> u64 {
        (2 + self.name.len() + 2 + 1 + 8 + 8 * self.shape.len()) as u64
    }
}

/// The size of the file holding `fields`, bytes.
pub fn file_len(fields: &[Data]) -> u64 {
    layout(fields).1
}

/// Each field's data offset, and the file's length.
fn layout(fields: &[Data]) -> (Vec<u64>, u64) {
    let mut at = 12 + 2 + 4 + fields.iter().map(Data::header_len).sum::<u64>();
    let offsets = fields
        .iter()
        .map(|f| {
            at = at.next_multiple_of(ALIGN);
            let offset = at;
            at += f.bytes.len() as u64;
            offset
        })
        .collect();
    (offsets, at)
}

/// Writes `fields` as a tensor file.
///
/// # Errors
/// The writer's.
pub fn write(mut out: impl Write, fields: &[Data]) -> io::Result<()> {
    let (offsets, _) = layout(fields);
    out.write_all(MAGIC)?;
    out.write_all(&[1, 0])?;
    out.write_all(&(fields.len() as u32).to_le_bytes())?;
    let mut at = 12 + 2 + 4;
    for (field, offset) in fields.iter().zip(&offsets) {
        out.write_all(&(field.name.len() as u16).to_le_bytes())?;
        out.write_all(field.name.as_bytes())?;
        out.write_all(&(field.shape.len() as u16).to_le_bytes())?;
        out.write_all(&[field.dtype.code()])?;
        out.write_all(&offset.to_le_bytes())?;
        for n in &field.shape {
            out.write_all(&n.to_le_bytes())?;
        }
        at += field.header_len();
    }
    for (field, &offset) in fields.iter().zip(&offsets) {
        out.write_all(&vec![0; (offset - at) as usize])?;
        out.write_all(&field.bytes)?;
        at = offset + field.bytes.len() as u64;
    }
    Ok(())
}

/// One field of a tensor file as read: its name, element type, shape and where its data lies.
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    /// The field's name (`theta_i`, `rgb`, `vndf`, …).
    pub name: String,
    /// The element type code (see the module docs).
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
    /// [`Error::Parse`] naming `path` for a wrong magic or version, a truncated directory, an
    /// unknown element type, or a field whose data runs past the end of the file.
    pub fn parse(path: &Path, bytes: &[u8]) -> Result<TensorFile> {
        let bad = |what: String| Error::Parse {
            path: path.display().to_string(),
            message: format!("not a valid tensor file: {what}"),
        };
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
        if f.dtype != DType::F32.code() {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_are_laid_out_aligned_after_the_header_and_read_back() {
        let fields = [
            Data::bytes("description", b"abc"),
            Data::f32("theta_i", &[3], &[0.0, 0.5, 1.0]),
            Data::f32("grid", &[2, 3], &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0]),
        ];
        let mut file = Vec::new();
        write(&mut file, &fields).unwrap();
        assert_eq!(file.len() as u64, file_len(&fields));
        let read = TensorFile::parse(Path::new("t.bsdf"), &file).unwrap();
        assert_eq!(read.fields.len(), 3);
        for (got, field) in read.fields.iter().zip(&fields) {
            assert_eq!(got.name, field.name);
            assert_eq!(got.dtype, field.dtype.code());
            assert_eq!(got.shape, field.shape);
            assert_eq!(got.offset % ALIGN, 0, "{} is not aligned", got.name);
            let data = &file[got.offset as usize..got.offset as usize + field.bytes.len()];
            assert_eq!(data, field.bytes.as_slice());
        }
        assert_eq!(read.description(&file).as_deref(), Some("abc"));
        assert_eq!(read.f32s(&file, "grid").unwrap()[4], 5.0); // row 1, column 1
        assert_eq!(DType::F32.size(), 4);
        // Every truncation is an error naming the file, never a panic.
        for n in 0..file.len() {
            let e = TensorFile::parse(Path::new("t.bsdf"), &file[..n]).unwrap_err();
            assert!(e.to_string().starts_with("t.bsdf"), "{e}");
        }
    }
}
