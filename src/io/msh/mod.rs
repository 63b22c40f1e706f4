//! Gmsh MSH: ASCII versions 2.x and 4.1 here, binary 4.1 in [`binary`], physical groups in
//! [`groups`] (see the module docs of [`crate::io`]).

mod binary;
mod groups;

use super::lex::{Lexer, Tok, clip, parse_f64, parse_usize, try_push, try_vec};
use super::{Encoding, IoError, MeshData, MshVersion, push_f64, push_face, push_int, push_xyz, write_items};
use crate::face::{NO_VERTEX, is_triangle};
use groups::Groups;
use std::collections::HashMap;
use std::io::Write;
use std::ops::Range;

/// Gmsh's element type number of a 3-node triangle.
const MSH_TRIANGLE: usize = 2;
/// Gmsh's element type number of a 4-node quad.
const MSH_QUAD: usize = 3;

/// The element type of a face.
fn element_type(face: &[u32; 4]) -> usize {
    if is_triangle(face) { MSH_TRIANGLE } else { MSH_QUAD }
}

/// The faces as MSH 4.1 element blocks: each run of faces of one type, in order, so the
/// elements keep the faces' order and numbers (one empty quad block for no faces).
fn blocks(faces: &[[u32; 4]]) -> Vec<(usize, Range<usize>)> {
    let mut out: Vec<(usize, Range<usize>)> = Vec::new();
    for (i, f) in faces.iter().enumerate() {
        match out.last_mut() {
            Some((ty, r)) if *ty == element_type(f) => r.end = i + 1,
            _ => out.push((element_type(f), i..i + 1)),
        }
    }
    if out.is_empty() {
        out.push((MSH_QUAD, 0..0));
    }
    out
}

/// Node tags to point indices. The tags 1, 2, 3, ... in order (what Gmsh and the writer
/// here produce) need no map; any other tag goes to a hash map.
#[derive(Default)]
struct NodeTags {
    /// Tags `1..=dense` are points `0..dense`.
    dense: usize,
    other: HashMap<u64, u32>,
}

impl NodeTags {
    fn get(&self, tag: u64) -> Option<u32> {
        if (1..=self.dense as u64).contains(&tag) {
            return Some((tag - 1) as u32);
        }
        self.other.get(&tag).copied()
    }

    /// Files `tag` as point `index`; false if the tag is already taken.
    fn insert(&mut self, tag: u64, index: u32) -> Result<bool, IoError> {
        if (1..=self.dense as u64).contains(&tag) {
            return Ok(false);
        }
        if self.other.is_empty() && tag == self.dense as u64 + 1 && index as usize == self.dense {
            self.dense += 1;
            return Ok(true);
        }
        self.other
            .try_reserve(1)
            .map_err(|_| crate::alloc::out_of_memory::<(u64, u32)>("node tags", self.other.len() + 1))?;
        Ok(self.other.insert(tag, index).is_none())
    }
}

/// Faces (quads and triangles) as read: resolved at once when the nodes are known (they come
/// first in every file Gmsh writes), else kept by node tag until the end.
#[derive(Default)]
struct Elements {
    quads: Vec<[u32; 4]>,
    /// (line, element index, node tags, node count) of the faces read before the nodes.
    raw: Vec<(usize, usize, [u64; 4], usize)>,
}

impl Elements {
    /// Files face `element` (3 or 4 node tags), resolving its nodes now if `tags` (the nodes
    /// read) is given.
    fn push(
        &mut self,
        tags: Option<&NodeTags>,
        line: usize,
        element: usize,
        nodes: &[u64],
    ) -> Result<(), IoError> {
        match tags {
            Some(tags) => try_push(&mut self.quads, resolve(tags, line, element, nodes)?, "quads"),
            None => {
                let mut q = [0u64; 4];
                let k = nodes.len().min(4);
                q[..k].copy_from_slice(&nodes[..k]);
                try_push(&mut self.raw, (line, element, q, k), "quads")
            }
        }
    }

