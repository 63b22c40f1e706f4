//! OFF (Object File Format) and its variants with extra per-vertex values (`COFF`, `NOFF`,
//! `STOFF`, ...). Only 3D, ASCII files; faces must have 3 or 4 vertices.

use super::lex::{Lexer, parse_f64, parse_usize, try_push, try_vec};
use super::{IoError, MeshData, push_face, push_int, push_xyz, write_items};
use crate::face::{NO_VERTEX, vertices};
use std::io::Write;

/// Reads an OFF text.
pub(super) fn read(text: &str) -> Result<MeshData, IoError> {
    let mut lex = Lexer::new(text, 1, Some('#'));
    let header = lex.next("the OFF header")?;
    let kind = header.s.strip_suffix("OFF").unwrap_or("");
    let known = ["", "C", "N", "CN", "ST", "STC", "STN", "STCN"];
    if !header.s.ends_with("OFF") || !known.contains(&kind) {
        if header.s.ends_with("OFF") {
            return Err(IoError::Unsupported(format!("OFF variant '{}' (only 3D OFF is read)", header.s)));
        }
        return Err(IoError::Parse {
            line: header.line,
            message: "the file does not start with 'OFF'".into(),
        });
    }
    if lex.peek().is_some_and(|t| t.s.eq_ignore_ascii_case("BINARY")) {
        return Err(IoError::Unsupported("binary OFF files".into()));
    }
    let nv = lex.usize("the vertex count")?;
    let nf = lex.usize("the face count")?;
    let _edges = lex.usize("the edge count")?;
    if nv > u32::MAX as usize {
        return Err(lex.error(format!("{nv} vertices are too many")));
    }
    let mut points = try_vec(nv.min(lex.max_tokens() / 3), "points")?;
    for _ in 0..nv {
        let line = lex.rest_of_line("a vertex")?;
        if line.len() < 3 {
            return Err(IoError::Parse { line: line[0].line, message: "a vertex needs x, y and z".into() });
        }
        let p = [
            parse_f64(line[0], "a coordinate")?,
            parse_f64(line[1], "a coordinate")?,
            parse_f64(line[2], "a coordinate")?,
        ];
        try_push(&mut points, p, "points")?;
    }
    let mut quads = try_vec(nf.min(lex.max_tokens() / 5), "quads")?;
    for face in 0..nf {
        let line = lex.rest_of_line("a face")?;
        let line_no = line[0].line;
        let k = parse_usize(line[0], "the face's vertex count")?;
        if !(3..=4).contains(&k) {
            return Err(IoError::NonQuad {
                line: line_no,
                cell: face,
                kind: format!("polygon with {k} vertices"),
            });
        }
        if line.len() < 1 + k {
            let message = if k == 4 {
                "a quad face needs 4 vertex indices"
            } else {
                "a triangle face needs 3 vertex indices"
            };
            return Err(IoError::Parse { line: line_no, message: message.into() });
        }
        let mut q = [NO_VERTEX; 4];
        for c in 0..k {
            let v = parse_usize(line[1 + c], "a vertex index")?;
            if v >= nv {
                return Err(IoError::Parse {
                    line: line_no,
                    message: format!("vertex index {v} is out of range ({nv} vertices)"),
                });
            }
            q[c] = v as u32;
        }
        try_push(&mut quads, q, "quads")?;
    }
    Ok(MeshData::new(points, quads))
}

/// Writes an OFF text.
pub(super) fn write(w: &mut dyn Write, data: &MeshData) -> std::io::Result<()> {
    writeln!(w, "OFF")?;
    writeln!(w, "{} {} 0", data.points.len(), data.quads.len())?;
    write_items(w, &data.points, |b, _, p| {
        push_xyz(b, p);
        b.push(b'\n');
    })?;
    write_items(w, &data.quads, |b, _, q| {
        push_int(b, vertices(q).len());
        push_face(b, q, 0);
        b.push(b'\n');
    })
}
