//! Legacy VTK, ASCII: `UNSTRUCTURED_GRID` with triangle and quad cells or `POLYDATA` with 3-
//! and 4-vertex polygons, and a point-data array `fixed` (see the module docs of [`crate::io`]).

use super::lex::{Lexer, Tok, clip, parse_usize, try_push, try_vec};
use super::{IoError, MeshData, push_f64, push_face, push_int, push_xyz, write_items};
use crate::face::{NO_VERTEX, corner_count, is_triangle};
use std::io::Write;

/// VTK's cell type number of a triangle.
const VTK_TRIANGLE: usize = 5;
/// VTK's cell type number of a polygon.
const VTK_POLYGON: usize = 7;
/// VTK's cell type number of a quad.
const VTK_QUAD: usize = 9;

/// Cells as read, kept as faces (quads, and triangles with [`NO_VERTEX`] fourth): of a cell
/// with another number of points only the first is remembered (for the error), and of the
/// point indices only the first out of range.
#[derive(Default)]
struct Cells {
    /// Number of cells.
    count: usize,
    /// The cells of 3 or 4 points (one per cell up to the first other cell).
    quads: Vec<[u32; 4]>,
    /// The line of each of `quads`.
    lines: Vec<usize>,
    /// Line of the first cell.
    first_line: Option<usize>,
    /// The first cell not of 3 or 4 points: (cell, its point count, line).
    other: Option<(usize, usize, usize)>,
    /// The first point index out of range: (cell, index, line). With no points read yet,
    /// the largest index, checked at the end.
    bad_index: Option<(usize, usize, usize)>,
}

impl Cells {
    /// Files point index `v` of cell `cell`, checked against `points` when known.
    fn index(&mut self, v: usize, cell: usize, line: usize, points: Option<usize>) -> u32 {
        let bad = match (points, self.bad_index) {
            (Some(n), None) => v >= n,
            (None, None) => true,
            (None, Some((_, worst, _))) => v > worst,
            (Some(_), Some(_)) => false,
        };
        if bad {
            self.bad_index = Some((cell, v, line));
        }
        u32::try_from(v).unwrap_or(u32::MAX)
    }

    /// Files a cell of `k` points (`k` is 3 or 4: `q` holds them).
    fn cell(&mut self, k: usize, q: [u32; 4], line: usize) -> Result<(), IoError> {
        self.first_line.get_or_insert(line);
        if k == 3 || k == 4 {
            self.face(k, q, line)?;
        } else if self.other.is_none() {
            self.other = Some((self.count, k, line));
        }
        self.count += 1;
        Ok(())
    }

    /// Keeps the face of a cell of `k` (3 or 4) points, the first `k` of `q`.
    fn face(&mut self, k: usize, mut q: [u32; 4], line: usize) -> Result<(), IoError> {
        if k == 3 {
            q[3] = NO_VERTEX;
        }
        try_push(&mut self.quads, q, "quads")?;
        try_push(&mut self.lines, line, "quads")
    }

    /// The number of points of cell `i`, when known.
    fn point_count(&self, i: usize) -> Option<usize> {
        match self.other {
            Some((j, k, _)) if j == i => Some(k),
            Some((j, ..)) if j < i => None,
            _ => self.quads.get(i).map(corner_count),
        }
    }
}

/// Cell types as read: their count, the types of triangles and quads, and the first that is
/// neither.
struct Types {
    count: usize,
    /// Per cell: its type if a triangle or a quad, else 0.
    kinds: Vec<u8>,
    /// Line of the first type.
    first_line: Option<usize>,
    /// The first type that is neither a triangle nor a quad: (cell, type, line).
    other: Option<(usize, usize, usize)>,
}

/// Where attribute arrays currently belong.
#[derive(Clone, Copy, PartialEq)]
enum Section {
    None,
    Point(usize),
    Cell(usize),
}