    /// The faces, in the file's order, once the nodes are known.
    fn finish(self, tags: &NodeTags) -> Result<Vec<[u32; 4]>, IoError> {
        let Elements { mut quads, raw } = self;
        for (line, element, q, k) in raw {
            try_push(&mut quads, resolve(tags, line, element, &q[..k])?, "quads")?;
        }
        Ok(quads)
    }
}

/// The face of an element's 3 or 4 node tags (a triangle's fourth is [`NO_VERTEX`]).
fn resolve(tags: &NodeTags, line: usize, element: usize, q: &[u64]) -> Result<[u32; 4], IoError> {
    let mut out = [NO_VERTEX; 4];
    for c in 0..q.len().min(4) {
        out[c] = tags.get(q[c]).ok_or_else(|| IoError::Parse {
            line,
            message: format!(
                "element {element} refers to node {}, which does not exist (element numbers are 0-based, node \
                 numbers are the file's tags)",
                q[c]
            ),
        })?;
    }
    Ok(out)
}

/// Reads an MSH file's bytes: binary 4.1 or text.
pub(super) fn read_bytes(bytes: &[u8]) -> Result<MeshData, IoError> {
    if binary::is_binary(bytes) {
        return binary::read(bytes);
    }
    let text = String::from_utf8_lossy(bytes);
    read(text.strip_prefix('\u{feff}').unwrap_or(&text))
}

/// Reads an MSH text.
pub(super) fn read(text: &str) -> Result<MeshData, IoError> {
    let mut lex = Lexer::new(text, 1, None);
    let t = lex.next("$MeshFormat")?;
    if t.s != "$MeshFormat" {
        return Err(err(t, "not a Gmsh MSH file (no $MeshFormat)".into()));
    }
    let v = lex.next("the format version")?;
    let version = match v.s {
        "2" | "2.0" | "2.1" | "2.2" => MshVersion::V2_2,
        "4.1" => MshVersion::V4_1,
        _ => return Err(IoError::Unsupported(format!("MSH version {} (2.2 and 4.1 are read)", clip(v.s)))),
    };
    let file_type = lex.next("the file type")?;
    if file_type.s == "1" {
        // Binary data that came as text (`read_mesh_str`): it is read as bytes.
        return binary::read(text.as_bytes());
    }
    if file_type.s != "0" {
        return Err(err(file_type, format!("file type '{}' (0 for ASCII, 1 for binary)", clip(file_type.s))));
    }
    lex.next("the data size")?;
    expect(&mut lex, "$EndMeshFormat")?;

    let mut points: Vec<[f64; 3]> = Vec::new();
    let mut tags = NodeTags::default();
    let mut elements: Option<Elements> = None;
    let (mut have_nodes, mut have_elements) = (false, false);
    let mut fixed = None;
    let mut groups = Groups::default();
    while let Some(t) = lex.peek() {
        lex.next("")?;
        match t.s {
            "$Nodes" if !have_nodes => {
                have_nodes = true;
                match version {
                    MshVersion::V2_2 => read_nodes_v2(&mut lex, &mut points, &mut tags)?,
                    MshVersion::V4_1 => read_nodes_v4(&mut lex, &mut points, &mut tags)?,
                }
                expect(&mut lex, "$EndNodes")?;
            }
            "$Elements" if !have_elements => {
                have_elements = true;
                let mut e = Elements::default();
                let known = have_nodes.then_some(&tags);
                match version {
                    MshVersion::V2_2 => read_elements_v2(&mut lex, known, &mut e, &mut groups)?,
                    MshVersion::V4_1 => read_elements_v4(&mut lex, known, &mut e, &mut groups)?,
                }
                expect(&mut lex, "$EndElements")?;
                elements = Some(e);
            }
            "$PhysicalNames" => {
                let n = lex.usize("the physical name count")?;
                for _ in 0..n {
                    let line = lex.rest_of_line("a physical name")?;
                    let words: Vec<&str> = line.iter().map(|t| t.s).collect();
                    let (dim, tag, name) = physical_name(&words.join(" "))
                        .ok_or_else(|| err(line[0], "a physical name is: dimension tag \"name\"".into()))?;
                    groups.name(dim, tag, name);
                }
                expect(&mut lex, "$EndPhysicalNames")?;
            }
            "$Entities" if version == MshVersion::V4_1 => {
                read_entities(&mut lex, &mut groups)?;
                expect(&mut lex, "$EndEntities")?;
            }
            "$NodeData" if have_nodes => {
                if let Some(flags) = read_node_flags(&mut lex, &tags, points.len(), "fixed")? {
                    fixed = Some(flags);
                }
            }
            s if s.starts_with('$') && !s.starts_with("$End") => {
                let end = format!("$End{}", &s[1..]);
                lex.skip_past(&end)?;
            }
            _ => return Err(err(t, format!("unexpected '{}' (expected a $Section)", clip(t.s)))),
        }
    }
    if !have_nodes {
        return Err(lex.error("the file has no $Nodes section"));
    }
    let Some(elements) = elements else {
        return Err(lex.error("the file has no $Elements section"));
    };
    let quads = elements.finish(&tags)?;
    let physical_groups = groups.finish(&tags)?;
    Ok(MeshData {
        points,
        quads,
        fixed,
        msh_version: Some(version),
        vtk_polydata: false,
        physical_groups,
        ..MeshData::default()
    })
}

