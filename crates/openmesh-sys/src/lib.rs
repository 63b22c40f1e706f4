//! # openmesh-sys
//!
//! Reads and writes polygon meshes with [OpenMesh](https://www.graphics.rwth-aachen.de/software/openmesh/)
//! 9, the library C++ meshers and OpenFlipper plugins use, so that what such a tool loads is
//! exactly what a Rust program gets.
//!
//! - [`ffi`]: the raw declarations bindgen generates from the C shim's header
//!   (`shim/openmesh_shim.h`), a C interface over an `OpenMesh::PolyMesh_ArrayKernelT` with
//!   double-precision points and `OpenMesh::IO`;
//! - the safe API: [`read`] / [`read_bytes`] give a [`MeshArrays`] (points, faces of any
//!   arity as offsets + indices, the vertex fixed flags) and a [`ReadInfo`]; [`write()`] /
//!   [`write_bytes`] write one back.
//!
//! ```no_run
//! let (mesh, info) = openmesh_sys::read("plate.ply")?;
//! println!("{} vertices, {} faces, binary: {}", mesh.points.len(), mesh.face_count(), info.binary);
//! openmesh_sys::write("plate.om", &mesh, &openmesh_sys::WriteOptions::default())?;
//! # Ok::<(), openmesh_sys::Error>(())
//! ```
//!
//! # What round-trips
//! | format | coordinates (OpenMesh 9) | fixed flags |
//! | --- | --- | --- |
//! | OM (binary) | `f64`, bit-identical | vertex property `fixed`, and the locked status |
//! | PLY ASCII / binary | `f32`: OpenMesh reads and writes `float x, y, z` | vertex property `fixed` (any numeric type on reading, `uchar` on writing) |
//! | OBJ, OFF | `f32` (OpenMesh parses them as `float`) | none |
//!
//! Writing coordinates that `f32` cannot hold exactly to PLY, OBJ or OFF is an
//! [`Error::PrecisionLoss`] unless [`WriteOptions::round_to_f32`] is set.
//!
//! # Nothing dropped silently
//! OpenMesh's importer skips faces it cannot add (an out-of-range or repeated vertex) and adds
//! non-manifold or duplicated faces with copies of their vertices; its readers stop quietly at
//! the end of the data. The shim records what the file declared and what the reader passed on,
//! and a read that lost anything is an [`Error::Incomplete`] naming the faces, never a smaller
//! mesh. Truncated and corrupt files are errors too, checked before OpenMesh's readers see them
//! (they loop with stale values on data they fail to parse): see the crate's README for what
//! each format must look like.

#![warn(missing_docs)]

/// The raw C interface (bindgen's output for `shim/openmesh_shim.h`). Every function catches
/// C++ exceptions and returns a status; see the header for the contract.
#[allow(non_camel_case_types, non_upper_case_globals, non_snake_case, missing_docs, clippy::all)]
pub mod ffi {
    include!(concat!(env!("OUT_DIR"), "/bindings.rs"));
}

mod io;

pub use io::{
    DropReason, DroppedFace, Error, Format, MeshArrays, ReadInfo, WriteOptions, read, read_bytes, write,
    write_bytes,
};