/// Reads a legacy VTK text.
pub(super) fn read(text: &str) -> Result<MeshData, IoError> {
    let mut lex = Lexer::new(text, 1, None);
    let header = lex.raw_line().unwrap_or("");
    if !header.trim_start().to_ascii_lowercase().starts_with("# vtk datafile") {
        return Err(IoError::Parse {
            line: 1,
            message: "not a legacy VTK file (no '# vtk DataFile' header)".into(),
        });
    }
    if lex.raw_line().is_none() {
        return Err(IoError::Parse {
            line: 2,
            message: "unexpected end of file (expected the title line)".into(),
        });
    }
    let encoding = lex.next("ASCII or BINARY")?;
    if encoding.s.eq_ignore_ascii_case("BINARY") {
        return Err(IoError::Unsupported("binary VTK files (save the mesh as ASCII)".into()));
    }
    if !encoding.s.eq_ignore_ascii_case("ASCII") {
        return Err(parse_err(encoding, format!("expected ASCII or BINARY, found '{}'", clip(encoding.s))));
    }
    let t = lex.next("DATASET")?;
    if !t.s.eq_ignore_ascii_case("DATASET") {
        return Err(parse_err(t, format!("expected DATASET, found '{}'", clip(t.s))));
    }
    let dataset = lex.next("the dataset type")?;
    let polydata = if dataset.s.eq_ignore_ascii_case("POLYDATA") {
        true
    } else if dataset.s.eq_ignore_ascii_case("UNSTRUCTURED_GRID") {
        false
    } else {
        return Err(IoError::Unsupported(format!(
            "VTK dataset {} (only UNSTRUCTURED_GRID and POLYDATA hold quad meshes)",
            clip(dataset.s)
        )));
    };

    let mut points: Option<Vec<[f64; 3]>> = None;
    let mut cells: Option<Cells> = None;
    let mut types: Option<Types> = None;
    let mut fixed: Option<Vec<bool>> = None;
    let mut section = Section::None;
    while let Some(key) = lex.peek() {
        lex.next("")?;
        let k = key.s.to_ascii_uppercase();
        match k.as_str() {
            "POINTS" => {
                let n = lex.usize("the point count")?;
                let _ty = data_type(&mut lex)?;
                if n > u32::MAX as usize {
                    return Err(parse_err(key, format!("{n} points are too many")));
                }
                let mut p = try_vec(n.min(lex.max_tokens() / 3), "points")?;
                for _ in 0..n {
                    let xyz = [lex.f64("a coordinate")?, lex.f64("a coordinate")?, lex.f64("a coordinate")?];
                    try_push(&mut p, xyz, "points")?;
                }
                points = Some(p);
            }
            "CELLS" if !polydata => cells = Some(read_cells(&mut lex, points.as_ref().map(Vec::len))?),
            "POLYGONS" if polydata => cells = Some(read_cells(&mut lex, points.as_ref().map(Vec::len))?),
            "VERTICES" | "LINES" | "TRIANGLE_STRIPS" if polydata => {
                let c = read_cells(&mut lex, None)?;
                if let Some(line) = c.first_line {
                    let kind = match k.as_str() {
                        "VERTICES" => "vertex cell",
                        "LINES" => "line",
                        _ => "triangle strip",
                    };
                    return Err(IoError::NonQuad { line, cell: 0, kind: kind.into() });
                }
            }
            "CELL_TYPES" if !polydata => {
                let n = lex.usize("the cell type count")?;
                let kinds = try_vec(n.min(lex.max_tokens()), "cell types")?;
                let mut t = Types { count: n, kinds, first_line: None, other: None };
                for i in 0..n {
                    let tok = lex.next("a cell type")?;
                    let ty = parse_usize(tok, "a cell type")?;
                    t.first_line.get_or_insert(tok.line);
                    let known = ty == VTK_QUAD || ty == VTK_TRIANGLE;
                    if !known && t.other.is_none() {
                        t.other = Some((i, ty, tok.line));
                    }
                    try_push(&mut t.kinds, if known { ty as u8 } else { 0 }, "cell types")?;
                }
                types = Some(t);
            }
            "POINT_DATA" => section = Section::Point(lex.usize("the point data count")?),
            "CELL_DATA" => section = Section::Cell(lex.usize("the cell data count")?),
            "SCALARS" => {
                let name = lex.next("the array name")?;
                let _ty = data_type(&mut lex)?;
                let mut comps = 1;
                // The optional component count is on the SCALARS line (values follow on the next).
                if lex.peek().is_some_and(|t| t.line == name.line && t.s.parse::<usize>().is_ok()) {
                    comps = lex.usize("the component count")?;
                }
                if lex.eat("LOOKUP_TABLE") {
                    lex.next("the lookup table name")?;
                }
                let count = attribute_count(section, key)?;
                if let (Section::Point(_), "fixed") = (section, name.s) {
                    fixed = Some(read_flags(&mut lex, count, comps)?);
                } else {
                    lex.skip(mul(count, comps, key)?, name.s)?;
                }
            }
            "FIELD" => {
                lex.next("the field name")?;
                let arrays = lex.usize("the array count")?;
                for _ in 0..arrays {
                    let name = lex.next("an array name")?;
                    let comps = lex.usize("the component count")?;
                    let tuples = lex.usize("the tuple count")?;
                    let _ty = data_type(&mut lex)?;
                    if matches!(section, Section::Point(_)) && name.s == "fixed" {
                        fixed = Some(read_flags(&mut lex, tuples, comps)?);
                    } else {
                        lex.skip(mul(tuples, comps, key)?, name.s)?;
                    }
                }
            }
            "VECTORS" | "NORMALS" | "TENSORS" | "GLOBAL_IDS" | "PEDIGREE_IDS" => {
                let name = lex.next("the array name")?;
                let _ty = data_type(&mut lex)?;
                let per = match k.as_str() {
                    "VECTORS" | "NORMALS" => 3,
                    "TENSORS" => 9,
                    _ => 1,
                };
                let count = attribute_count(section, key)?;
                lex.skip(mul(count, per, key)?, name.s)?;
            }
            "TEXTURE_COORDINATES" => {
                let name = lex.next("the array name")?;
                let dim = lex.usize("the dimension")?;
                let _ty = data_type(&mut lex)?;
                let count = attribute_count(section, key)?;
                lex.skip(mul(count, dim, key)?, name.s)?;
            }
            "COLOR_SCALARS" => {
                let name = lex.next("the array name")?;
                let per = lex.usize("the value count")?;
                let count = attribute_count(section, key)?;
                lex.skip(mul(count, per, key)?, name.s)?;
            }
            "LOOKUP_TABLE" => {
                let name = lex.next("the table name")?;
                let size = lex.usize("the table size")?;
                lex.skip(mul(size, 4, key)?, name.s)?;
            }
            "METADATA" => {
                // Information keys, up to a blank line.
                while lex.peek().is_some() && !lex.blank_line_before_next() {
                    lex.next("")?;
                }
            }
            _ => return Err(parse_err(key, format!("unexpected '{}'", clip(key.s)))),
        }
    }

    let Some(points) = points else {
        return Err(IoError::Parse { line: lex.line(), message: "the file has no POINTS section".into() });
    };
    let n = points.len();
    let what = if polydata { "POLYGONS" } else { "CELLS" };
    let cells = cells.ok_or_else(|| lex.error(format!("the file has no {what} section")))?;
    // The first cell whose point count is wrong: not 3 or 4, or not its type's.
    let mut wrong = cells.other;
    let mut kinds = Vec::new();
    if !polydata {
        let types = types.ok_or_else(|| lex.error("the file has no CELL_TYPES section"))?;
        if types.count != cells.count {
            return Err(IoError::Parse {
                line: types.first_line.unwrap_or_else(|| lex.line()),
                message: format!("{} cell types were given for {} cells", types.count, cells.count),
            });
        }
        if let Some((i, ty, line)) = types.other {
            let mut kind = format!("{} (VTK type {ty})", type_name(ty));
            if let (VTK_POLYGON, Some(k)) = (ty, cells.point_count(i)) {
                kind = format!("{kind} with {k} vertices");
            }
            return Err(IoError::NonQuad { line, cell: i, kind });
        }
        let before = cells.other.map_or(cells.quads.len(), |(i, ..)| i).min(cells.quads.len());
        let expected = |i: usize| if usize::from(types.kinds[i]) == VTK_TRIANGLE { 3 } else { 4 };
        if let Some(i) = (0..before).find(|&i| corner_count(&cells.quads[i]) != expected(i)) {
            wrong = Some((i, corner_count(&cells.quads[i]), cells.lines[i]));
        }
        kinds = types.kinds;
    }
    // The first problem cell: one with a wrong point count, or one referring to a missing point.
    let bad_index = cells.bad_index.filter(|&(_, v, _)| v >= n);
    let other_first = match (wrong, bad_index) {
        (Some((a, ..)), Some((b, ..))) => a <= b,
        (other, _) => other.is_some(),
    };
    if let (true, Some((i, k, line))) = (other_first, wrong) {
        if polydata {
            return Err(IoError::NonQuad { line, cell: i, kind: format!("polygon with {k} vertices") });
        }
        let kind = if usize::from(kinds[i]) == VTK_TRIANGLE { "triangle" } else { "quad" };
        return Err(IoError::Parse {
            line,
            message: format!("{kind} cell {i} has {k} vertices (cell numbers are 0-based)"),
        });
    }
    if let Some((i, v, line)) = bad_index {
        return Err(IoError::Parse {
            line,
            message: format!(
                "cell {i} refers to point {v}, but there are only {n} points (cell and point numbers are 0-based)"
            ),
        });
    }
    let quads = cells.quads;
    if let Some(len) = fixed.as_ref().map(Vec::len).filter(|&len| len != n) {
        return Err(lex.error(format!("the fixed array has {len} values for {n} points")));
    }
    Ok(MeshData { points, quads, fixed, msh_version: None, vtk_polydata: polydata, ..MeshData::default() })
}

