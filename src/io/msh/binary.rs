//! Gmsh MSH 4.1 binary (`Mesh.Binary=1`), read and written.
//!
//! The layout is the ASCII one with the numbers as raw bytes: `int` is 4 bytes, `size_t` the
//! file's data size (8; nothing else is read), `double` 8. The header's binary `int` 1 gives
//! the byte order; a file written on a big-endian machine is read by swapping every number,
//! and a header that is 1 in neither order is an error. Section keywords, `$PhysicalNames`
//! and the string, real and integer tags of post-processing views are text, as gmsh writes
//! them. Views (`$NodeData` ...) store each entry as an `int` tag and `double` values.
//!
//! Every count read is checked against the bytes left before anything is allocated, so
//! arbitrary bytes give an error, never a panic or a huge allocation.

use super::groups::{Groups, low_dimension};
use super::{Elements, MSH_QUAD, MSH_TRIANGLE, NodeTags, blocks, physical_name};
use crate::face::vertices;
use crate::io::lex::{clip, try_push, try_vec};
use crate::io::{Encoding, IoError, MeshData, MshVersion};
use std::io::Write;

fn bad(message: impl Into<String>) -> IoError {
    IoError::Malformed(format!("binary MSH: {}", message.into()))
}

/// Whether `bytes` start like a binary MSH file (`$MeshFormat`, then a version and file
/// type 1).
pub(super) fn is_binary(bytes: &[u8]) -> bool {
    let bytes = bytes.strip_prefix(b"\xef\xbb\xbf").unwrap_or(bytes);
    let mut c = Cursor { bytes, at: 0, swap: false };
    if c.line().map(str::trim) != Some("$MeshFormat") {
        return false;
    }
    c.line().is_some_and(|l| l.split_ascii_whitespace().nth(1) == Some("1"))
}

/// A position in the file and its byte order.
struct Cursor<'a> {
    bytes: &'a [u8],
    at: usize,
    swap: bool,
}

impl<'a> Cursor<'a> {
    /// The next line of text (without its end of line, which is consumed), skipping the
    /// newline that ends a binary block; `None` at the end. Invalid UTF-8 reads as an empty
    /// line.
    fn line(&mut self) -> Option<&'a str> {
        while self.bytes.get(self.at).is_some_and(|&b| b == b'\n' || b == b'\r') {
            self.at += 1;
        }
        if self.at >= self.bytes.len() {
            return None;
        }
        let rest = &self.bytes[self.at..];
        let end = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
        self.at += (end + 1).min(rest.len());
        Some(std::str::from_utf8(&rest[..end]).map_or("", |s| s.trim_end_matches('\r')))
    }

    fn expect_line(&mut self, word: &str) -> Result<(), IoError> {
        match self.line() {
            Some(l) if l.trim() == word => Ok(()),
            Some(l) => Err(bad(format!("expected {word}, found '{}' at byte {}", clip(l), self.at))),
            None => Err(bad(format!("the file ends before {word} (truncated file?)"))),
        }
    }

    /// A line holding one count.
    fn count_line(&mut self, what: &str) -> Result<usize, IoError> {
        let l = self.line().ok_or_else(|| bad(format!("the file ends before {what} (truncated file?)")))?;
        l.trim().parse().map_err(|_| bad(format!("expected {what}, found '{}'", clip(l))))
    }

    fn take<const N: usize>(&mut self, what: &str) -> Result<[u8; N], IoError> {
        let b = self
            .bytes
            .get(self.at..self.at + N)
            .ok_or_else(|| bad(format!("the data ends inside {what} (truncated file?)")))?;
        self.at += N;
        let mut a: [u8; N] = b.try_into().map_err(|_| bad("internal: slice length"))?;
        if self.swap {
            a.reverse();
        }
        Ok(a)
    }

    fn int(&mut self, what: &str) -> Result<i32, IoError> {
        Ok(i32::from_le_bytes(self.take(what)?))
    }

    fn size(&mut self, what: &str) -> Result<u64, IoError> {
        Ok(u64::from_le_bytes(self.take(what)?))
    }

    fn real(&mut self, what: &str) -> Result<f64, IoError> {
        Ok(f64::from_le_bytes(self.take(what)?))
    }

    /// A `size_t` count of items of `item_bytes` each, checked against the bytes left.
    fn count(&mut self, item_bytes: usize, what: &str) -> Result<usize, IoError> {
        let n = self.size(what)?;
        let left = (self.bytes.len() - self.at) as u64;
        if n.saturating_mul(item_bytes.max(1) as u64) > left {
            return Err(bad(format!("{what} {n} is more than the file holds (truncated file?)")));
        }
        Ok(n as usize)
    }

    /// Skips `n` bytes.
    fn skip(&mut self, n: usize, what: &str) -> Result<(), IoError> {
        if n > self.bytes.len() - self.at {
            return Err(bad(format!("the data ends inside {what} (truncated file?)")));
        }
        self.at += n;
        Ok(())
    }
}

