//! Mesh files: Wavefront OBJ, OFF, legacy VTK (ASCII), Gmsh MSH (ASCII 2.2 and 4.1, binary 4.1)
//! and VTK XML UnstructuredGrid (`.vtu`), read and written, chosen by file extension; and the mapping of a planar mesh in 3D space to the
//! 2D [`Mesh`](crate::Mesh) the optimizer works on ([`planar`]).
//!
//! Every format reads and writes quad-dominant meshes: quads and triangles, in the file's
//! order (a triangle is stored as in [`crate::face`], [`NO_VERTEX`](crate::face::NO_VERTEX)
//! fourth). A face of any other size is an error naming it.
//!
//! # Why hand-written parsers
//! The formats are small and line-oriented, and each available crate misses something this
//! tool needs: `tobj` re-indexes vertices per object (dropping unused vertices and the file's
//! vertex order) and reads `f32` unless a feature is set; `vtkio` does not read `bit` arrays
//! as flags and its reader is not documented as panic-free; `mshio` reads MSH 4.1 only (not
//! 2.2) and does not write. The readers here read coordinates with Rust's correctly rounded
//! `f64` parser, the writers use shortest round-trip formatting (`{:?}`), so values come back
//! bit-identical; and they never panic on arbitrary bytes (every count read from a file is
//! checked against the input actually present before anything is allocated or indexed), which
//! the fuzz targets rely on.
//!
//! # What is read
//! - OBJ: `v` (x y z; a missing z is 0), `f` with 3 or 4 vertices (`a`, `a/b`, `a//c`, `a/b/c`,
//!   negative relative indices). Faces with another vertex count and `l`/`p` elements are
//!   errors; other statements (`vt`, `vn`, `g`, `o`, `usemtl`, ...) are ignored.
//! - OFF (also `COFF`, `NOFF`, `STOFF` ...: extra per-vertex and per-face values are ignored),
//!   faces of 3 or 4 vertices.
//! - VTK legacy ASCII, `UNSTRUCTURED_GRID` with triangle and quad cells (types 5 and 9) or
//!   `POLYDATA` with 3- and 4-vertex `POLYGONS`, in the classic `CELLS n size` layout or VTK
//!   5.1's `OFFSETS`/`CONNECTIVITY`.
//!   A point-data array named `fixed` (`SCALARS` or `FIELD`, any numeric or `bit` type) gives
//!   the fixed flags (nonzero = fixed); every other attribute is skipped.
//! - MSH ASCII 2.x and 4.1, and binary 4.1 (gmsh's `Mesh.Binary=1`; the byte-order integer
//!   is checked, binary 2.2 is refused): nodes in file order (tags may be sparse), 3-node
//!   triangles (type 2) and 4-node quads (type 3). Point and line elements (Gmsh writes them for corners and boundary curves) are
//!   skipped as elements but give the nodes of the physical groups ([`MeshData::physical_groups`]:
//!   `$PhysicalNames`, with `$Entities` in 4.1 and the elements' tags in 2.x); any other
//!   element (higher-order elements, volumes) is an error. A one-component `$NodeData`
//!   view named `fixed` gives the fixed flags (nonzero = fixed); other views are skipped.
//!   Written in the version and encoding read (ASCII 4.1 by default; in 4.1, one element block
//!   per run of faces of one kind, so the file keeps the faces' order); physical groups are not
//!   written back.
//! - VTU: one `<Piece>` of triangle and quad cells (types 5 and 9), data arrays in ASCII, inline base64 or
//!   appended (raw or base64) form, either byte order, UInt32 or UInt64 headers, zlib
//!   compression or none; the point-data array `fixed` gives the fixed flags. Other arrays
//!   are skipped. The crates considered and why the reader is hand-written: see the module
//!   `vtu`'s source.
//!
//! Vertices used by no face are kept as they are, in their place.
//!
//! # What is written besides the mesh
//! [`MeshData::quality`] as cell data `scaled_jacobian` (one value per face, triangles
//! included, in the file's face order) and [`MeshData::fixed`] and
//! [`MeshData::corner`] as 0/1 point data of those names: VTK `CELL_DATA` / `POINT_DATA`
//! `SCALARS`, VTU `<CellData>` / `<PointData>` arrays, MSH `$ElementData` / `$NodeData` views (element and node tags are the 1-based
//! indices the writers number them by). OBJ and OFF carry none of them.

