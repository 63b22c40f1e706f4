//! The safe wrapper: flat arrays in, flat arrays out, every failure an [`Error`].

use crate::ffi;
use std::ffi::{CStr, CString};
use std::fmt;
use std::path::{Path, PathBuf};
use std::ptr::NonNull;

/// A file format OpenMesh reads and writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Format {
    /// Stanford PLY, ASCII or binary.
    Ply,
    /// OpenMesh's own binary format.
    Om,
    /// Wavefront OBJ.
    Obj,
    /// Object File Format.
    Off,
}

impl Format {
    /// Every format.
    pub const ALL: [Format; 4] = [Format::Ply, Format::Om, Format::Obj, Format::Off];

    /// The format named by an extension without the dot (ASCII case-insensitive).
    pub fn from_extension(ext: &str) -> Option<Format> {
        match ext.to_ascii_lowercase().as_str() {
            "ply" => Some(Format::Ply),
            "om" => Some(Format::Om),
            "obj" => Some(Format::Obj),
            "off" => Some(Format::Off),
            _ => None,
        }
    }

    /// The format named by a path's extension.
    pub fn from_path(path: &Path) -> Option<Format> {
        path.extension().and_then(|e| e.to_str()).and_then(Format::from_extension)
    }

    /// The extension, without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            Format::Ply => "ply",
            Format::Om => "om",
            Format::Obj => "obj",
            Format::Off => "off",
        }
    }

    /// Whether OpenMesh 9 keeps `f64` coordinates in this format: only OM. Its PLY reader and
    /// writer use `float x, y, z`, and it parses OBJ and OFF coordinates as `float`.
    pub fn keeps_f64(self) -> bool {
        self == Format::Om
    }

    /// Whether the format carries the fixed flags (a vertex property `fixed`).
    pub fn carries_fixed(self) -> bool {
        matches!(self, Format::Ply | Format::Om)
    }
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Format::Ply => "PLY",
            Format::Om => "OM",
            Format::Obj => "OBJ",
            Format::Off => "OFF",
        })
    }
}

/// A polygon mesh as flat arrays, in OpenMesh's vertex and face order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshArrays {
    /// Vertex coordinates.
    pub points: Vec<[f64; 3]>,
    /// `face_offsets[f]..face_offsets[f + 1]` is face `f`'s range in `face_indices`; starts at 0,
    /// one more entry than there are faces.
    pub face_offsets: Vec<u32>,
    /// The faces' vertex indices (0-based), each face in its own order (the file's order for
    /// PLY, OBJ and OFF; OpenMesh's face-vertex circulator order in general).
    pub face_indices: Vec<u32>,
    /// Per-vertex fixed flags, if the file had them (a vertex property `fixed`, nonzero =
    /// fixed, or OM's locked vertex status).
    pub fixed: Option<Vec<bool>>,
}

impl MeshArrays {
    /// A mesh from points and faces, with no fixed flags. Panics if there are more than
    /// `u32::MAX` face indices.
    pub fn new<F: AsRef<[u32]>>(points: Vec<[f64; 3]>, faces: impl IntoIterator<Item = F>) -> MeshArrays {
        let mut face_offsets = vec![0];
        let mut face_indices = Vec::new();
        for face in faces {
            face_indices.extend_from_slice(face.as_ref());
            face_offsets.push(u32::try_from(face_indices.len()).expect("at most u32::MAX face indices"));
        }
        MeshArrays { points, face_offsets, face_indices, fixed: None }
    }

    /// The number of faces.
    pub fn face_count(&self) -> usize {
        self.face_offsets.len().saturating_sub(1)
    }

    /// Face `f`'s vertex indices. Panics if `f` is out of range.
    pub fn face(&self, f: usize) -> &[u32] {
        &self.face_indices[self.face_offsets[f] as usize..self.face_offsets[f + 1] as usize]
    }