/// Reads a binary MSH 4.1 file.
pub(super) fn read(bytes: &[u8]) -> Result<MeshData, IoError> {
    let bytes = bytes.strip_prefix(b"\xef\xbb\xbf").unwrap_or(bytes);
    let mut c = Cursor { bytes, at: 0, swap: false };
    c.expect_line("$MeshFormat")?;
    let header = c.line().unwrap_or("");
    let words: Vec<&str> = header.split_ascii_whitespace().collect();
    match words.as_slice() {
        ["4.1", "1", "8"] => {}
        ["4.1", "1", size] => {
            return Err(IoError::Unsupported(format!(
                "binary MSH with data size {} (8 is read)",
                clip(size)
            )));
        }
        [v, "1", ..] => {
            return Err(IoError::Unsupported(format!(
                "binary MSH version {} (4.1 binary, and 2.2 and 4.1 ASCII, are read)",
                clip(v)
            )));
        }
        _ => return Err(bad(format!("bad $MeshFormat line '{}'", clip(header)))),
    }
    // The byte-order check: an int 1, right after the header line's newline.
    let one: [u8; 4] = c.take("the byte-order check")?;
    c.swap = match (u32::from_le_bytes(one), u32::from_be_bytes(one)) {
        (1, _) => false,
        (_, 1) => true,
        _ => return Err(bad(format!("the byte-order check reads {one:02x?}, not 1 in either byte order"))),
    };
    c.expect_line("$EndMeshFormat")?;

    let mut points: Vec<[f64; 3]> = Vec::new();
    let mut tags = NodeTags::default();
    let mut elements: Option<Elements> = None;
    let mut have_nodes = false;
    let mut fixed = None;
    let mut groups = Groups::default();
    while let Some(line) = c.line() {
        let section = line.trim();
        match section {
            "$PhysicalNames" => {
                let n = c.count_line("the physical name count")?;
                for _ in 0..n {
                    let l = c.line().unwrap_or("");
                    let (dim, tag, name) = physical_name(l)
                        .ok_or_else(|| bad(format!("bad physical name line '{}'", clip(l))))?;
                    groups.name(dim, tag, name);
                }
                c.expect_line("$EndPhysicalNames")?;
            }
            "$Entities" => {
                read_entities(&mut c, &mut groups)?;
                c.expect_line("$EndEntities")?;
            }
            "$Nodes" if !have_nodes => {
                have_nodes = true;
                read_nodes(&mut c, &mut points, &mut tags)?;
                c.expect_line("$EndNodes")?;
            }
            "$Elements" if elements.is_none() => {
                let mut e = Elements::default();
                read_elements(&mut c, have_nodes.then_some(&tags), &mut e, &mut groups)?;
                c.expect_line("$EndElements")?;
                elements = Some(e);
            }
            "$NodeData" | "$ElementData" => {
                let flags = read_view(&mut c, section, &tags, points.len())?;
                if section == "$NodeData" && flags.is_some() {
                    fixed = flags;
                }
            }
            s if s.starts_with('$') && !s.starts_with("$End") => skip_section(&mut c, s)?,
            s => return Err(bad(format!("unexpected '{}' at byte {} (expected a $Section)", clip(s), c.at))),
        }
    }
    if !have_nodes {
        return Err(bad("the file has no $Nodes section"));
    }
    let Some(elements) = elements else {
        return Err(bad("the file has no $Elements section"));
    };
    let quads = elements.finish(&tags)?;
    let physical_groups = groups.finish(&tags)?;
    Ok(MeshData {
        points,
        quads,
        fixed,
        msh_version: Some(MshVersion::V4_1),
        encoding: Encoding::Binary,
        physical_groups,
        ..MeshData::default()
    })
}

/// An unknown section: skipped up to its end keyword at the start of a line.
fn skip_section(c: &mut Cursor<'_>, section: &str) -> Result<(), IoError> {
    let end = format!("\n$End{}", &section[1..]);
    let rest = &c.bytes[c.at..];
    let at = rest
        .windows(end.len())
        .position(|w| w == end.as_bytes())
        .ok_or_else(|| bad(format!("{section} has no {} (truncated file?)", &end[1..])))?;
    c.at += at + end.len();
    Ok(())
}