pub mod output;
pub mod planar;

mod lex;
mod msh;
mod obj;
mod off;
mod vtk;
mod vtu;

pub use output::{remove_pending_temporary_files, write_file, write_output};
pub use planar::{PlanarFrame, PlanarMesh};

use std::fs;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use thiserror::Error;

/// Everything that can go wrong reading or writing a mesh file.
#[derive(Debug, Error)]
pub enum IoError {
    /// The file could not be opened, read or written.
    #[error("cannot {action} {}: {source}", path.display())]
    File {
        /// The file.
        path: PathBuf,
        /// "read" or "write".
        action: &'static str,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// Writing to a stream failed.
    #[error("write failed: {0}")]
    Stream(#[source] std::io::Error),
    /// The file extension names no supported format.
    #[error("{}: unknown mesh format (expected the extension .obj, .off, .vtk, .msh or .vtu)", path.display())]
    UnknownFormat {
        /// The file.
        path: PathBuf,
    },
    /// The text is malformed.
    #[error("line {line}: {message}")]
    Parse {
        /// 1-based line of the problem.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// The content of a file without meaningful lines (VTU's XML and binary blocks) is
    /// malformed.
    #[error("{0}")]
    Malformed(String),
    /// A cell is neither a triangle nor a quad.
    #[error(
        "line {line}: cell {cell} is a {kind}; only triangles and quads are supported (cell numbers are 0-based)"
    )]
    NonQuad {
        /// 1-based line of the cell (or of its type).
        line: usize,
        /// 0-based index of the cell among the file's cells (or faces, or elements).
        cell: usize,
        /// What the cell is, e.g. "line (VTK type 3)" or "polygon with 5 vertices".
        kind: String,
    },
    /// A valid file using a feature this reader does not support (binary data, ...).
    #[error("unsupported: {0}")]
    Unsupported(String),
    /// The mesh itself is invalid (index out of range, non-manifold, not planar, ...).
    #[error(transparent)]
    Mesh(#[from] crate::Error),
    /// An error inside a named file.
    #[error("{}: {source}", path.display())]
    InFile {
        /// The file.
        path: PathBuf,
        /// What went wrong in it.
        source: Box<IoError>,
    },
}

/// A supported file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Wavefront OBJ (`.obj`).
    Obj,
    /// Object File Format (`.off`).
    Off,
    /// Legacy VTK, ASCII (`.vtk`).
    Vtk,
    /// Gmsh MSH (`.msh`): ASCII 2.2 and 4.1, binary 4.1.
    Msh,
    /// VTK XML UnstructuredGrid (`.vtu`): ASCII, base64 or appended raw, zlib or not.
    Vtu,
}

impl Format {
    /// Every format.
    pub const ALL: [Format; 5] = [Format::Obj, Format::Off, Format::Vtk, Format::Msh, Format::Vtu];

    /// The format named by a path's extension (ASCII case-insensitive).
    pub fn from_path(path: &Path) -> Result<Format, IoError> {
        let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("obj") => Ok(Format::Obj),
            Some("off") => Ok(Format::Off),
            Some("vtk") => Ok(Format::Vtk),
            Some("msh") => Ok(Format::Msh),
            Some("vtu") => Ok(Format::Vtu),
            _ => Err(IoError::UnknownFormat { path: path.to_path_buf() }),
        }
    }

    /// The usual file extension, without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            Format::Obj => "obj",
            Format::Off => "off",
            Format::Vtk => "vtk",
            Format::Msh => "msh",
            Format::Vtu => "vtu",
        }
    }
}