    /// Every face's vertex indices.
    pub fn faces(&self) -> impl Iterator<Item = &[u32]> + '_ {
        self.face_offsets.windows(2).map(|w| &self.face_indices[w[0] as usize..w[1] as usize])
    }

    /// Checks the array shapes the C interface relies on (the shim checks the mesh itself).
    fn check_shape(&self) -> Result<(), Error> {
        let invalid = |message: String| Err(Error::InvalidMesh { message });
        if self.face_offsets.first() != Some(&0) {
            return invalid("face_offsets must start with 0".into());
        }
        if self.face_offsets.last().map(|&o| o as usize) != Some(self.face_indices.len()) {
            return invalid("the last face offset must be the number of face indices".into());
        }
        if let Some(f) = self.face_offsets.windows(2).position(|w| w[1] < w[0]) {
            return invalid(format!("face_offsets decrease at face {f}"));
        }
        if let Some(fixed) = &self.fixed
            && fixed.len() != self.points.len()
        {
            return invalid(format!("{} fixed flags for {} vertices", fixed.len(), self.points.len()));
        }
        Ok(())
    }
}

/// What a read saw besides the mesh.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ReadInfo {
    /// The format read.
    pub format: Format,
    /// The file was binary (PLY binary, OM).
    pub binary: bool,
    /// The vertex count the file declared (PLY, OFF and OM headers; OBJ `v` lines).
    pub declared_vertices: Option<u64>,
    /// The face count the file declared (PLY, OFF and OM headers; OBJ `f` lines).
    pub declared_faces: Option<u64>,
    /// The file had a vertex property `fixed`.
    pub has_fixed_property: bool,
    /// The file had vertex status (OM), whose locked flags count as fixed.
    pub has_vertex_status: bool,
}

/// Why a face of the file is not in the mesh OpenMesh built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DropReason {
    /// Fewer than 3 vertices.
    TooFewVertices,
    /// A vertex index out of range.
    InvalidIndex,
    /// The same vertex twice.
    RepeatedVertex,
    /// OpenMesh's `add_face` refused it: a non-manifold vertex or edge, or a duplicated face.
    NonManifold,
    /// A reason code this version does not know.
    Other(i32),
}

impl DropReason {
    fn from_code(code: ffi::OmsysDropReason) -> DropReason {
        match code as u32 {
            ffi::OMSYS_DROP_TOO_FEW_VERTICES => DropReason::TooFewVertices,
            ffi::OMSYS_DROP_INVALID_INDEX => DropReason::InvalidIndex,
            ffi::OMSYS_DROP_REPEATED_VERTEX => DropReason::RepeatedVertex,
            ffi::OMSYS_DROP_NON_MANIFOLD => DropReason::NonManifold,
            _ => DropReason::Other(code),
        }
    }
}

impl fmt::Display for DropReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DropReason::TooFewVertices => f.write_str("fewer than 3 vertices"),
            DropReason::InvalidIndex => f.write_str("a vertex index out of range"),
            DropReason::RepeatedVertex => f.write_str("a repeated vertex"),
            DropReason::NonManifold => f.write_str("non-manifold or duplicated"),
            DropReason::Other(c) => write!(f, "reason {c}"),
        }
    }
}

/// A face of the file that OpenMesh did not add as given.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DroppedFace {
    /// 0-based index among the file's faces.
    pub face: u64,
    /// Why.
    pub reason: DropReason,
}

