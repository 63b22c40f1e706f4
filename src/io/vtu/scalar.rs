//! VTK's data array types: their names, sizes, and the values of their little-endian bytes.

use super::clip;
use crate::io::IoError;

/// A data array's element type.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    I64,
    U64,
    F32,
    F64,
}

impl Scalar {
    pub fn parse(name: &str) -> Result<Scalar, IoError> {
        Ok(match name {
            "Int8" | "Char" => Scalar::I8,
            "UInt8" | "UnsignedChar" => Scalar::U8,
            "Int16" => Scalar::I16,
            "UInt16" => Scalar::U16,
            "Int32" => Scalar::I32,
            "UInt32" => Scalar::U32,
            "Int64" => Scalar::I64,
            "UInt64" => Scalar::U64,
            "Float32" => Scalar::F32,
            "Float64" => Scalar::F64,
            _ => return Err(IoError::Unsupported(format!("VTU data type {:?}", clip(name)))),
        })
    }

    pub fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::I64 | Scalar::U64 | Scalar::F64 => 8,
        }
    }

    /// The value of one element of `bytes` (exactly `size()` of them, little-endian).
    pub fn decode(self, b: &[u8]) -> f64 {
        let a = |n: usize| {
            let mut x = [0u8; 8];
            x[..n].copy_from_slice(&b[..n]);
            x
        };
        match self {
            Scalar::I8 => f64::from(b[0] as i8),
            Scalar::U8 => f64::from(b[0]),
            Scalar::I16 => f64::from(i16::from_le_bytes([b[0], b[1]])),
            Scalar::U16 => f64::from(u16::from_le_bytes([b[0], b[1]])),
            Scalar::I32 => f64::from(i32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::U32 => f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::I64 => i64::from_le_bytes(a(8)) as f64,
            Scalar::U64 => u64::from_le_bytes(a(8)) as f64,
            Scalar::F32 => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::F64 => f64::from_le_bytes(a(8)),
        }
    }

    /// Integers of 64 bits are kept exact (an index above 2^53 is out of range anyway).
    pub fn decode_int(self, b: &[u8]) -> Option<i64> {
        match self {
            Scalar::I64 => Some(i64::from_le_bytes(b[..8].try_into().ok()?)),
            Scalar::U64 => i64::try_from(u64::from_le_bytes(b[..8].try_into().ok()?)).ok(),
            Scalar::F32 | Scalar::F64 => None,
            _ => Some(self.decode(b) as i64),
        }
    }
}