/// Gmsh MSH file format version.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum MshVersion {
    /// MSH 2.2 (also read: 2.0, 2.1).
    V2_2,
    /// MSH 4.1, the default for writing.
    #[default]
    V4_1,
}

/// A quad(-dominant) mesh as stored in a file: 3D points, faces (0-based indices, as given), optional
/// per-vertex fixed flags, and format details kept for writing the mesh back the same way.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshData {
    /// Vertex coordinates.
    pub points: Vec<[f64; 3]>,
    /// Faces, in the file's order: quads (four 0-based vertex indices) and triangles (three,
    /// and [`NO_VERTEX`](crate::face::NO_VERTEX) fourth, as in [`crate::face`]).
    pub quads: Vec<[u32; 4]>,
    /// Per-vertex fixed flags (VTK point-data array `fixed`), if the file had them.
    pub fixed: Option<Vec<bool>>,
    /// The MSH version read (written back when writing MSH; 4.1 when `None`).
    pub msh_version: Option<MshVersion>,
    /// Whether a VTK file was `POLYDATA` (written back as such when writing VTK).
    pub vtk_polydata: bool,
    /// Per-face signed scaled Jacobian, written as cell data `scaled_jacobian` (VTK/VTU
    /// `CELL_DATA`, MSH `$ElementData`); readers leave it `None` (they ignore the array).
    pub quality: Option<Vec<f64>>,
    /// Per-vertex corner flags, written as point data `corner`; readers leave it `None`.
    pub corner: Option<Vec<bool>>,
    /// How the file stored its data (written back the same way where the format allows).
    pub encoding: Encoding,
    /// Whether a VTU file's data blocks were zlib-compressed (written back the same way).
    pub compressed: bool,
    /// Gmsh physical points and curves (MSH files; empty otherwise). Read only: the MSH
    /// writers write one surface entity with the faces and no groups.
    pub physical_groups: Vec<PhysicalGroup>,
}

/// A Gmsh physical group of dimension 0 (points) or 1 (curves), with the nodes of its
/// elements.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct PhysicalGroup {
    /// 0 for a physical point, 1 for a physical curve.
    pub dim: u8,
    /// The physical tag.
    pub tag: i32,
    /// Its name from `$PhysicalNames` (empty if it has none).
    pub name: String,
    /// The 0-based indices of its nodes, sorted, each once.
    pub nodes: Vec<u32>,
}

/// How a format with several encodings stores its data.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Encoding {
    /// Text.
    #[default]
    Ascii,
    /// Binary: MSH's `Mesh.Binary=1`; VTU's inline base64 `format="binary"`.
    Binary,
    /// VTU's appended raw data (`<AppendedData encoding="raw">`); MSH treats it as `Binary`.
    Appended,
}

impl MeshData {
    /// A mesh from points and faces (quads and triangles), with no fixed flags.
    pub fn new(points: Vec<[f64; 3]>, quads: Vec<[u32; 4]>) -> MeshData {
        MeshData { points, quads, ..MeshData::default() }
    }

    /// Checks that every face index refers to a point and that the fixed flags (if any) have
    /// one entry per point; writers call this so they never emit a broken file.
    pub fn check(&self) -> Result<(), IoError> {
        let n = self.points.len();
        for (qi, q) in self.quads.iter().enumerate() {
            for (c, &v) in crate::face::vertices(q).iter().enumerate() {
                if v as usize >= n {
                    return Err(crate::Error::IndexOutOfRange {
                        quad: qi,
                        corner: c,
                        index: v as u64,
                        vertex_count: n,
                    }
                    .into());
                }
            }
        }
        if let Some(got) = self.fixed.as_ref().map(Vec::len).filter(|&len| len != n) {
            return Err(crate::Error::FixedLengthMismatch { expected: n, got }.into());
        }
        if let Some(got) = self.corner.as_ref().map(Vec::len).filter(|&len| len != n) {
            return Err(IoError::Unsupported(format!("{got} corner flags for {n} points")));
        }
        if let Some(g) = self.physical_groups.iter().find(|g| g.nodes.iter().any(|&v| v as usize >= n)) {
            return Err(IoError::Unsupported(format!(
                "physical group {:?} refers to a missing point",
                g.name
            )));
        }
        let m = self.quads.len();
        if let Some(got) = self.quality.as_ref().map(Vec::len).filter(|&len| len != m) {
            return Err(IoError::Unsupported(format!("{got} quality values for {m} quads")));
        }
        Ok(())
    }
}