/// Everything that can go wrong.
#[derive(Debug)]
pub enum Error {
    /// A file could not be read or written.
    File {
        /// The file.
        path: PathBuf,
        /// "read" or "write".
        action: &'static str,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// The path's extension names no format OpenMesh handles here.
    UnknownFormat {
        /// The file.
        path: PathBuf,
    },
    /// OpenMesh cannot read the data, or it is truncated or corrupt.
    Read {
        /// What went wrong (with OpenMesh's own message when it gave one).
        message: String,
    },
    /// OpenMesh read the data but the mesh differs from what the file declared.
    Incomplete {
        /// A summary naming the dropped faces.
        message: String,
        /// What the file declared, if it declares counts.
        declared_vertices: Option<u64>,
        /// What the file declared, if it declares counts.
        declared_faces: Option<u64>,
        /// The faces OpenMesh did not add, in file order.
        dropped: Vec<DroppedFace>,
    },
    /// The arrays do not make an OpenMesh mesh (bad shape, index, non-manifold face).
    InvalidMesh {
        /// What is wrong.
        message: String,
    },
    /// The format stores `f32` coordinates (in OpenMesh 9) and a coordinate is not an `f32`.
    PrecisionLoss {
        /// The format.
        format: Format,
        /// The vertex.
        vertex: usize,
        /// 0, 1 or 2 for x, y, z.
        axis: usize,
        /// The coordinate.
        value: f64,
    },
    /// The format cannot carry what the mesh has (fixed flags in OBJ or OFF).
    Unsupported {
        /// What.
        message: String,
    },
    /// OpenMesh's writer failed.
    Write {
        /// OpenMesh's message.
        message: String,
    },
    /// Out of memory inside the shim.
    OutOfMemory,
    /// OpenMesh threw an unexpected exception.
    Internal {
        /// The exception's message.
        message: String,
    },
    /// An error inside a named file.
    InFile {
        /// The file.
        path: PathBuf,
        /// The error.
        source: Box<Error>,
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::File { path, action, source } => write!(f, "cannot {action} {}: {source}", path.display()),
            Error::UnknownFormat { path } => write!(
                f,
                "{}: not a format OpenMesh handles here (expected .ply, .om, .obj or .off)",
                path.display()
            ),
            Error::Read { message } => write!(f, "{message}"),
            Error::Incomplete { message, .. } => write!(f, "OpenMesh did not load the whole mesh: {message}"),
            Error::InvalidMesh { message } => write!(f, "invalid mesh: {message}"),
            Error::PrecisionLoss { format, vertex, axis, value } => write!(
                f,
                "{format} through OpenMesh 9 stores float32 coordinates: {} of vertex {vertex} ({value:?}) \
                 would be rounded (write .om for full precision, or allow rounding)",
                ["x", "y", "z"][*axis]
            ),
            Error::Unsupported { message } => write!(f, "{message}"),
            Error::Write { message } => write!(f, "{message}"),
            Error::OutOfMemory => f.write_str("out of memory in the OpenMesh shim"),
            Error::Internal { message } => write!(f, "{message}"),
            Error::InFile { path, source } => write!(f, "{}: {source}", path.display()),
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Error::File { source, .. } => Some(source),
            Error::InFile { source, .. } => Some(source.as_ref()),
            _ => None,
        }
    }
}

/// How to write.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WriteOptions {
    /// Binary PLY (little endian) instead of ASCII. OM is always binary, OBJ and OFF ASCII.
    pub binary: bool,
    /// Let PLY, OBJ and OFF round coordinates to `f32` (see [`Format::keeps_f64`]) instead of
    /// failing with [`Error::PrecisionLoss`].
    pub round_to_f32: bool,
}

/// An owned shim handle.
struct Handle(NonNull<ffi::OmsysMesh>);

impl Handle {
    fn new() -> Result<Handle, Error> {
        // SAFETY: no preconditions; NULL means out of memory.
        NonNull::new(unsafe { ffi::omsys_mesh_new() }).map(Handle).ok_or(Error::OutOfMemory)
    }

    fn ptr(&self) -> *mut ffi::OmsysMesh {
        self.0.as_ptr()
    }

    fn message(&self) -> String {
        // SAFETY: the handle is live; the shim returns a NUL-terminated string it owns, valid
        // until the next call on the handle, copied here at once.
        unsafe { CStr::from_ptr(ffi::omsys_mesh_error(self.ptr())) }.to_string_lossy().into_owned()
    }

    /// Turns a status into a result, with the handle's message.
    fn check(&self, status: ffi::OmsysStatus) -> Result<(), Error> {
        let message = || self.message();
        match status as u32 {
            ffi::OMSYS_OK => Ok(()),
            ffi::OMSYS_READ_FAILED => Err(Error::Read { message: message() }),
            ffi::OMSYS_INVALID_MESH => Err(Error::InvalidMesh { message: message() }),
            ffi::OMSYS_WRITE_FAILED => Err(Error::Write { message: message() }),
            ffi::OMSYS_OUT_OF_MEMORY => Err(Error::OutOfMemory),
            ffi::OMSYS_INVALID_ARGUMENT => Err(Error::Unsupported { message: message() }),
            _ => Err(Error::Internal { message: format!("status {status}: {}", message()) }),
        }
    }