fn parse_err(t: Tok<'_>, message: String) -> IoError {
    IoError::Parse { line: t.line, message }
}

fn mul(a: usize, b: usize, at: Tok<'_>) -> Result<usize, IoError> {
    a.checked_mul(b).ok_or_else(|| parse_err(at, "array size overflows".into()))
}

/// The number of tuples of an attribute in the current section.
fn attribute_count(section: Section, key: Tok<'_>) -> Result<usize, IoError> {
    match section {
        Section::Point(n) | Section::Cell(n) => Ok(n),
        Section::None => Err(parse_err(key, format!("{} before POINT_DATA or CELL_DATA", clip(key.s)))),
    }
}

/// A data type name (checked, so a shifted file is caught early).
fn data_type<'a>(lex: &mut Lexer<'a>) -> Result<Tok<'a>, IoError> {
    const TYPES: [&str; 17] = [
        "bit",
        "char",
        "unsigned_char",
        "short",
        "unsigned_short",
        "int",
        "unsigned_int",
        "long",
        "unsigned_long",
        "float",
        "double",
        "vtkidtype",
        "vtktypeint64",
        "vtktypeint32",
        "vtktypeuint64",
        "vtktypeuint32",
        "string",
    ];
    let t = lex.next("a data type")?;
    if !TYPES.iter().any(|k| t.s.eq_ignore_ascii_case(k)) {
        return Err(parse_err(t, format!("unknown data type '{}'", clip(t.s))));
    }
    Ok(t)
}

