//! Wavefront OBJ: `v` and 3- or 4-vertex `f` statements (see the module docs of [`crate::io`]).

use super::lex::{Tok, clip, parse_f64, parse_i64, try_push};
use super::{IoError, MeshData, push_face, push_xyz, write_items};
use crate::face::NO_VERTEX;
use std::io::Write;

/// Reads an OBJ text.
pub(super) fn read(text: &str) -> Result<MeshData, IoError> {
    let mut points: Vec<[f64; 3]> = Vec::new();
    let mut quads: Vec<[u32; 4]> = Vec::new();
    // The faces whose indices cannot be resolved yet (a vertex not defined so far, or out of
    // range): (line, face, vertices defined at the face, indices as written), checked at the
    // end as every face would be, so the error names the first bad face and the final count.
    let mut unresolved: Vec<(usize, usize, usize, Raw)> = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line_no = i + 1;
        let body = line.split('#').next().unwrap_or("");
        let mut words = body.split_ascii_whitespace();
        let Some(key) = words.next() else { continue };
        let tok = |s| Tok { s, line: line_no };
        match key {
            "v" => {
                let mut xyz = [0.0; 3];
                let mut count = 0;
                for (c, w) in words.by_ref().take(3).enumerate() {
                    xyz[c] = parse_f64(tok(w), "a coordinate")?;
                    count += 1;
                }
                if count < 2 {
                    return Err(IoError::Parse {
                        line: line_no,
                        message: "a vertex needs x, y and z".into(),
                    });
                }
                // Further values (w, or colours) are ignored; a missing z is 0.
                try_push(&mut points, xyz, "points")?;
            }
            "f" => {
                let corners: [Option<&str>; 5] = std::array::from_fn(|_| words.next());
                let count = corners.iter().filter(|c| c.is_some()).count() + words.count();
                if !(3..=4).contains(&count) {
                    let kind = match count {
                        0..=2 => format!("face with {count} vertices"),
                        n => format!("polygon with {n} vertices"),
                    };
                    return Err(IoError::NonQuad { line: line_no, cell: quads.len(), kind });
                }
                let defined = points.len();
                let mut raw = Raw { indices: [0i64; 4], count };
                for (c, w) in corners.iter().take(count).enumerate() {
                    let head = w.unwrap_or("").split('/').next().unwrap_or("");
                    raw.indices[c] = parse_i64(tok(head), "a vertex index")?;
                }
                let q = match resolve(raw, defined, defined) {
                    Some(q) => q,
                    None => {
                        try_push(&mut unresolved, (line_no, quads.len(), defined, raw), "quads")?;
                        [0; 4]
                    }
                };
                try_push(&mut quads, q, "quads")?;
            }
            "l" | "p" => {
                let kind = if key == "l" { "line" } else { "point element" };
                return Err(IoError::NonQuad { line: line_no, cell: quads.len(), kind: kind.into() });
            }
            _ => {}
        }
    }
    if points.is_empty() && quads.is_empty() {
        // Bytes of another kind (a binary file named .obj): every line is an unknown statement,
        // which OBJ readers skip; say so rather than that the mesh has no quads.
        return Err(IoError::Malformed(
            "nothing in the file parsed as OBJ geometry: it has no vertex (v) or face (f) statement".into(),
        ));
    }
    let n = points.len();
    for (line, qi, defined, raw) in unresolved {
        quads[qi] = resolve(raw, defined, n).ok_or_else(|| {
            let one = |v| Raw { indices: [v; 4], count: 1 };
            let v =
                raw.written().iter().copied().find(|&v| resolve(one(v), defined, n).is_none()).unwrap_or(0);
            IoError::Parse {
                line,
                message: format!("vertex index {} is out of range ({n} vertices)", clip(&v.to_string())),
            }
        })?;
    }
    Ok(MeshData::new(points, quads))
}

/// A face's vertex indices as written: `count` (3 or 4) of them.
#[derive(Clone, Copy)]
struct Raw {
    indices: [i64; 4],
    count: usize,
}

impl Raw {
    fn written(&self) -> &[i64] {
        &self.indices[..self.count]
    }
}

/// The 0-based indices of a face as written (positive: 1-based; negative: relative to the
/// `defined` vertices before it), if all are below `n`; a triangle's fourth is [`NO_VERTEX`].
fn resolve(raw: Raw, defined: usize, n: usize) -> Option<[u32; 4]> {
    let mut q = [NO_VERTEX; 4];
    for (c, &v) in raw.written().iter().enumerate() {
        let index = if v > 0 { v - 1 } else { (defined as i64).checked_add(v)? };
        if v == 0 || index < 0 || index >= n as i64 || index > u32::MAX as i64 {
            return None;
        }
        q[c] = index as u32;
    }
    Some(q)
}

/// Writes an OBJ text.
pub(super) fn write(w: &mut dyn Write, data: &MeshData) -> std::io::Result<()> {
    writeln!(w, "# quad mesh written by quadopt")?;
    write_items(w, &data.points, |b, _, p| {
        b.extend_from_slice(b"v ");
        push_xyz(b, p);
        b.push(b'\n');
    })?;
    write_items(w, &data.quads, |b, _, q| {
        b.push(b'f');
        push_face(b, q, 1);
        b.push(b'\n');
    })
}