/// One `$PhysicalNames` line: `dim tag "name"` (the name may hold spaces; its quotes are
/// dropped, and a name without them is taken as it stands).
fn physical_name(line: &str) -> Option<(u8, i32, String)> {
    let mut words = line.trim().splitn(3, |c: char| c.is_ascii_whitespace());
    let dim = words.next()?.parse().ok()?;
    let tag = words.next()?.parse().ok()?;
    let name = words.next().unwrap_or("").trim();
    let name = name.strip_prefix('"').and_then(|n| n.strip_suffix('"')).unwrap_or(name);
    Some((dim, tag, name.to_string()))
}

/// MSH 4.1 ASCII `$Entities`: the physical tags of each point and curve (one entity a line).
fn read_entities(lex: &mut Lexer<'_>, groups: &mut Groups) -> Result<(), IoError> {
    let counts = [
        lex.usize("the point entity count")?,
        lex.usize("the curve entity count")?,
        lex.usize("the surface entity count")?,
        lex.usize("the volume entity count")?,
    ];
    for (dim, &count) in counts.iter().enumerate() {
        // A point has x y z; the others a bounding box.
        let coordinates = if dim == 0 { 3 } else { 6 };
        for _ in 0..count {
            let line = lex.rest_of_line("an entity")?;
            let at = |i: usize| {
                line.get(i).copied().ok_or_else(|| err(line[0], "the entity line ends early".into()))
            };
            let tag = parse_i32(at(0)?)?;
            let n = parse_usize(at(1 + coordinates)?, "the physical tag count")?;
            let mut physicals = Vec::new();
            for i in 0..n {
                try_push(&mut physicals, parse_i32(at(2 + coordinates + i)?)?, "physical tags")?;
            }
            groups.entity(dim as u8, tag, physicals);
        }
    }
    Ok(())
}

fn parse_i32(t: Tok<'_>) -> Result<i32, IoError> {
    t.s.parse().map_err(|_| err(t, format!("expected a tag (an integer), found '{}'", clip(t.s))))
}

fn err(t: Tok<'_>, message: String) -> IoError {
    IoError::Parse { line: t.line, message }
}

fn expect(lex: &mut Lexer<'_>, word: &str) -> Result<(), IoError> {
    let t = lex.next(word)?;
    if t.s != word {
        return Err(err(t, format!("expected {word}, found '{}'", clip(t.s))));
    }
    Ok(())
}

fn tag(t: Tok<'_>, what: &str) -> Result<u64, IoError> {
    t.s.parse::<u64>()
        .map_err(|_| err(t, format!("expected {what} (a positive integer), found '{}'", clip(t.s))))
}

fn add_node(
    t: Tok<'_>,
    node: u64,
    p: [f64; 3],
    points: &mut Vec<[f64; 3]>,
    tags: &mut NodeTags,
) -> Result<(), IoError> {
    if points.len() >= u32::MAX as usize {
        return Err(err(t, "too many nodes".into()));
    }
    if !tags.insert(node, points.len() as u32)? {
        return Err(err(t, format!("node {node} is defined twice")));
    }
    try_push(points, p, "points")
}

