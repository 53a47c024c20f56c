//! The tensor file: named, typed n-dimensional arrays in one file, as Mitsuba 3's `TensorFile`
//! and pbrt-v4's `Tensor` read them (the container of RGL's `.bsdf` files, [`super::rgl`]).
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
//! The type codes are the readers': 1 = `u8`, 10 = `f32` (the two this format's BRDF files
//! use).

use std::io::{self, Write};

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

/// One named array.
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    /// The field's name.
    pub name: String,
    /// The element type.
    pub dtype: DType,
    /// The extents, outermost first.
    pub shape: Vec<u64>,
    /// The elements' bytes, little-endian, row-major.
    pub bytes: Vec<u8>,
}

impl Field {
    /// A byte field (e.g. a text).
    pub fn bytes(name: &str, data: &[u8]) -> Field {
        Field {
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
    pub fn f32(name: &str, shape: &[usize], data: &[f32]) -> Field {
        assert_eq!(
            shape.iter().product::<usize>(),
            data.len(),
            "field `{name}`: the data do not fill the shape"
        );
        Field {
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
pub fn file_len(fields: &[Field]) -> u64 {
    layout(fields).1
}

/// Each field's data offset, and the file's length.
fn layout(fields: &[Field]) -> (Vec<u64>, u64) {
    let mut at = 12 + 2 + 4 + fields.iter().map(Field::header_len).sum::<u64>();
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
pub fn write(mut out: impl Write, fields: &[Field]) -> io::Result<()> {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Reads a header as the format's readers do: each field's name, type code, offset, shape.
    fn headers(file: &[u8]) -> Vec<(String, u8, u64, Vec<u64>)> {
        assert_eq!(&file[..12], MAGIC);
        assert_eq!(&file[12..14], &[1, 0]);
        let n = u32::from_le_bytes(file[14..18].try_into().unwrap());
        let mut at = 18;
        let mut take = |k: usize| {
            let s = &file[at..at + k];
            at += k;
            s.to_vec()
        };
        (0..n)
            .map(|_| {
                let len = u16::from_le_bytes(take(2).try_into().unwrap()) as usize;
                let name = String::from_utf8(take(len)).unwrap();
                let rank = u16::from_le_bytes(take(2).try_into().unwrap());
                let code = take(1)[0];
                let offset = u64::from_le_bytes(take(8).try_into().unwrap());
                let shape = (0..rank)
                    .map(|_| u64::from_le_bytes(take(8).try_into().unwrap()))
                    .collect();
                (name, code, offset, shape)
            })
            .collect()
    }

    #[test]
    fn fields_are_laid_out_aligned_after_the_header_with_their_shapes_and_codes() {
        let fields = [
            Field::bytes("description", b"abc"),
            Field::f32("theta_i", &[3], &[0.0, 0.5, 1.0]),
            Field::f32("grid", &[2, 3], &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0]),
        ];
        let mut file = Vec::new();
        write(&mut file, &fields).unwrap();
        assert_eq!(file.len() as u64, file_len(&fields));
        let read = headers(&file);
        assert_eq!(read.len(), 3);
        for ((name, code, offset, shape), field) in read.iter().zip(&fields) {
            assert_eq!(name, &field.name);
            assert_eq!(*code, field.dtype.code());
            assert_eq!(shape, &field.shape);
            assert_eq!(offset % ALIGN, 0, "{name} is not aligned");
            let data = &file[*offset as usize..*offset as usize + field.bytes.len()];
            assert_eq!(data, field.bytes.as_slice());
        }
        let grid = &read[2];
        let at = grid.2 as usize + 4 * 4; // row 1, column 1
        assert_eq!(
            f32::from_le_bytes(file[at..at + 4].try_into().unwrap()),
            5.0
        );
        assert_eq!(DType::F32.size(), 4);
    }
}