    fn read_info(&self, format: Format) -> Result<ReadInfo, Error> {
        let mut raw = std::mem::MaybeUninit::<ffi::OmsysReadInfo>::zeroed();
        // SAFETY: the handle is live and `raw` is a writable OmsysReadInfo.
        self.check(unsafe { ffi::omsys_read_info(self.ptr(), raw.as_mut_ptr()) })?;
        // SAFETY: all-zero is a valid OmsysReadInfo, and the shim filled it on success.
        let raw = unsafe { raw.assume_init() };
        let declared = |n: u64| (n != u64::MAX).then_some(n);
        Ok(ReadInfo {
            format,
            binary: raw.binary != 0,
            declared_vertices: declared(raw.declared_vertices),
            declared_faces: declared(raw.declared_faces),
            has_fixed_property: raw.has_fixed_property != 0,
            has_vertex_status: raw.has_vertex_status != 0,
        })
    }

    fn dropped(&self, count: u64) -> Result<Vec<DroppedFace>, Error> {
        let mut out = Vec::new();
        for i in 0..count as usize {
            let (mut record, mut reason) = (0u64, 0 as ffi::OmsysDropReason);
            // SAFETY: the handle is live; `i` < the count the shim reported; both outputs are
            // writable.
            self.check(unsafe { ffi::omsys_dropped_face(self.ptr(), i, &mut record, &mut reason) })?;
            out.push(DroppedFace { face: record, reason: DropReason::from_code(reason) });
        }
        Ok(out)
    }

    fn arrays(&self) -> Result<MeshArrays, Error> {
        let mut c = ffi::OmsysCounts { vertices: 0, faces: 0, face_indices: 0, has_fixed: 0 };
        // SAFETY: the handle is live and `c` is writable.
        self.check(unsafe { ffi::omsys_mesh_counts(self.ptr(), &mut c) })?;
        let mut points = vec![0f64; 3 * c.vertices];
        let mut face_offsets = vec![0u32; c.faces + 1];
        let mut face_indices = vec![0u32; c.face_indices];
        let mut fixed = vec![0u8; if c.has_fixed != 0 { c.vertices } else { 0 }];
        // SAFETY: every buffer is writable for exactly the length passed, which the shim checks
        // against its own counts before copying.
        self.check(unsafe {
            ffi::omsys_mesh_get(
                self.ptr(),
                points.as_mut_ptr(),
                points.len(),
                face_offsets.as_mut_ptr(),
                face_offsets.len(),
                face_indices.as_mut_ptr(),
                face_indices.len(),
                fixed.as_mut_ptr(),
                fixed.len(),
            )
        })?;
        Ok(MeshArrays {
            points: points.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect(),
            face_offsets,
            face_indices,
            fixed: (c.has_fixed != 0).then(|| fixed.iter().map(|&f| f != 0).collect()),
        })
    }
}

impl Drop for Handle {
    fn drop(&mut self) {
        // SAFETY: the handle came from omsys_mesh_new and is freed once.
        unsafe { ffi::omsys_mesh_free(self.ptr()) }
    }
}

fn format_name(format: Format) -> CString {
    CString::new(format.extension()).expect("no NUL in an extension")
}

/// Reads a mesh from a file's bytes with OpenMesh. Never panics, whatever the bytes.
pub fn read_bytes(bytes: &[u8], format: Format) -> Result<(MeshArrays, ReadInfo), Error> {
    let h = Handle::new()?;
    let name = format_name(format);
    // SAFETY: the handle is live; `bytes` is readable for its length; `name` is NUL-terminated.
    let status = unsafe { ffi::omsys_read(h.ptr(), bytes.as_ptr(), bytes.len(), name.as_ptr()) };
    if status as u32 == ffi::OMSYS_INCOMPLETE {
        let message = h.message();
        let info = h.read_info(format)?;
        let mut raw = std::mem::MaybeUninit::<ffi::OmsysReadInfo>::zeroed();
        // SAFETY: as in read_info.
        h.check(unsafe { ffi::omsys_read_info(h.ptr(), raw.as_mut_ptr()) })?;
        // SAFETY: filled by the shim.
        let dropped = h.dropped(unsafe { raw.assume_init() }.dropped_faces)?;
        return Err(Error::Incomplete {
            message,
            declared_vertices: info.declared_vertices,
            declared_faces: info.declared_faces,
            dropped,
        });
    }
    h.check(status)?;
    let info = h.read_info(format)?;
    Ok((h.arrays()?, info))
}