/// Room for `n` more points, or an out-of-memory error.
fn reserve(points: &mut Vec<[f64; 3]>, n: usize) -> Result<(), IoError> {
    points.try_reserve_exact(n).map_err(|_| crate::alloc::out_of_memory::<[f64; 3]>("points", n).into())
}

/// A coordinate triple from a line's tokens.
fn xyz(line: &[Tok<'_>]) -> Result<[f64; 3], IoError> {
    if line.len() < 3 {
        return Err(err(line[0], "a node needs x, y and z".into()));
    }
    Ok([
        parse_f64(line[0], "a coordinate")?,
        parse_f64(line[1], "a coordinate")?,
        parse_f64(line[2], "a coordinate")?,
    ])
}

fn read_nodes_v2(
    lex: &mut Lexer<'_>,
    points: &mut Vec<[f64; 3]>,
    tags: &mut NodeTags,
) -> Result<(), IoError> {
    let n = lex.usize("the node count")?;
    reserve(points, n.min(lex.max_tokens() / 4))?;
    for _ in 0..n {
        let line = lex.rest_of_line("a node")?;
        if line.len() < 4 {
            return Err(err(line[0], "a node needs a tag, x, y and z".into()));
        }
        let node = tag(line[0], "a node tag")?;
        let p = xyz(&line[1..])?;
        add_node(line[0], node, p, points, tags)?;
    }
    Ok(())
}

fn read_nodes_v4(
    lex: &mut Lexer<'_>,
    points: &mut Vec<[f64; 3]>,
    tags: &mut NodeTags,
) -> Result<(), IoError> {
    let blocks = lex.usize("the entity block count")?;
    let total = lex.usize("the node count")?;
    lex.usize("the minimum node tag")?;
    lex.usize("the maximum node tag")?;
    reserve(points, total.min(lex.max_tokens() / 4))?;
    for _ in 0..blocks {
        lex.usize("the entity dimension")?;
        lex.next("the entity tag")?;
        lex.usize("the parametric flag")?;
        let n = lex.usize("the block's node count")?;
        let mut block_tags = try_vec(n.min(lex.max_tokens()), "node tags")?;
        for _ in 0..n {
            let t = lex.next("a node tag")?;
            try_push(&mut block_tags, (tag(t, "a node tag")?, t), "node tags")?;
        }
        for &(node, t) in &block_tags {
            let line = lex.rest_of_line("node coordinates")?;
            add_node(t, node, xyz(line)?, points, tags)?;
        }
    }
    if points.len() != total {
        return Err(lex.error(format!("{} nodes were read, but {total} were announced", points.len())));
    }
    Ok(())
}

/// Files an element: triangles and quads are kept, points and lines skipped, anything else is
/// an error.
fn element(
    line: usize,
    index: usize,
    ty: usize,
    nodes: &[Tok<'_>],
    tags: Option<&NodeTags>,
    elements: &mut Elements,
) -> Result<(), IoError> {
    match ty {
        MSH_TRIANGLE | MSH_QUAD => {
            let (k, kind) = if ty == MSH_QUAD { (4, "quad") } else { (3, "triangle") };
            if nodes.len() != k {
                return Err(IoError::Parse {
                    line,
                    message: format!(
                        "{kind} element {index} has {} nodes (element numbers are 0-based)",
                        nodes.len()
                    ),
                });
            }
            let mut q = [0u64; 4];
            for c in 0..k {
                q[c] = tag(nodes[c], "a node tag")?;
            }
            elements.push(tags, line, index, &q[..k])
        }
        // Point, and lines of order 1 to 5: corners and boundary curves.
        15 | 1 | 8 | 26 | 27 | 28 => Ok(()),
        _ => {
            let kind = match ty {
                9 | 20..=25 => "higher-order triangle",
                10 | 16 => "higher-order quad",
                4 | 11 | 29..=31 => "tetrahedron",
                5 | 12 | 17 | 92 | 93 => "hexahedron",
                6 | 13 | 18 => "prism",
                7 | 14 | 19 => "pyramid",
                _ => "element",
            };
            Err(IoError::NonQuad { line, cell: index, kind: format!("{kind} (Gmsh element type {ty})") })
        }
    }
}

fn read_elements_v2(
    lex: &mut Lexer<'_>,
    tags: Option<&NodeTags>,
    elements: &mut Elements,
    groups: &mut Groups,
) -> Result<(), IoError> {
    let n = lex.usize("the element count")?;
    for index in 0..n {
        let line = lex.rest_of_line("an element")?;
        let l = line[0].line;
        if line.len() < 3 {
            return Err(IoError::Parse {
                line: l,
                message: "an element needs a tag, a type and a tag count".into(),
            });
        }
        let ty = parse_usize(line[1], "the element type")?;
        let ntags = parse_usize(line[2], "the tag count")?;
        let nodes = line.get(3usize.saturating_add(ntags)..).ok_or_else(|| IoError::Parse {
            line: l,
            message: format!("the element has fewer than {ntags} tags"),
        })?;
        // The first tag is the physical group; 0 (or no tags) is none, whose nodes are not read.
        if let (Some(dim), true) = (groups::low_dimension(ty), ntags > 0) {
            let physical = parse_i32(line[3])?.abs();
            if physical != 0 {
                groups.element_of_physical(dim, physical, &node_tags(nodes)?)?;
            }
        }
        element(l, index, ty, nodes, tags, elements)?;
    }
    Ok(())
}

fn read_elements_v4(
    lex: &mut Lexer<'_>,
    tags: Option<&NodeTags>,
    elements: &mut Elements,
    groups: &mut Groups,
) -> Result<(), IoError> {
    let blocks = lex.usize("the entity block count")?;
    let total = lex.usize("the element count")?;
    lex.usize("the minimum element tag")?;
    lex.usize("the maximum element tag")?;
    let mut index = 0;
    for _ in 0..blocks {
        lex.usize("the entity dimension")?;
        let t = lex.next("the entity tag")?;
        let entity = parse_i32(t)?;
        let ty = lex.usize("the element type")?;
        let low = groups::low_dimension(ty);
        let n = lex.usize("the block's element count")?;
        for _ in 0..n {
            let line = lex.rest_of_line("an element")?;
            if let Some(dim) = low {
                groups.element_of_entity(dim, entity, &node_tags(&line[1..])?)?;
            }
            element(line[0].line, index, ty, &line[1..], tags, elements)?;
            index += 1;
        }
    }
    if index != total {
        return Err(lex.error(format!("{index} elements were read, but {total} were announced")));
    }
    Ok(())
}

/// The node tags of an element's line (a point or line element has at most 6).
fn node_tags(nodes: &[Tok<'_>]) -> Result<Vec<u64>, IoError> {
    nodes.iter().take(6).map(|&t| tag(t, "a node tag")).collect()
}

/// Writes an MSH text in the version the mesh was read in (4.1 by default).
pub(super) fn write(w: &mut dyn Write, data: &MeshData) -> std::io::Result<()> {
    if data.encoding != Encoding::Ascii {
        return binary::write(w, data);
    }
    let (n, m) = (data.points.len(), data.quads.len());
    match data.msh_version.unwrap_or_default() {
        MshVersion::V2_2 => {
            writeln!(w, "$MeshFormat\n2.2 0 8\n$EndMeshFormat")?;
            writeln!(w, "$Nodes\n{n}")?;
            write_items(w, &data.points, |b, i, p| {
                push_int(b, i + 1);
                b.push(b' ');
                push_xyz(b, p);
                b.push(b'\n');
            })?;
            writeln!(w, "$EndNodes\n$Elements\n{m}")?;
            write_items(w, &data.quads, |b, i, q| {
                push_int(b, i + 1);
                b.push(b' ');
                push_int(b, element_type(q));
                b.extend_from_slice(b" 2 0 1");
                push_face(b, q, 1);
                b.push(b'\n');
            })?;
            writeln!(w, "$EndElements")?;
        }
        MshVersion::V4_1 => {
            writeln!(w, "$MeshFormat\n4.1 0 8\n$EndMeshFormat")?;
            // One surface entity holding every node and every quad.
            writeln!(w, "$Nodes\n1 {n} {} {n}\n2 1 0 {n}", n.min(1))?;
            write_items(w, &data.points, |b, i, _| {
                push_int(b, i + 1);
                b.push(b'\n');
            })?;
            write_items(w, &data.points, |b, _, p| {
                push_xyz(b, p);
                b.push(b'\n');
            })?;
            let blocks = blocks(&data.quads);
            writeln!(w, "$EndNodes\n$Elements\n{} {m} {} {m}", blocks.len(), m.min(1))?;
            for (ty, range) in blocks {
                writeln!(w, "2 1 {ty} {}", range.len())?;
                let start = range.start;
                write_items(w, &data.quads[range], |b, k, q| {
                    push_int(b, start + k + 1);
                    push_face(b, q, 1);
                    b.push(b'\n');
                })?;
            }
            writeln!(w, "$EndElements")?;
        }
    }
    write_views(w, data)
}

/// A `$NodeData` view after its keyword: the flags (nonzero = set) if the view is named
/// `name` and has one component, else `None`; either way up to and including `$EndNodeData`.
/// Nodes the view does not list are not set.
fn read_node_flags(
    lex: &mut Lexer<'_>,
    tags: &NodeTags,
    nodes: usize,
    name: &str,
) -> Result<Option<Vec<bool>>, IoError> {
    let strings = lex.usize("the view's string tag count")?;
    let mut view_name = String::new();
    for i in 0..strings {
        let words: Vec<&str> = lex.rest_of_line("a string tag")?.iter().map(|t| t.s).collect();
        if i == 0 {
            view_name = words.join(" ");
        }
    }
    let reals = lex.usize("the view's real tag count")?;
    lex.skip(reals, "real tags")?;
    let integers = lex.usize("the view's integer tag count")?;
    let mut ints = Vec::new();
    for _ in 0..integers {
        try_push(&mut ints, lex.usize("an integer tag")?, "integer tags")?;
    }
    let (components, count) = (ints.get(1).copied().unwrap_or(1), ints.get(2).copied().unwrap_or(0));
    if view_name != format!("\"{name}\"") || components != 1 {
        lex.skip_past("$EndNodeData")?;
        return Ok(None);
    }
    let mut flags = try_vec(nodes, "flags")?;
    flags.resize(nodes, false);
    for _ in 0..count {
        let t = lex.next("a node tag")?;
        let tag = parse_usize(t, "a node tag")? as u64;
        let index = tags
            .get(tag)
            .ok_or_else(|| err(t, format!("view \"{name}\" refers to node {tag}, which does not exist")))?;
        flags[index as usize] = lex.f64("a view value")? != 0.0;
    }
    expect(lex, "$EndNodeData")?;
    Ok(Some(flags))
}

/// The quality and the flags as post-processing views, which gmsh shows by name: an
/// `$ElementData` view `scaled_jacobian` (element tags are the quads' 1-based indices, as
/// both writers number them) and `$NodeData` views `fixed` and `corner` (0 or 1).
fn write_views(w: &mut dyn Write, data: &MeshData) -> std::io::Result<()> {
    let header = |w: &mut dyn Write, section: &str, name: &str, count: usize| {
        // One string tag (the name), one real tag (the time), three integer tags (time step,
        // components, entities).
        writeln!(w, "${section}\n1\n\"{name}\"\n1\n0.0\n3\n0\n1\n{count}")
    };
    if let Some(quality) = &data.quality {
        header(w, "ElementData", "scaled_jacobian", quality.len())?;
        write_items(w, quality, |b, i, &v| {
            push_int(b, i + 1);
            b.push(b' ');
            push_f64(b, v);
            b.push(b'\n');
        })?;
        writeln!(w, "$EndElementData")?;
    }
    for (name, flags) in [("fixed", &data.fixed), ("corner", &data.corner)] {
        let Some(flags) = flags else { continue };
        header(w, "NodeData", name, flags.len())?;
        write_items(w, flags, |b, i, &f| {
            push_int(b, i + 1);
            b.extend_from_slice(if f { b" 1\n" } else { b" 0\n" });
        })?;
        writeln!(w, "$EndNodeData")?;
    }
    Ok(())
}
