//! Legacy VTK, ASCII: `UNSTRUCTURED_GRID` with quad cells or `POLYDATA` with 4-vertex
//! polygons, and a point-data array `fixed` (see the module docs of [`crate::io`]).

use super::lex::{Lexer, Tok, clip, parse_usize};
use super::{IoError, MeshData, Num};
use std::io::Write;

/// VTK's cell type number of a quad.
const VTK_QUAD: usize = 9;

/// Cells as read: per cell its vertex indices (flat) and the line it starts on.
#[derive(Default)]
struct Cells {
    offsets: Vec<usize>,
    indices: Vec<usize>,
    lines: Vec<usize>,
}

impl Cells {
    fn len(&self) -> usize {
        self.lines.len()
    }
    fn cell(&self, i: usize) -> &[usize] {
        &self.indices[self.offsets[i]..self.offsets[i + 1]]
    }
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
    let mut lines = text.lines();
    let header = lines.next().unwrap_or("");
    if !header.trim_start().to_ascii_lowercase().starts_with("# vtk datafile") {
        return Err(IoError::Parse {
            line: 1,
            message: "not a legacy VTK file (no '# vtk DataFile' header)".into(),
        });
    }
    if lines.next().is_none() {
        return Err(IoError::Parse {
            line: 2,
            message: "unexpected end of file (expected the title line)".into(),
        });
    }
    let mut lex = Lexer::new(lines, 3, None);
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
    let mut types: Option<Vec<(usize, usize)>> = None;
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
                let mut p = Vec::with_capacity(n.min(lex.remaining() / 3));
                for _ in 0..n {
                    p.push([lex.f64("a coordinate")?, lex.f64("a coordinate")?, lex.f64("a coordinate")?]);
                }
                points = Some(p);
            }
            "CELLS" if !polydata => cells = Some(read_cells(&mut lex)?),
            "POLYGONS" if polydata => cells = Some(read_cells(&mut lex)?),
            "VERTICES" | "LINES" | "TRIANGLE_STRIPS" if polydata => {
                let c = read_cells(&mut lex)?;
                if c.len() > 0 {
                    let kind = match k.as_str() {
                        "VERTICES" => "vertex cell",
                        "LINES" => "line",
                        _ => "triangle strip",
                    };
                    return Err(IoError::NonQuad { line: c.lines[0], cell: 0, kind: kind.into() });
                }
            }
            "CELL_TYPES" if !polydata => {
                let n = lex.usize("the cell type count")?;
                let mut t = Vec::with_capacity(n.min(lex.remaining()));
                for _ in 0..n {
                    let tok = lex.next("a cell type")?;
                    t.push((parse_usize(tok, "a cell type")?, tok.line));
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
    let mut quads = Vec::with_capacity(cells.len());
    if !polydata {
        let types = types.ok_or_else(|| lex.error("the file has no CELL_TYPES section"))?;
        if types.len() != cells.len() {
            return Err(IoError::Parse {
                line: types.first().map_or(lex.line(), |t| t.1),
                message: format!("{} cell types were given for {} cells", types.len(), cells.len()),
            });
        }
        for (i, &(ty, line)) in types.iter().enumerate() {
            if ty != VTK_QUAD {
                return Err(IoError::NonQuad {
                    line,
                    cell: i,
                    kind: format!("{} (VTK type {ty})", type_name(ty)),
                });
            }
        }
    }
    for i in 0..cells.len() {
        let c = cells.cell(i);
        let line = cells.lines[i];
        if c.len() != 4 {
            if polydata {
                return Err(IoError::NonQuad {
                    line,
                    cell: i,
                    kind: format!("polygon with {} vertices", c.len()),
                });
            }
            return Err(IoError::Parse { line, message: format!("quad cell {i} has {} vertices", c.len()) });
        }
        let mut q = [0u32; 4];
        for (j, &v) in c.iter().enumerate() {
            if v >= n {
                return Err(IoError::Parse {
                    line,
                    message: format!("cell {i} refers to point {v}, but there are only {n} points"),
                });
            }
            q[j] = v as u32;
        }
        quads.push(q);
    }
    if let Some(len) = fixed.as_ref().map(Vec::len).filter(|&len| len != n) {
        return Err(lex.error(format!("the fixed array has {len} values for {n} points")));
    }
    Ok(MeshData { points, quads, fixed, msh_version: None, vtk_polydata: polydata })
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
    let mut flags = Vec::with_capacity(count.min(lex.remaining()));
    for _ in 0..count {
        let mut any = false;
        for _ in 0..comps {
            let v = lex.f64("a fixed flag")?;
            any |= v != 0.0;
        }
        flags.push(any);
    }
    Ok(flags)
}

/// Reads a cell list: classic `n size` followed by `count i0 i1 ...` per cell, or VTK 5.1's
/// `n_offsets n_conn` followed by `OFFSETS type ...` and `CONNECTIVITY type ...`.
fn read_cells(lex: &mut Lexer<'_>) -> Result<Cells, IoError> {
    let n = lex.usize("the cell count")?;
    let size = lex.usize("the cell list size")?;
    let mut cells = Cells::default();
    if lex.eat("OFFSETS") {
        data_type(lex)?;
        let mut offsets = Vec::with_capacity(n.min(lex.remaining()));
        let mut lines = Vec::with_capacity(n.min(lex.remaining()));
        for i in 0..n {
            let t = lex.next("an offset")?;
            let o = parse_usize(t, "an offset")?;
            if o > size || offsets.last().is_some_and(|&p| o < p) || (i == 0 && o != 0) {
                return Err(parse_err(t, format!("offset {o} is out of order or beyond {size}")));
            }
            offsets.push(o);
            lines.push(t.line);
        }
        if !lex.eat("CONNECTIVITY") {
            return Err(lex.error("expected CONNECTIVITY"));
        }
        data_type(lex)?;
        let mut indices = Vec::with_capacity(size.min(lex.remaining()));
        for _ in 0..size {
            indices.push(lex.usize("a point index")?);
        }
        if offsets.last().is_some_and(|&o| o != size) {
            return Err(lex.error(format!("the last offset is not the connectivity size {size}")));
        }
        if offsets.is_empty() {
            offsets.push(0);
        }
        lines.pop();
        cells.offsets = offsets;
        cells.indices = indices;
        cells.lines = lines;
        return Ok(cells);
    }
    let available = lex.remaining();
    cells.offsets = Vec::with_capacity(n.min(available) + 1);
    cells.offsets.push(0);
    cells.indices = Vec::with_capacity(size.min(available));
    cells.lines = Vec::with_capacity(n.min(available));
    for _ in 0..n {
        let t = lex.next("a cell")?;
        let k = parse_usize(t, "the cell's point count")?;
        for _ in 0..k {
            cells.indices.push(lex.usize("a point index")?);
        }
        cells.offsets.push(cells.indices.len());
        cells.lines.push(t.line);
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
    for p in &data.points {
        writeln!(w, "{} {} {}", Num(p[0]), Num(p[1]), Num(p[2]))?;
    }
    let m = data.quads.len();
    writeln!(w, "{} {m} {}", if data.vtk_polydata { "POLYGONS" } else { "CELLS" }, 5 * m)?;
    for q in &data.quads {
        writeln!(w, "4 {} {} {} {}", q[0], q[1], q[2], q[3])?;
    }
    if !data.vtk_polydata {
        writeln!(w, "CELL_TYPES {m}")?;
        for _ in 0..m {
            writeln!(w, "{VTK_QUAD}")?;
        }
    }
    if let Some(fixed) = &data.fixed {
        writeln!(w, "POINT_DATA {}", data.points.len())?;
        writeln!(w, "SCALARS fixed int 1")?;
        writeln!(w, "LOOKUP_TABLE default")?;
        for &f in fixed {
            writeln!(w, "{}", u8::from(f))?;
        }
    }
    Ok(())
}