fn read_entities(c: &mut Cursor<'_>, groups: &mut Groups) -> Result<(), IoError> {
    let mut counts = [0usize; 4];
    for n in &mut counts {
        *n = c.count(4, "the entity count")?;
    }
    for (dim, &count) in counts.iter().enumerate() {
        let coordinates = if dim == 0 { 3 } else { 6 };
        for _ in 0..count {
            let tag = c.int("an entity tag")?;
            c.skip(8 * coordinates, "an entity's coordinates")?;
            let n = c.count(4, "the physical tag count")?;
            let mut physicals = try_vec(n, "physical tags")?;
            for _ in 0..n {
                physicals.push(c.int("a physical tag")?);
            }
            if dim > 0 {
                let bounding = c.count(4, "the bounding entity count")?;
                c.skip(4 * bounding, "bounding entities")?;
            }
            groups.entity(dim as u8, tag, physicals);
        }
    }
    Ok(())
}

fn read_nodes(c: &mut Cursor<'_>, points: &mut Vec<[f64; 3]>, tags: &mut NodeTags) -> Result<(), IoError> {
    let blocks = c.count(16, "the entity block count")?;
    let total = c.count(32, "the node count")?;
    c.size("the minimum node tag")?;
    c.size("the maximum node tag")?;
    points.try_reserve_exact(total).map_err(|_| crate::alloc::out_of_memory::<[f64; 3]>("points", total))?;
    for _ in 0..blocks {
        let dim = c.int("the entity dimension")?;
        c.int("the entity tag")?;
        let parametric = c.int("the parametric flag")?;
        // Parametric nodes carry u (curves) or u v (surfaces) after x y z.
        let params = if parametric != 0 { dim.clamp(0, 2) as usize } else { 0 };
        let n = c.count(32 + 8 * params, "the block's node count")?;
        let tag_start = c.at;
        c.skip(8 * n, "node tags")?;
        let mut at_tag = tag_start;
        for _ in 0..n {
            let mut t = Cursor { bytes: c.bytes, at: at_tag, swap: c.swap };
            let node = t.size("a node tag")?;
            at_tag = t.at;
            let p = [c.real("a coordinate")?, c.real("a coordinate")?, c.real("a coordinate")?];
            c.skip(8 * params, "parametric coordinates")?;
            if points.len() >= u32::MAX as usize {
                return Err(bad("too many nodes"));
            }
            if !tags.insert(node, points.len() as u32)? {
                return Err(bad(format!("node {node} is defined twice")));
            }
            try_push(points, p, "points")?;
        }
    }
    if points.len() != total {
        return Err(bad(format!("{} nodes were read, but {total} were announced", points.len())));
    }
    Ok(())
}

/// The node count of an element type this reader meets: triangles, quads, points and lines.
fn nodes_of(element_type: i32) -> Option<usize> {
    Some(match element_type {
        2 => 3,
        3 => 4,
        15 => 1,
        1 => 2,
        8 => 3,
        26 => 4,
        27 => 5,
        28 => 6,
        _ => return None,
    })
}

fn read_elements(
    c: &mut Cursor<'_>,
    tags: Option<&NodeTags>,
    elements: &mut Elements,
    groups: &mut Groups,
) -> Result<(), IoError> {
    let blocks = c.count(20, "the entity block count")?;
    let total = c.size("the element count")?;
    c.size("the minimum element tag")?;
    c.size("the maximum element tag")?;
    let mut index = 0usize;
    for _ in 0..blocks {
        c.int("the entity dimension")?;
        let entity = c.int("the entity tag")?;
        let ty = c.int("the element type")?;
        let Some(k) = nodes_of(ty) else {
            return Err(IoError::Unsupported(format!(
                "element {index} has Gmsh element type {ty}; only triangles (type 2), quads (type 3), points and \
                 lines are read \
                 (element numbers are 0-based)"
            )));
        };
        let n = c.count(8 * (1 + k), "the block's element count")?;
        let low = low_dimension(ty as usize);
        let mut nodes = [0u64; 6];
        for _ in 0..n {
            c.size("an element tag")?;
            for slot in nodes.iter_mut().take(k) {
                *slot = c.size("a node tag")?;
            }
            if let Some(dim) = low {
                groups.element_of_entity(dim, entity, &nodes[..k])?;
            } else if ty as usize == MSH_QUAD || ty as usize == MSH_TRIANGLE {
                // Line numbers mean nothing here: 0.
                elements.push(tags, 0, index, &nodes[..k])?;
            }
            index += 1;
        }
    }
    if index as u64 != total {
        return Err(bad(format!("{index} elements were read, but {total} were announced")));
    }
    Ok(())
}