/// Reads `count` tuples of `comps` numbers as flags: a tuple is fixed when any component is
/// nonzero.
fn read_flags(lex: &mut Lexer<'_>, count: usize, comps: usize) -> Result<Vec<bool>, IoError> {
    if comps == 0 {
        return Err(lex.error("the fixed array has 0 components"));
    }
    let mut flags = try_vec(count.min(lex.max_tokens()), "fixed flags")?;
    for _ in 0..count {
        let mut any = false;
        for _ in 0..comps {
            let v = lex.f64("a fixed flag")?;
            any |= v != 0.0;
        }
        try_push(&mut flags, any, "fixed flags")?;
    }
    Ok(flags)
}

/// Reads a cell list: classic `n size` followed by `count i0 i1 ...` per cell, or VTK 5.1's
/// `n_offsets n_conn` followed by `OFFSETS type ...` and `CONNECTIVITY type ...`. `points`
/// is the number of points when they were read before.
fn read_cells(lex: &mut Lexer<'_>, points: Option<usize>) -> Result<Cells, IoError> {
    let n = lex.usize("the cell count")?;
    let size = lex.usize("the cell list size")?;
    let mut cells = Cells::default();
    if lex.eat("OFFSETS") {
        data_type(lex)?;
        let cell_count = n.saturating_sub(1);
        cells.quads = try_vec(cell_count.min(lex.max_tokens()), "quads")?;
        // Per cell: where it ends, and the line of that offset.
        let mut ends: Vec<(usize, usize)> = try_vec(cell_count.min(lex.max_tokens()), "offsets")?;
        let mut previous: Option<usize> = None;
        for i in 0..n {
            let t = lex.next("an offset")?;
            let o = parse_usize(t, "an offset")?;
            if o > size || previous.is_some_and(|p| o < p) || (i == 0 && o != 0) {
                return Err(parse_err(t, format!("offset {o} is out of order or beyond {size}")));
            }
            // Cell i - 1 starts at the previous offset; its line is that offset's.
            if let Some(p) = previous {
                cells.first_line.get_or_insert(t.line);
                if !(3..=4).contains(&(o - p)) && cells.other.is_none() {
                    cells.other = Some((i - 1, o - p, t.line));
                }
                try_push(&mut ends, (o, t.line), "offsets")?;
                cells.count += 1;
            }
            previous = Some(o);
        }
        if !lex.eat("CONNECTIVITY") {
            return Err(lex.error("expected CONNECTIVITY"));
        }
        data_type(lex)?;
        let mut q = [0u32; 4];
        // The cell the index at `k` belongs to (`ends.len()` past the last offset), and where
        // it starts.
        let (mut cell, mut start) = (0, 0);
        for k in 0..size {
            let t = lex.next("a point index")?;
            let v = parse_usize(t, "a point index")?;
            while ends.get(cell).is_some_and(|&(end, _)| end <= k) {
                start = ends[cell].0;
                cell += 1;
            }
            let index = cells.index(v, cell, t.line, points);
            if let Some(c) = q.get_mut(k - start) {
                *c = index;
            }
            // A cell of 3 or 4 points is complete at its last index.
            if let Some(&(end, line)) = ends.get(cell).filter(|&&(end, _)| end == k + 1) {
                if (3..=4).contains(&(end - start)) {
                    cells.face(end - start, q, line)?;
                }
            }
        }
        if previous.is_some_and(|o| o != size) {
            return Err(lex.error(format!("the last offset is not the connectivity size {size}")));
        }
        return Ok(cells);
    }
    cells.quads = try_vec(n.min(lex.max_tokens() / 5), "quads")?;
    for i in 0..n {
        let t = lex.next("a cell")?;
        let k = parse_usize(t, "the cell's point count")?;
        let mut q = [0u32; 4];
        for j in 0..k {
            let v = lex.usize("a point index")?;
            let index = cells.index(v, i, t.line, points);
            if let Some(c) = q.get_mut(j) {
                *c = index;
            }
        }
        cells.cell(k, q, t.line)?;
    }
    // The announced size is redundant with the per-cell counts, and some files get it wrong
    // (Mesquite's unstrquad.vtk says 80 for 150 values); Mesquite's reader ignores it too.
    Ok(cells)
}

