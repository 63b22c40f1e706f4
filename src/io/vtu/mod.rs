//! VTK XML UnstructuredGrid (`.vtu`), ParaView's own format: triangles and quads (cell types 5
//! and 9), the point
//! data array `fixed` read as the fixed flags, and the arrays of [`MeshData`] written.
//!
//! Read: data arrays in `ascii`, inline `binary` (base64) and `appended` (raw or base64)
//! form, little- or big-endian, UInt32 or UInt64 block headers, uncompressed or compressed
//! with `vtkZLibDataCompressor` (ParaView's default); any other compressor is an error that
//! names it. Written: Float64 points, Int64 connectivity and offsets, UInt8 types and flags,
//! little-endian with UInt64 headers, in [`MeshData::encoding`], zlib-compressed when
//! [`MeshData::compressed`].
//!
//! The XML is parsed with `quick-xml`, zlib by `flate2`, base64 by `base64`. `vtkio` (the
//! crate that reads and writes XML VTK) was not used: its XML support is in 0.7, which is a
//! release candidate only (0.7.0-rc2), and its reader does not document that it never panics,
//! which the fuzz targets require.
//!
//! By concern: [`xml`] reads the XML structure (the file's settings, the piece's counts, the
//! data arrays and where they sit) without decoding any data; [`decode`] decodes a data
//! array (ASCII, inline base64, appended raw or base64, zlib blocks) into values of a
//! [`scalar`] type, checking every size a header declares against what the piece's counts
//! need (points x 3, cells) and against the bytes present before anything is allocated or
//! decompressed; [`write`](mod@write) writes a file. This module puts the mesh together.

mod decode;
mod scalar;
mod write;
mod xml;

pub(super) use write::write;

use super::lex::try_vec;
use super::{IoError, MeshData};
use crate::face::NO_VERTEX;
use decode::Decoder;
use xml::{Document, Section};

/// VTK's cell type of a triangle.
const VTK_TRIANGLE: i64 = 5;
/// VTK's cell type of a quad.
const VTK_QUAD: i64 = 9;

/// The number of points of a cell of VTK type `ty`, if it is a triangle or a quad.
fn corners_of(ty: i64) -> Option<usize> {
    match ty {
        VTK_TRIANGLE => Some(3),
        VTK_QUAD => Some(4),
        _ => None,
    }
}

fn bad(message: impl Into<String>) -> IoError {
    IoError::Malformed(message.into())
}

fn clip(s: &str) -> String {
    super::lex::clip(s)
}

/// Reads a VTU file. Never panics, whatever the bytes.
pub(super) fn read(bytes: &[u8]) -> Result<MeshData, IoError> {
    let Document { info, points: n, cells: m, arrays, appended, appended_base64 } = xml::parse(bytes)?;
    let mut ctx = Decoder::new(info, appended, appended_base64);

    let find = |sec: Section, name: Option<&str>| {
        arrays.iter().position(|(s, a)| *s == sec && name.is_none_or(|nm| a.name == nm))
    };
    let points_at = find(Section::Points, None).ok_or_else(|| bad("<Points> has no <DataArray>"))?;
    let pa = &arrays[points_at].1;
    if pa.components != 3 {
        return Err(bad(format!("points have {} components (3 expected)", pa.components)));
    }
    let coords = ctx.reals(pa, n.checked_mul(3).ok_or_else(|| bad("too many points"))?)?;
    let mut points = try_vec(n, "points")?;
    points.extend(coords.chunks_exact(3).map(|c| [c[0], c[1], c[2]]));

    let cell = |name: &str| {
        find(Section::Cells, Some(name)).ok_or_else(|| bad(format!("<Cells> has no DataArray {name:?}")))
    };
    let (ci, oi, ti) = (cell("connectivity")?, cell("offsets")?, cell("types")?);
    let ints = |ctx: &mut Decoder<'_>, i: usize, count: usize| ctx.ints(&arrays[i].1, count);
    let types = ints(&mut ctx, ti, m)?;
    let offsets = ints(&mut ctx, oi, m)?;
    // Every cell's type and extent first, so the connectivity is decoded at the size they call
    // for (at most 4 per cell).
    let mut start = 0i64;
    for c in 0..m {
        let Some(corners) = corners_of(types[c]) else {
            let points = offsets[c].checked_sub(start).filter(|&k| k >= 0 && types[c] == 7);
            let with = points.map_or(String::new(), |k| format!(" (polygon) with {k} vertices"));
            return Err(IoError::Unsupported(format!(
                "cell {c} is of VTK type {}{with}; only triangles (type 5) and quads (type 9) are read \
                 (cell numbers are 0-based)",
                types[c]
            )));
        };
        if offsets[c] != start + corners as i64 {
            let kind = if corners == 3 { "a triangle has 3 vertices" } else { "a quad has 4 vertices" };
            return Err(bad(format!(
                "offsets: cell {c} ends at {} after starting at {start} ({kind}; cell numbers are 0-based)",
                offsets[c]
            )));
        }
        start = offsets[c];
    }
    let connectivity = ints(&mut ctx, ci, start as usize)?;
    let mut quads = try_vec(m, "quads")?;
    let mut s = 0;
    for (c, &ty) in types.iter().enumerate() {
        let corners = corners_of(ty).unwrap_or(4);
        let mut q = [NO_VERTEX; 4];
        for (k, slot) in q.iter_mut().take(corners).enumerate() {
            let v = connectivity[s + k];
            let out_of_range = IoError::Mesh(crate::Error::IndexOutOfRange {
                quad: c,
                corner: k,
                index: v as u64,
                vertex_count: n,
            });
            *slot = u32::try_from(v).ok().filter(|&v| (v as usize) < n).ok_or(out_of_range)?;
        }
        quads.push(q);
        s += corners;
    }
    let fixed = match find(Section::PointData, Some("fixed")) {
        Some(i) if arrays[i].1.components == 1 => {
            Some(ctx.reals(&arrays[i].1, n)?.iter().map(|&x| x != 0.0).collect())
        }
        _ => None,
    };
    let encoding = ctx.encoding();
    Ok(MeshData { points, quads, fixed, encoding, compressed: info.compressed, ..MeshData::default() })
}