/// A view: the `fixed` flags if it is a one-component `$NodeData` view named "fixed",
/// else `None`; the data is skipped either way.
fn read_view(
    c: &mut Cursor<'_>,
    section: &str,
    tags: &NodeTags,
    nodes: usize,
) -> Result<Option<Vec<bool>>, IoError> {
    let strings = c.count_line("the view's string tag count")?;
    let mut name = String::new();
    for i in 0..strings {
        let l = c.line().unwrap_or("");
        if i == 0 {
            name = l.trim().to_string();
        }
    }
    let reals = c.count_line("the view's real tag count")?;
    for _ in 0..reals {
        c.line();
    }
    let integers = c.count_line("the view's integer tag count")?;
    let mut ints = Vec::new();
    for _ in 0..integers {
        try_push(&mut ints, c.count_line("an integer tag")?, "integer tags")?;
    }
    let components = ints.get(1).copied().unwrap_or(1);
    let count = ints.get(2).copied().unwrap_or(0);
    let entry = 4usize.saturating_add(components.saturating_mul(8));
    if count.saturating_mul(entry) > c.bytes.len().saturating_sub(c.at) {
        return Err(bad(format!("view {} holds more entries than the file (truncated file?)", clip(&name))));
    }
    let wanted = section == "$NodeData" && name == "\"fixed\"" && components == 1;
    let mut flags = if wanted {
        let mut f = try_vec(nodes, "flags")?;
        f.resize(nodes, false);
        Some(f)
    } else {
        None
    };
    for _ in 0..count {
        let tag = c.int("a view's tag")?;
        if let Some(flags) = flags.as_mut() {
            let index = u64::try_from(tag)
                .ok()
                .and_then(|t| tags.get(t))
                .ok_or_else(|| bad(format!("view \"fixed\" refers to node {tag}, which does not exist")))?;
            flags[index as usize] = c.real("a view value")? != 0.0;
        } else {
            c.skip(8 * components, "a view's values")?;
        }
    }
    c.expect_line(&format!("$End{}", &section[1..]))?;
    Ok(flags)
}

/// Writes binary MSH 4.1, little-endian: one surface entity with every node and face (one
/// element block per run of faces of one type, as [`blocks`]), and
/// the views of [`super::write_views`] with binary entries.
pub(super) fn write(w: &mut dyn Write, data: &MeshData) -> std::io::Result<()> {
    let (n, m) = (data.points.len(), data.quads.len());
    let size = |w: &mut dyn Write, v: usize| w.write_all(&(v as u64).to_le_bytes());
    let int = |w: &mut dyn Write, v: i32| w.write_all(&v.to_le_bytes());
    w.write_all(b"$MeshFormat\n4.1 1 8\n")?;
    int(w, 1)?;
    w.write_all(b"\n$EndMeshFormat\n$Nodes\n")?;
    for v in [1, n, n.min(1), n] {
        size(w, v)?;
    }
    for v in [2, 1, 0] {
        int(w, v)?;
    }
    size(w, n)?;
    let mut buf = Vec::with_capacity(8 * n.max(3 * n));
    for i in 1..=n {
        buf.extend_from_slice(&(i as u64).to_le_bytes());
    }
    w.write_all(&buf)?;
    buf.clear();
    for c in data.points.iter().flatten() {
        buf.extend_from_slice(&c.to_le_bytes());
    }
    w.write_all(&buf)?;
    w.write_all(b"\n$EndNodes\n$Elements\n")?;
    let blocks = blocks(&data.quads);
    for v in [blocks.len(), m, m.min(1), m] {
        size(w, v)?;
    }
    for (ty, range) in blocks {
        for v in [2, 1, ty as i32] {
            int(w, v)?;
        }
        size(w, range.len())?;
        buf.clear();
        for i in range {
            buf.extend_from_slice(&(i as u64 + 1).to_le_bytes());
            for &v in vertices(&data.quads[i]) {
                buf.extend_from_slice(&(u64::from(v) + 1).to_le_bytes());
            }
        }
        w.write_all(&buf)?;
    }
    w.write_all(b"\n$EndElements\n")?;
    let header = |w: &mut dyn Write, section: &str, name: &str, count: usize| {
        // As the ASCII views: the name, the time, then step, components and entity count.
        write!(w, "${section}\n1\n\"{name}\"\n1\n0.0\n3\n0\n1\n{count}\n")
    };
    if let Some(quality) = &data.quality {
        header(w, "ElementData", "scaled_jacobian", quality.len())?;
        buf.clear();
        for (i, &v) in quality.iter().enumerate() {
            buf.extend_from_slice(&(i as i32 + 1).to_le_bytes());
            buf.extend_from_slice(&v.to_le_bytes());
        }
        w.write_all(&buf)?;
        w.write_all(b"\n$EndElementData\n")?;
    }
    for (name, flags) in [("fixed", &data.fixed), ("corner", &data.corner)] {
        let Some(flags) = flags else { continue };
        header(w, "NodeData", name, flags.len())?;
        buf.clear();
        for (i, &f) in flags.iter().enumerate() {
            buf.extend_from_slice(&(i as i32 + 1).to_le_bytes());
            buf.extend_from_slice(&f64::from(u8::from(f)).to_le_bytes());
        }
        w.write_all(&buf)?;
        w.write_all(b"\n$EndNodeData\n")?;
    }
    Ok(())
}