/// Reads a mesh file; the format is chosen by the extension. Errors name the path.
pub fn read_mesh(path: impl AsRef<Path>) -> Result<MeshData, IoError> {
    let path = path.as_ref();
    not_a_directory(path, "read")?;
    let format = Format::from_path(path)?;
    let bytes =
        fs::read(path).map_err(|source| IoError::File { path: path.into(), action: "read", source })?;
    read_mesh_bytes(&bytes, format).map_err(|e| IoError::InFile { path: path.into(), source: Box::new(e) })
}

/// Reads a mesh from bytes (invalid UTF-8 is replaced; it can only occur in comments and
/// titles of a valid file). Never panics, whatever the bytes.
pub fn read_mesh_bytes(bytes: &[u8], format: Format) -> Result<MeshData, IoError> {
    // Formats with binary data are read as bytes.
    let binary = match format {
        Format::Vtu => Some(vtu::read(bytes)),
        Format::Msh => Some(msh::read_bytes(bytes)),
        _ => None,
    };
    if let Some(data) = binary {
        let data = data?;
        data.check()?;
        return Ok(data);
    }
    // Checking first is several times faster than the lossy decoding, which is for the rare
    // file with invalid bytes (the same text either way).
    match std::str::from_utf8(bytes) {
        Ok(text) => read_mesh_str(text, format),
        Err(_) => read_mesh_str(&String::from_utf8_lossy(bytes), format),
    }
}

/// Reads a mesh from text (a leading UTF-8 byte-order mark is skipped). Never panics,
/// whatever the text.
pub fn read_mesh_str(text: &str, format: Format) -> Result<MeshData, IoError> {
    // Editors on Windows start UTF-8 files with a BOM; it is not part of the first token.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let data = match format {
        Format::Obj => obj::read(text)?,
        Format::Off => off::read(text)?,
        Format::Vtk => vtk::read(text)?,
        Format::Msh => msh::read(text)?,
        Format::Vtu => vtu::read(text.as_bytes())?,
    };
    data.check()?;
    Ok(data)
}

/// Writes a mesh to a stream in `format`.
pub fn write_mesh_to(writer: &mut dyn Write, format: Format, data: &MeshData) -> Result<(), IoError> {
    data.check()?;
    let mut w = BufWriter::new(writer);
    write_body(&mut w, format, data).and_then(|()| w.flush()).map_err(IoError::Stream)
}

/// Writes a mesh to bytes in `format` (binary encodings included).
pub fn write_mesh_bytes(format: Format, data: &MeshData) -> Result<Vec<u8>, IoError> {
    let mut buf = Vec::new();
    write_mesh_to(&mut buf, format, data)?;
    Ok(buf)
}

/// Writes a mesh to text in `format`. A binary encoding ([`MeshData::encoding`]) that is not
/// valid UTF-8 is an error: use [`write_mesh_bytes`] for those.
pub fn write_mesh_string(format: Format, data: &MeshData) -> Result<String, IoError> {
    let buf = write_mesh_bytes(format, data)?;
    String::from_utf8(buf).map_err(|e| IoError::Stream(std::io::Error::other(e)))
}

/// Writes a mesh file, the format chosen by the extension; see [`write_mesh_as`].
pub fn write_mesh(path: impl AsRef<Path>, data: &MeshData) -> Result<(), IoError> {
    let path = path.as_ref();
    not_a_directory(path, "write")?;
    write_mesh_as(path, Format::from_path(path)?, data)
}