/// The name of a VTK cell type.
fn type_name(ty: usize) -> &'static str {
    match ty {
        1 => "vertex",
        2 => "poly-vertex",
        3 => "line",
        4 => "poly-line",
        5 => "triangle",
        6 => "triangle strip",
        7 => "polygon",
        8 => "pixel",
        10 => "tetrahedron",
        11 => "voxel",
        12 => "hexahedron",
        13 => "wedge",
        14 => "pyramid",
        21 => "quadratic edge",
        22 => "quadratic triangle",
        23 => "quadratic quad",
        28 => "biquadratic quad",
        _ => "cell",
    }
}

/// Writes a legacy VTK text (POLYDATA if the mesh was read from POLYDATA).
pub(super) fn write(w: &mut dyn Write, data: &MeshData) -> std::io::Result<()> {
    writeln!(w, "# vtk DataFile Version 3.0")?;
    writeln!(w, "quad mesh written by quadopt")?;
    writeln!(w, "ASCII")?;
    let dataset = if data.vtk_polydata { "POLYDATA" } else { "UNSTRUCTURED_GRID" };
    writeln!(w, "DATASET {dataset}")?;
    writeln!(w, "POINTS {} double", data.points.len())?;
    write_items(w, &data.points, |b, _, p| {
        push_xyz(b, p);
        b.push(b'\n');
    })?;
    let m = data.quads.len();
    let size: usize = data.quads.iter().map(|q| 1 + corner_count(q)).sum();
    writeln!(w, "{} {m} {size}", if data.vtk_polydata { "POLYGONS" } else { "CELLS" })?;
    write_items(w, &data.quads, |b, _, q| {
        push_int(b, corner_count(q));
        push_face(b, q, 0);
        b.push(b'\n');
    })?;
    if !data.vtk_polydata {
        writeln!(w, "CELL_TYPES {m}")?;
        write_items(w, &data.quads, |b, _, q| {
            push_int(b, if is_triangle(q) { VTK_TRIANGLE } else { VTK_QUAD });
            b.push(b'\n');
        })?;
    }
    if let Some(quality) = &data.quality {
        writeln!(w, "CELL_DATA {m}")?;
        writeln!(w, "SCALARS scaled_jacobian double 1")?;
        writeln!(w, "LOOKUP_TABLE default")?;
        write_items(w, quality, |b, _, &v| {
            push_f64(b, v);
            b.push(b'\n');
        })?;
    }
    let flags = [("fixed", &data.fixed), ("corner", &data.corner)];
    if flags.iter().any(|(_, f)| f.is_some()) {
        writeln!(w, "POINT_DATA {}", data.points.len())?;
    }
    for (name, values) in flags {
        let Some(values) = values else { continue };
        writeln!(w, "SCALARS {name} int 1")?;
        writeln!(w, "LOOKUP_TABLE default")?;
        write_items(w, values, |b, _, &f| b.extend_from_slice(if f { b"1\n" } else { b"0\n" }))?;
    }
    Ok(())
}