/// Reads a mesh file with OpenMesh; the format comes from the extension. Errors name the path.
pub fn read(path: impl AsRef<Path>) -> Result<(MeshArrays, ReadInfo), Error> {
    let path = path.as_ref();
    let format = Format::from_path(path).ok_or_else(|| Error::UnknownFormat { path: path.into() })?;
    let bytes =
        std::fs::read(path).map_err(|source| Error::File { path: path.into(), action: "read", source })?;
    read_bytes(&bytes, format).map_err(|e| Error::InFile { path: path.into(), source: Box::new(e) })
}

/// The first coordinate `f32` cannot hold exactly, if the format stores `f32`.
fn check_precision(mesh: &MeshArrays, format: Format, options: &WriteOptions) -> Result<(), Error> {
    if format.keeps_f64() {
        return Ok(());
    }
    for (vertex, p) in mesh.points.iter().enumerate() {
        for (axis, &value) in p.iter().enumerate() {
            let single = value as f32;
            let exact = f64::from(single) == value;
            if !exact && (!options.round_to_f32 || single.is_infinite()) {
                return Err(Error::PrecisionLoss { format, vertex, axis, value });
            }
        }
    }
    Ok(())
}

/// Writes a mesh with OpenMesh into memory.
pub fn write_bytes(mesh: &MeshArrays, format: Format, options: &WriteOptions) -> Result<Vec<u8>, Error> {
    mesh.check_shape()?;
    if mesh.fixed.is_some() && !format.carries_fixed() {
        return Err(Error::Unsupported {
            message: format!("{format} cannot carry the fixed flags (write .ply or .om, or drop them)"),
        });
    }
    check_precision(mesh, format, options)?;
    let h = Handle::new()?;
    let points: Vec<f64> = mesh.points.iter().flatten().copied().collect();
    let fixed: Option<Vec<u8>> = mesh.fixed.as_ref().map(|f| f.iter().map(|&b| u8::from(b)).collect());
    // SAFETY: the handle is live; each array is readable for the length passed (points: 3 per
    // vertex; offsets: faces + 1, checked by check_shape; fixed: one per vertex or NULL).
    h.check(unsafe {
        ffi::omsys_mesh_set(
            h.ptr(),
            points.as_ptr(),
            mesh.points.len(),
            mesh.face_offsets.as_ptr(),
            mesh.face_count(),
            mesh.face_indices.as_ptr(),
            mesh.face_indices.len(),
            fixed.as_ref().map_or(std::ptr::null(), |f| f.as_ptr()),
        )
    })?;
    let name = format_name(format);
    let opts = ffi::OmsysWriteOptions { binary: i32::from(options.binary) };
    // SAFETY: the handle is live; `name` is NUL-terminated; `opts` is readable.
    h.check(unsafe { ffi::omsys_write(h.ptr(), name.as_ptr(), &opts) })?;
    let (mut data, mut len) = (std::ptr::null::<u8>(), 0usize);
    // SAFETY: the handle is live; both outputs are writable.
    h.check(unsafe { ffi::omsys_output(h.ptr(), &mut data, &mut len) })?;
    if len == 0 {
        return Ok(Vec::new());
    }
    // SAFETY: the shim's output buffer holds `len` bytes, valid until the next call on `h`;
    // copied here before `h` is dropped.
    Ok(unsafe { std::slice::from_raw_parts(data, len) }.to_vec())
}

/// Writes a mesh file with OpenMesh; the format comes from the extension. Atomic: the bytes
/// go to a temporary file in the same directory, renamed over `path` once complete.
pub fn write(path: impl AsRef<Path>, mesh: &MeshArrays, options: &WriteOptions) -> Result<(), Error> {
    let path = path.as_ref();
    let format = Format::from_path(path).ok_or_else(|| Error::UnknownFormat { path: path.into() })?;
    let bytes = write_bytes(mesh, format, options)
        .map_err(|e| Error::InFile { path: path.into(), source: Box::new(e) })?;
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let tmp = dir.join(format!(".{name}.{}.tmp", std::process::id()));
    let result = std::fs::write(&tmp, &bytes).and_then(|()| std::fs::rename(&tmp, path));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result.map_err(|source| Error::File { path: path.into(), action: "write", source })
}