/// Writes a mesh file in `format`, whatever its name: a regular file is replaced atomically
/// (never left half-written, its permissions kept), a symbolic link's target is replaced, a
/// device or FIFO is written in place with every write checked ([`output`] has the details).
pub fn write_mesh_as(path: impl AsRef<Path>, format: Format, data: &MeshData) -> Result<(), IoError> {
    data.check()?;
    output::write_output(path.as_ref(), |w| write_body(w, format, data))
}

/// A directory is not a mesh file: say so (rather than that its name has no known extension).
fn not_a_directory(path: &Path, action: &'static str) -> Result<(), IoError> {
    if path.is_dir() {
        let source = std::io::Error::new(std::io::ErrorKind::IsADirectory, "it is a directory");
        return Err(IoError::File { path: path.into(), action, source });
    }
    Ok(())
}

/// The text of a checked mesh.
fn write_body(w: &mut dyn Write, format: Format, data: &MeshData) -> std::io::Result<()> {
    match format {
        Format::Obj => obj::write(w, data),
        Format::Off => off::write(w, data),
        Format::Vtk => vtk::write(w, data),
        Format::Msh => msh::write(w, data),
        Format::Vtu => vtu::write(w, data),
    }
}

/// `x` as `{:?}` writes it, when `ryu` writes the same text. Both write the shortest digits
/// that read back as `x`, the nearest to `x` of those; they differ on exact ties (when `x`
/// lies exactly halfway between the two nearest, `ryu` rounds to even, `{:?}` up:
/// 266703219052002.125 is `...002.12` against `...002.13`), and in notation: for 0 and
/// magnitudes in [1e-4, 1e16) both are positional (`{:?}` switches to `1e-5` below 1e-4, `ryu`
/// only below 1e-5). Elsewhere (exponents, NaN, infinities, possible ties) `None`: the caller
/// falls back to `{:?}`. The unit test `ryu_writes_what_debug_writes` compares the two on
/// millions of values.
#[inline]
fn fast_f64(b: &mut ryu::Buffer, x: f64) -> Option<&str> {
    let a = x.abs();
    if !((1e-4..1e16).contains(&a) || a == 0.0) {
        return None;
    }
    let s = b.format_finite(x);
    (!tie_possible(a, s)).then_some(s)
}

/// Whether `a` (positive or 0, below 1e16) may lie exactly halfway between two decimals of
/// the length of its shortest digits `s`: then its exact decimal expansion has one digit
/// more than `s` (a 5). With `a = m 2^e`, `m` odd, `e < 0`, that expansion's digits are those
/// of `m 5^-e`; an integer below 2^53 is written exactly (no tie); larger ones are not checked.
#[inline]
fn tie_possible(a: f64, s: &str) -> bool {
    if a >= 9007199254740992.0 {
        return true;
    }
    let bits = a.to_bits();
    let biased = ((bits >> 52) & 0x7ff) as i32;
    if biased == 0 {
        // 0 (subnormals are below 1e-4).
        return false;
    }
    let mut m = (bits & ((1u64 << 52) - 1)) | (1u64 << 52);
    let tz = m.trailing_zeros();
    m >>= tz;
    let e = biased - 1075 + tz as i32;
    if e >= 0 {
        return false;
    }
    let k = e.unsigned_abs();
    // 5^26 alone exceeds 10^18: an expansion that long is longer than 17 digits plus one.
    if k > 26 {
        return false;
    }
    let exact = u128::from(m) * 5u128.pow(k);
    if exact >= 1_000_000_000_000_000_000 {
        return false;
    }
    let exact_digits = exact.ilog10() as usize + 1;
    let digits = s.bytes().filter(u8::is_ascii_digit).skip_while(|&c| c == b'0').count();
    exact_digits == digits + 1
}

/// Appends `x` as `{:?}` writes it: shortest round-trip precision (`1.0`, `0.1`, `1e-7`, `-0.0`).
#[inline]
pub(crate) fn push_f64(buf: &mut Vec<u8>, x: f64) {
    let mut b = ryu::Buffer::new();
    match fast_f64(&mut b, x) {
        Some(s) => buf.extend_from_slice(s.as_bytes()),
        None => {
            let _ = write!(buf, "{x:?}");
        }
    }
}

