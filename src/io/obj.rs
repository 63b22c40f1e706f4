//! Wavefront OBJ: `v` and 4-vertex `f` statements (see the module docs of [`crate::io`]).

use super::lex::{Lexer, Tok, clip, parse_f64, parse_i64};
use super::{IoError, MeshData, Num};
use std::io::Write;

/// Reads an OBJ text.
pub(super) fn read(text: &str) -> Result<MeshData, IoError> {
    let mut points: Vec<[f64; 3]> = Vec::new();
    let mut quads: Vec<[u32; 4]> = Vec::new();
    // (line, corner values as written) of every quad, resolved once all vertices are known.
    let mut raw: Vec<(usize, [i64; 4], usize)> = Vec::new();
    let mut element = 0usize;
    for (i, line) in text.lines().enumerate() {
        let line_no = i + 1;
        let mut lex = Lexer::new(std::iter::once(line), line_no, Some('#'));
        let Some(key) = lex.peek() else { continue };
        lex.next("a statement")?;
        let args: Vec<Tok> = std::iter::from_fn(|| lex.next("").ok()).collect();
        match key.s {
            "v" => {
                if args.len() < 2 {
                    return Err(IoError::Parse {
                        line: line_no,
                        message: "a vertex needs x, y and z".into(),
                    });
                }
                let x = parse_f64(args[0], "a coordinate")?;
                let y = parse_f64(args[1], "a coordinate")?;
                let z = match args.get(2) {
                    Some(&t) => parse_f64(t, "a coordinate")?,
                    None => 0.0,
                };
                points.push([x, y, z]);
            }
            "f" => {
                if args.len() != 4 {
                    let kind = match args.len() {
                        0..=2 => format!("face with {} vertices", args.len()),
                        3 => "triangle".to_string(),
                        n => format!("polygon with {n} vertices"),
                    };
                    return Err(IoError::NonQuad { line: line_no, cell: element, kind });
                }
                let mut q = [0i64; 4];
                for (c, t) in args.iter().enumerate() {
                    let head = Tok { s: t.s.split('/').next().unwrap_or(""), line: line_no };
                    q[c] = parse_i64(head, "a vertex index")?;
                }
                raw.push((line_no, q, points.len()));
                element += 1;
            }
            "l" | "p" => {
                let kind = if key.s == "l" { "line" } else { "point element" };
                return Err(IoError::NonQuad { line: line_no, cell: element, kind: kind.into() });
            }
            _ => {}
        }
    }
    let n = points.len();
    for (line, q, defined) in raw {
        let mut out = [0u32; 4];
        for c in 0..4 {
            let v = q[c];
            // Positive: 1-based; negative: relative to the vertices defined so far.
            let index = if v > 0 { v - 1 } else { defined as i64 + v };
            if v == 0 || index < 0 || index >= n as i64 || index > u32::MAX as i64 {
                return Err(IoError::Parse {
                    line,
                    message: format!("vertex index {} is out of range ({n} vertices)", clip(&v.to_string())),
                });
            }
            out[c] = index as u32;
        }
        quads.push(out);
    }
    Ok(MeshData::new(points, quads))
}

/// Writes an OBJ text.
pub(super) fn write(w: &mut dyn Write, data: &MeshData) -> std::io::Result<()> {
    writeln!(w, "# quad mesh written by quadopt")?;
    for p in &data.points {
        writeln!(w, "v {} {} {}", Num(p[0]), Num(p[1]), Num(p[2]))?;
    }
    for q in &data.quads {
        writeln!(w, "f {} {} {} {}", q[0] + 1, q[1] + 1, q[2] + 1, q[3] + 1)?;
    }
    Ok(())
}