/// Appends an integer in decimal.
#[inline]
pub(crate) fn push_int(buf: &mut Vec<u8>, x: impl itoa::Integer) {
    buf.extend_from_slice(itoa::Buffer::new().format(x).as_bytes());
}

/// Writes one line (or any text) per item of `items`, `line(buf, i, item)` appending item
/// `i`'s text to `buf`: the text is made in chunks of items, several chunks at a time on
/// rayon's threads, and written in order, so the output is exactly that of a sequential loop.
pub(crate) fn write_items<T: Sync>(
    w: &mut dyn Write,
    items: &[T],
    line: impl Fn(&mut Vec<u8>, usize, &T) + Sync,
) -> std::io::Result<()> {
    use rayon::prelude::*;
    const CHUNK: usize = 1 << 14;
    let batch = CHUNK * 2 * rayon::current_num_threads().max(1);
    let mut bufs: Vec<Vec<u8>> = Vec::new();
    for (b, batch_items) in items.chunks(batch).enumerate() {
        let base = b * batch;
        let chunks = batch_items.len().div_ceil(CHUNK);
        bufs.resize_with(chunks.max(bufs.len()), Vec::new);
        bufs[..chunks].par_iter_mut().enumerate().for_each(|(c, buf)| {
            buf.clear();
            let start = c * CHUNK;
            let end = (start + CHUNK).min(batch_items.len());
            for (k, item) in batch_items[start..end].iter().enumerate() {
                line(buf, base + start + k, item);
            }
        });
        for buf in &bufs[..chunks] {
            w.write_all(buf)?;
        }
    }
    Ok(())
}

/// Appends `x y z` (no line end).
#[inline]
pub(crate) fn push_xyz(buf: &mut Vec<u8>, p: &[f64; 3]) {
    push_f64(buf, p[0]);
    buf.push(b' ');
    push_f64(buf, p[1]);
    buf.push(b' ');
    push_f64(buf, p[2]);
}

/// Appends ` a b c (d)` for a face's vertices plus `offset` (no line end).
#[inline]
pub(crate) fn push_face(buf: &mut Vec<u8>, q: &[u32; 4], offset: u64) {
    for &v in crate::face::vertices(q) {
        buf.push(b' ');
        push_int(buf, u64::from(v) + offset);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(x: f64) {
        let mut buf = Vec::new();
        push_f64(&mut buf, x);
        assert_eq!(std::str::from_utf8(&buf).unwrap(), format!("{x:?}"), "{:#x}", x.to_bits());
    }

    #[test]
    fn ryu_writes_what_debug_writes() {
        use rand_core::{RngCore, SeedableRng};
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(45);
        for x in [0.0, -0.0, 1.0, 0.1, 1e-4, 1e-5, 9.999e-5, 1e-7, 1e15, 1e16, 9.999999999999998e15, 123456.0]
        {
            check(x);
            check(-x);
        }
        for x in [f64::from_bits(0x42ee5215d439bc44), 0.125, 2.5, 0.0625, 1.5e-4, 3.0517578125e-5] {
            check(x);
        }
        for x in
            [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, f64::MIN_POSITIVE, 5e-324, f64::MAX, f64::EPSILON]
        {
            check(x);
        }
        for _ in 0..2_000_000 {
            // Any bit pattern; a value in [0, 1) with 53 random bits; one with a few digits; a
            // value near the notation thresholds.
            check(f64::from_bits(rng.next_u64()));
            let u = (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
            check(u);
            check((u * 1e6).round() / 1e3);
            let e = (rng.next_u32() % 40) as i32 - 20;
            check(u * 10f64.powi(e));
            // Short exact binary fractions: exact decimal expansions, ties among them.
            let t = (rng.next_u64() % (1 << 50)) as f64 / (1u64 << (rng.next_u32() % 60)) as f64;
            check(t);
            check(t * 1e-3);
        }
    }
}
