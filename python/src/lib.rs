//! `quadopt._quadopt`: the Rust half of the Python package `quadopt` (python/quadopt/ is the
//! Python half, which documents the API and calls the functions here).
//!
//! A run does what `quadopt optimize` does with a file holding the same mesh, step for step,
//! so that its results are the CLI's bit for bit (python/tests/ compares them):
//! - the planarity rule of every interface ([`PlanarFrame::fit`] on the vertices used by a
//!   face; an `(n, 2)` array is the plane z = 0, as a 2D file is): a planar mesh is optimized
//!   in its plane by [`Optimizer`], anything else on its surface by [`SurfaceOptimizer`] with
//!   the marked feature edges;
//! - the CLI's options: the defaults with the effort, method, boundary mode, feature angle and
//!   sweep cap set;
//! - the CLI's write-back: a vertex whose position did not change keeps the caller's
//!   coordinates bit for bit; the report is `quadopt::json`'s, as the CLI prints it.
//!
//! Copies: each input array is read once into the Rust value the library takes (any real or
//! integer dtype converted on the way, strided and read-only arrays read as they are), and
//! each output array is made once from the result and handed to numpy without another copy.
//! The caller's arrays are never written. Everything is read before the run starts and
//! nothing is returned on an error, so there is nothing half-written.
//!
//! The run releases the GIL. The progress callback (and the check for a pending signal such
//! as Ctrl-C, which raises KeyboardInterrupt) runs after every sweep on the calling thread;
//! an exception there cancels the run and is raised once it has stopped.

use numpy::ndarray::{Array1, Array2, ArrayView1, ArrayView2};
use numpy::{
    Element, IntoPyArray, PyArray1, PyArray2, PyArrayMethods, PyUntypedArray, PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyException, PyMemoryError, PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyList};
use quadopt::face::NO_VERTEX;
use quadopt::io::PlanarFrame;
use quadopt::surface::{SurfaceMesh, SurfaceOptimizer};
use quadopt::{BoundaryMode, DVec2, DVec3, Effort, Error, Mesh, Method, Optimizer, Options, Progress};
use serde_json::Value;
use std::sync::mpsc;
use std::time::Instant;

pyo3::create_exception!(
    quadopt,
    MeshError,
    PyValueError,
    "The mesh cannot be optimized or measured as given: an index out of range, a NaN \
     coordinate, a face that is not a triangle or a quad, a non-manifold edge, ... The message \
     names the face, corner or vertex (numbered from 0)."
);
pyo3::create_exception!(
    quadopt,
    CancelledError,
    PyException,
    "The progress callback returned False: the run stopped and nothing was returned."
);

/// The library's error as a Python exception: an invalid option is a ValueError, a mesh that
/// cannot be used a MeshError, memory and threads their own kinds.
fn py_error(e: Error) -> PyErr {
    match e {
        Error::InvalidOption { .. } => PyValueError::new_err(e.to_string()),
        Error::OutOfMemory { .. } => PyMemoryError::new_err(e.to_string()),
        Error::NoThreads { .. } => PyRuntimeError::new_err(e.to_string()),
        e => MeshError::new_err(e.to_string()),
    }
}

fn mesh_error(message: String) -> PyErr {
    MeshError::new_err(message)
}

/// The numbers of an array element type, as the library takes them.
trait Number: Element + Copy {
    fn to_f64(self) -> f64;
    fn to_i128(self) -> i128;
}

macro_rules! numbers {
    ($($t:ty),*) => {$(
        impl Number for $t {
            #[allow(clippy::cast_precision_loss, clippy::cast_lossless)]
            fn to_f64(self) -> f64 { self as f64 }
            #[allow(clippy::cast_possible_truncation, clippy::cast_lossless)]
            fn to_i128(self) -> i128 { self as i128 }
        }
    )*};
}
numbers!(f64, f32, i64, i32, i16, i8, u64, u32, u16, u8);

/// Calls `$f::<T>(view)` with a read-only view of `$a` (a 2D or 1D array, by `$array`) for the
/// element type `T` among `$types` that it has; `None` for any other dtype.
macro_rules! dispatch {
    ($a:expr, $array:ident, [$($t:ty),*], $f:ident) => {
        dispatch!($a, $array, [$($t),*], $f, ())
    };
    ($a:expr, $array:ident, [$($t:ty),*], $f:ident, $extra:tt) => {{
        let a = $a;
        let mut out = None;
        $(
            if out.is_none() {
                if let Ok(x) = a.cast::<$array<$t>>() {
                    let r = x.try_readonly().map_err(|e| PyValueError::new_err(e.to_string()))?;
                    out = Some($f::<$t>(r.as_array(), $extra));
                }
            }
        )*
        out
    }};
}

fn type_name(a: &Bound<'_, PyAny>) -> String {
    a.get_type().name().map_or_else(|_| "?".into(), |n| n.to_string())
}

/// The dtype of `a`, for messages.
fn dtype_name(a: &Bound<'_, PyAny>) -> String {
    a.cast::<PyUntypedArray>().map_or_else(|_| type_name(a), |u| u.dtype().to_string())
}

fn rows_f64<T: Number, const D: usize>(v: ArrayView2<'_, T>) -> Vec<[f64; D]> {
    v.rows().into_iter().map(|r| std::array::from_fn(|k| r[k].to_f64())).collect()
}

fn rows2<T: Number>(v: ArrayView2<'_, T>, _: ()) -> Vec<[f64; 2]> {
    rows_f64(v)
}

fn rows3<T: Number>(v: ArrayView2<'_, T>, _: ()) -> Vec<[f64; 3]> {
    rows_f64(v)
}

/// The points: a numpy array of shape (n, 2) or (n, 3) of a real or integer dtype (the Python
/// half has converted anything else), read once into rows.
macro_rules! read_points {
    ($a:expr, $rows:ident) => {{
        let a = $a;
        dispatch!(a, PyArray2, [f64, f32, i64, i32, i16, i8, u64, u32, u16, u8], $rows).ok_or_else(|| {
            PyTypeError::new_err(format!("points: an array of real numbers is needed, not {}", dtype_name(a)))
        })
    }};
}

fn rows_i128<T: Number>(v: ArrayView2<'_, T>, _: ()) -> (usize, Vec<i128>) {
    (v.ncols(), v.iter().map(|x| x.to_i128()).collect())
}

fn items_i128<T: Number>(v: ArrayView1<'_, T>, _: ()) -> Vec<i128> {
    v.iter().map(|x| x.to_i128()).collect()
}

/// A 2D integer array as its column count and its values in row order.
fn read_index_rows(a: &Bound<'_, PyAny>, what: &str) -> PyResult<(usize, Vec<i128>)> {
    let rows = dispatch!(a, PyArray2, [i64, i32, u32, u64, i16, u16, i8, u8], rows_i128);
    rows.ok_or_else(|| {
        PyTypeError::new_err(format!("{what}: an array of integers is needed, not {}", dtype_name(a)))
    })
}

/// One vertex index of face `f`, corner `c`: -1 is allowed in the fourth corner only (the
/// triangle's missing one); a number past `u32` is out of range for any mesh.
fn face_index(v: i128, f: usize, c: usize, vertex_count: usize) -> PyResult<u32> {
    if v == -1 && c == 3 {
        return Ok(NO_VERTEX);
    }
    if v < 0 {
        return Err(mesh_error(format!(
            "face {f} corner {c} is {v}: vertex numbers are 0-based, and -1 only stands in a triangle's \
             fourth corner (face and corner numbers are 0-based)"
        )));
    }
    match u32::try_from(v) {
        Ok(v) if v != NO_VERTEX => Ok(v),
        _ => Err(py_error(Error::IndexOutOfRange {
            quad: f,
            corner: c,
            index: u64::try_from(v).unwrap_or(u64::MAX),
            vertex_count,
        })),
    }
}

/// The faces: an (m, 3) or (m, 4) integer array (-1 in the fourth column for a triangle), or a
/// sequence of sequences of 3 or 4 indices.
fn read_faces(a: &Bound<'_, PyAny>, vertex_count: usize) -> PyResult<Vec<[u32; 4]>> {
    let face = |f: usize, corners: &[i128]| -> PyResult<[u32; 4]> {
        if !(3..=4).contains(&corners.len()) {
            return Err(py_error(Error::UnsupportedFace { face: f, corners: corners.len() }));
        }
        let mut q = [NO_VERTEX; 4];
        for (c, &v) in corners.iter().enumerate() {
            q[c] = face_index(v, f, c, vertex_count)?;
        }
        Ok(q)
    };
    if let Ok(u) = a.cast::<PyUntypedArray>() {
        let rows = u.shape().first().copied().unwrap_or(0);
        let (k, values) = read_index_rows(a, "faces")?;
        if k == 0 {
            // Faces of no vertex (an (m, 0) array), or no face at all.
            return if rows == 0 {
                Ok(Vec::new())
            } else {
                Err(py_error(Error::UnsupportedFace { face: 0, corners: 0 }))
            };
        }
        return values.chunks(k).enumerate().map(|(f, c)| face(f, c)).collect();
    }
    let mut faces = Vec::with_capacity(a.len().unwrap_or(0));
    for (f, item) in a.try_iter()?.enumerate() {
        let item = item?;
        let corners: Vec<i128> = item.extract().map_err(|_| {
            PyTypeError::new_err(format!(
                "faces: face {f} is not a sequence of integers ({})",
                type_name(&item)
            ))
        })?;
        faces.push(face(f, &corners)?);
    }
    Ok(faces)
}

/// The fixed flags: a boolean mask of one flag per vertex, or an array of vertex indices.
fn read_fixed(a: &Bound<'_, PyAny>, vertex_count: usize) -> PyResult<Vec<bool>> {
    if let Ok(mask) = a.cast::<PyArray1<bool>>() {
        let r = mask.try_readonly().map_err(|e| PyValueError::new_err(e.to_string()))?;
        return Ok(r.as_array().to_vec());
    }
    let indices =
        dispatch!(a, PyArray1, [i64, i32, u32, u64, i16, u16, i8, u8], items_i128).ok_or_else(|| {
            PyTypeError::new_err(format!(
                "fixed: a boolean mask or an array of vertex indices is needed, not {}",
                dtype_name(a)
            ))
        })?;
    let mut fixed = vec![false; vertex_count];
    for (k, v) in indices.into_iter().enumerate() {
        match usize::try_from(v).ok().and_then(|v| fixed.get_mut(v)) {
            Some(flag) => *flag = true,
            None => {
                return Err(mesh_error(format!(
                    "fixed index {k} is vertex {v}, but there are only {vertex_count} vertices (vertex numbers \
                     are 0-based)"
                )));
            }
        }
    }
    Ok(fixed)
}

/// The marked feature edges: a (k, 2) integer array of vertex pairs.
fn read_feature_edges(a: &Bound<'_, PyAny>) -> PyResult<Vec<[u32; 2]>> {
    let (k, values) = read_index_rows(a, "feature_edges")?;
    if values.is_empty() {
        return Ok(Vec::new());
    }
    if k != 2 {
        return Err(PyTypeError::new_err(format!("feature_edges: a (k, 2) array is needed, not (k, {k})")));
    }
    values
        .chunks(2)
        .enumerate()
        .map(|(e, p)| {
            let v = |x: i128| {
                u32::try_from(x).map_err(|_| {
                    PyValueError::new_err(format!(
                        "invalid option feature_edges: marked edge {e} has vertex {x}, which no mesh has (vertex \
                         numbers are 0-based)"
                    ))
                })
            };
            Ok([v(p[0])?, v(p[1])?])
        })
        .collect()
}

/// The mesh as the library takes it, before the planarity rule has been applied.
struct Input {
    /// The coordinates: 2D (the plane z = 0) or 3D.
    points: Points,
    faces: Vec<[u32; 4]>,
    fixed: Option<Vec<bool>>,
}

enum Points {
    Two(Vec<DVec2>),
    Three(Vec<[f64; 3]>),
}

impl Points {
    fn len(&self) -> usize {
        match self {
            Points::Two(p) => p.len(),
            Points::Three(p) => p.len(),
        }
    }
}

/// The mesh after the planarity rule: in its plane, or on a curved surface.
enum Placed {
    Planar {
        mesh: Mesh,
        /// The 3D input and its plane (`None` for a 2D input).
        frame: Option<(Vec<[f64; 3]>, PlanarFrame)>,
    },
    Curved(SurfaceMesh),
}

fn read_input(
    points: &Bound<'_, PyAny>,
    faces: &Bound<'_, PyAny>,
    fixed: Option<&Bound<'_, PyAny>>,
) -> PyResult<Input> {
    let u = points.cast::<PyUntypedArray>().map_err(|_| {
        PyTypeError::new_err(format!("points: a numpy array is needed, not {}", type_name(points)))
    })?;
    let points = match u.shape() {
        [_, 2] => Points::Two(read_points!(points, rows2)?.into_iter().map(DVec2::from_array).collect()),
        [_, 3] => Points::Three(read_points!(points, rows3)?),
        shape => {
            return Err(PyTypeError::new_err(format!(
                "points: an (n, 2) or (n, 3) array is needed, not {shape:?}"
            )));
        }
    };
    let n = points.len();
    let faces = read_faces(faces, n)?;
    let fixed = match fixed {
        None => None,
        Some(f) if f.is_none() => None,
        Some(f) => Some(read_fixed(f, n)?),
    };
    Ok(Input { points, faces, fixed })
}

impl Input {
    /// The CLI's `load_input` on a file holding this mesh: the checks of `MeshData::check`,
    /// the planarity rule on the used vertices, then the 2D mesh or the surface mesh.
    fn place(self) -> Result<Placed, Error> {
        let Input { points, faces, fixed } = self;
        let n = points.len();
        for (f, q) in faces.iter().enumerate() {
            for (c, &v) in quadopt::face::vertices(q).iter().enumerate() {
                if v as usize >= n {
                    return Err(Error::IndexOutOfRange {
                        quad: f,
                        corner: c,
                        index: u64::from(v),
                        vertex_count: n,
                    });
                }
            }
        }
        if let Some(got) = fixed.as_ref().map(Vec::len).filter(|&len| len != n) {
            return Err(Error::FixedLengthMismatch { expected: n, got });
        }
        match points {
            // A 2D file's mesh lies in the plane z = 0: its 2D coordinates are x and y.
            Points::Two(p) => {
                if let Some(v) = p.iter().position(|q| !q.is_finite()) {
                    return Err(Error::NonFiniteCoordinate { vertex: v });
                }
                Ok(Placed::Planar { mesh: Mesh::with_faces(p, faces, fixed)?, frame: None })
            }
            Points::Three(p) => {
                let mut used = vec![false; n];
                for q in &faces {
                    for &v in quadopt::face::vertices(q) {
                        used[v as usize] = true;
                    }
                }
                match PlanarFrame::fit(&p, Some(&used)) {
                    Ok(frame) => {
                        let flat: Vec<DVec2> = p.iter().map(|&q| frame.to_2d(q)).collect();
                        Ok(Placed::Planar {
                            mesh: Mesh::with_faces(flat, faces, fixed)?,
                            frame: Some((p, frame)),
                        })
                    }
                    Err(Error::NotPlanar { .. }) => {
                        // Same size and alignment: the vector is reused, not copied.
                        let p: Vec<DVec3> = p.into_iter().map(DVec3::from_array).collect();
                        Ok(Placed::Curved(SurfaceMesh::new(p, faces, fixed)?))
                    }
                    Err(e) => Err(e),
                }
            }
        }
    }
}

/// The CLI's options: the defaults with what its flags of the same names set.
fn options(
    effort: &str,
    boundary: &str,
    method: &str,
    feature_angle: f64,
    max_iterations: Option<usize>,
) -> PyResult<Options> {
    let parse_error = |e: String| PyValueError::new_err(e);
    let effort: Effort = effort.parse().map_err(parse_error)?;
    let boundary: BoundaryMode = boundary.parse().map_err(parse_error)?;
    let method: Method = method.parse().map_err(parse_error)?;
    let o = Options::default()
        .with_effort(effort)
        .with_method(method)
        .with_boundary(boundary)
        .with_max_iterations(max_iterations.unwrap_or(Options::default().max_iterations))
        .with_feature_angle_deg(feature_angle);
    o.validate().map_err(py_error)?;
    Ok(o)
}

/// The progress of a run, passed to the `progress` callable after every sweep.
#[pyclass(module = "quadopt", frozen, get_all, name = "Progress")]
#[derive(Clone)]
struct PyProgress {
    /// Sweeps done so far in the current pass (0 while untangling).
    iteration: usize,
    /// The sweep cap.
    max_iterations: usize,
    /// The current pass, from 1.
    #[pyo3(name = "pass_")]
    pass: usize,
    /// The passes planned (1).
    passes: usize,
    /// The collective energy after the last sweep (NaN while untangling and in the max-min stage).
    energy: f64,
    /// The energy's change in the last sweep (NaN where the energy is).
    energy_change: f64,
}

#[pymethods]
impl PyProgress {
    fn __repr__(&self) -> String {
        format!(
            "Progress(iteration={}, max_iterations={}, pass_={}, passes={}, energy={:?}, energy_change={:?})",
            self.iteration, self.max_iterations, self.pass, self.passes, self.energy, self.energy_change
        )
    }
}

impl From<&Progress> for PyProgress {
    fn from(p: &Progress) -> Self {
        PyProgress {
            iteration: p.iteration,
            max_iterations: p.max_iterations,
            pass: p.pass,
            passes: p.passes,
            energy: p.energy,
            energy_change: p.energy_change,
        }
    }
}

/// What the calling thread does with each progress report: checks for a pending signal
/// (Ctrl-C raises KeyboardInterrupt there), calls the callback, and remembers why the run is
/// to stop.
struct Listener {
    callback: Option<Py<PyAny>>,
    /// The exception that stopped the run (the callback's, or KeyboardInterrupt's).
    error: Option<PyErr>,
    /// The callback returned False.
    declined: bool,
}

impl Listener {
    fn hear(&mut self, p: &Progress) -> bool {
        if self.error.is_some() || self.declined {
            return false;
        }
        Python::attach(|py| {
            if let Err(e) = py.check_signals() {
                self.error = Some(e);
                return false;
            }
            let Some(callback) = &self.callback else { return true };
            match callback.call1(py, (PyProgress::from(p),)) {
                Err(e) => {
                    self.error = Some(e);
                    false
                }
                Ok(answer) => {
                    let declined = answer.bind(py).cast::<PyBool>().is_ok_and(|b| !b.is_true());
                    self.declined = declined;
                    !declined
                }
            }
        })
    }

    /// The exception a stopped run raises.
    fn stopped(self) -> PyErr {
        self.error.unwrap_or_else(|| CancelledError::new_err("cancelled by the progress callback"))
    }
}

/// Runs `job` (with the progress function to hand to the library) on `threads` workers, or on
/// quadopt's own pool for `None` (where the library calls the progress function on this
/// thread), with `listener` answering the reports on this thread either way. With `threads`,
/// as the CLI's `--threads`: a rayon pool of that many workers (capped as quadopt caps them),
/// the job installed in it, the reports handed here through a channel.
fn with_workers<R: Send>(
    threads: Option<usize>,
    listener: &mut Listener,
    job: impl FnOnce(&mut dyn FnMut(&Progress) -> bool) -> R + Send,
) -> Result<R, Error> {
    let Some(n) = threads else {
        return Ok(job(&mut |p: &Progress| listener.hear(p)));
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(n.min(quadopt::max_threads()))
        .build()
        .map_err(|e| Error::NoThreads { why: format!("cannot start {n} threads: {e}") })?;
    std::thread::scope(|s| {
        let (report, reports) = mpsc::channel::<Progress>();
        let (answer, answers) = mpsc::channel::<bool>();
        let worker = s.spawn(move || {
            pool.install(move || {
                let mut forward = |p: &Progress| report.send(*p).is_ok() && answers.recv().unwrap_or(false);
                job(&mut forward)
            })
        });
        for p in reports {
            if answer.send(listener.hear(&p)).is_err() {
                break;
            }
        }
        match worker.join() {
            Ok(r) => Ok(r),
            Err(panic) => std::panic::resume_unwind(panic),
        }
    })
}

/// What a run gives back: the new coordinates (rows of 2 or 3), the report (`moved` still to
/// count for a 2D input), the per-face quality.
struct Outcome {
    points: Vec<f64>,
    dim: usize,
    report: RunReport,
    quality: Vec<f64>,
    vertices: usize,
    faces: usize,
}

enum RunReport {
    /// A planar run, and the vertices that moved (`None` for a 2D input: counted against the
    /// caller's array once the GIL is back, rather than from a copy of it).
    Planar(quadopt::Report, Option<usize>),
    /// A run on a surface, the vertices that moved, and the optimizer's setup time.
    Surface(quadopt::surface::SurfaceReport, usize, f64),
}

/// Whether two 2D positions differ bitwise.
fn bits_differ(a: DVec2, b: DVec2) -> bool {
    a.x.to_bits() != b.x.to_bits() || a.y.to_bits() != b.y.to_bits()
}

fn count_moved<T: Number>(v: ArrayView2<'_, T>, now: &[f64]) -> usize {
    v.rows()
        .into_iter()
        .zip(now.chunks(2))
        .filter(|(r, q)| bits_differ(DVec2::new(r[0].to_f64(), r[1].to_f64()), DVec2::new(q[0], q[1])))
        .count()
}

/// `quadopt optimize`'s run, write-back and report (see the module docs); `Ok(None)` when the
/// listener stopped it.
fn run_optimize(
    input: Input,
    marked: Vec<[u32; 2]>,
    options: &Options,
    threads: Option<usize>,
    listener: &mut Listener,
) -> PyResult<Option<Outcome>> {
    let faces = input.faces.len();
    let start = Instant::now();
    let placed = input.place().map_err(py_error)?;
    match placed {
        Placed::Planar { mut mesh, frame } => {
            if !marked.is_empty() {
                return Err(PyValueError::new_err(
                    "feature_edges apply to meshes on curved surfaces; this mesh is planar (its corners come from \
                     feature_angle)",
                ));
            }
            let n = mesh.points().len();
            let report = with_workers(threads, listener, |progress| {
                let optimizer = Optimizer::new(&mesh);
                optimizer.run(&mut mesh, options, Some(progress))
            })
            .and_then(|r| r)
            .map_err(py_error)?;
            LAST_RUN_SECONDS.set(start.elapsed().as_secs_f64());
            if report.cancelled {
                return Ok(None);
            }
            // As `PlanarMesh::write_back`: a moved vertex gets its point of the plane, any other
            // keeps the caller's coordinates bit for bit.
            let (points, dim, moved) = match frame {
                None => (mesh.points().iter().flat_map(|p| [p.x, p.y]).collect(), 2, None),
                Some((mut p, frame)) => {
                    let mut moved = 0;
                    for (q, now) in p.iter_mut().zip(mesh.points()) {
                        if bits_differ(*now, frame.to_2d(*q)) {
                            *q = frame.to_3d(*now);
                            moved += 1;
                        }
                    }
                    (p.into_flattened(), 3, Some(moved))
                }
            };
            let quality = mesh.quality_values();
            Ok(Some(Outcome {
                points,
                dim,
                report: RunReport::Planar(report, moved),
                quality,
                vertices: n,
                faces,
            }))
        }
        Placed::Curved(mut surface) => {
            let n = surface.points().len();
            let run = with_workers(threads, listener, |progress| -> Result<_, Error> {
                let setup = Instant::now();
                let optimizer = SurfaceOptimizer::new(&surface, options.feature_angle_deg, &marked)?;
                let setup_seconds = setup.elapsed().as_secs_f64();
                // The input positions, to write back only what moved (the optimizer keeps a
                // copy of its own: this one is the caller's, for the output array).
                let mut points: Vec<f64> = surface.points().iter().flat_map(|p| p.to_array()).collect();
                let report = optimizer.run(&mut surface, options, Some(progress))?;
                if report.cancelled {
                    return Ok(None);
                }
                let mut moved = 0;
                for (p, q) in points.chunks_mut(3).zip(surface.points()) {
                    let q = q.to_array();
                    if *p != q {
                        p.copy_from_slice(&q);
                        moved += 1;
                    }
                }
                Ok(Some((report, setup_seconds, points, moved)))
            })
            .and_then(|r| r)
            .map_err(py_error)?;
            let Some((mut report, setup_seconds, points, moved)) = run else { return Ok(None) };
            // The run's own values of its output, as the CLI writes them: what its report summarizes.
            let quality = std::mem::take(&mut report.output_values);
            Ok(Some(Outcome {
                points,
                dim: 3,
                report: RunReport::Surface(report, moved, setup_seconds),
                quality,
                vertices: n,
                faces,
            }))
        }
    }
}

/// A JSON value as the Python object `json.loads` makes of it.
fn to_python<'py>(py: Python<'py>, v: &Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => PyBool::new(py, *b).to_owned().into_any(),
        Value::Number(n) => match (n.as_u64(), n.as_i64()) {
            (Some(u), _) => u.into_pyobject(py)?.into_any(),
            (_, Some(i)) => i.into_pyobject(py)?.into_any(),
            _ => PyFloat::new(py, n.as_f64().unwrap_or(f64::NAN)).into_any(),
        },
        Value::String(s) => s.into_pyobject(py)?.into_any(),
        Value::Array(items) => {
            let list = PyList::empty(py);
            for item in items {
                list.append(to_python(py, item)?)?;
            }
            list.into_any()
        }
        Value::Object(map) => {
            let dict = PyDict::new(py);
            for (k, item) in map {
                dict.set_item(k, to_python(py, item)?)?;
            }
            dict.into_any()
        }
    })
}

fn points_array(py: Python<'_>, points: Vec<f64>, dim: usize) -> PyResult<Bound<'_, PyAny>> {
    let n = points.len() / dim;
    let a = Array2::from_shape_vec((n, dim), points).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    Ok(a.into_pyarray(py).into_any())
}

/// The optimizer: see `quadopt.optimize` (python/quadopt/__init__.py) for the documentation.
/// Returns `(points, report, quality)`.
#[pyfunction]
#[pyo3(signature = (points, faces, fixed, feature_edges, effort, boundary, method, feature_angle, max_iterations, threads, progress))]
#[allow(clippy::too_many_arguments)]
fn optimize<'py>(
    py: Python<'py>,
    points: &Bound<'py, PyAny>,
    faces: &Bound<'py, PyAny>,
    fixed: Option<&Bound<'py, PyAny>>,
    feature_edges: Option<&Bound<'py, PyAny>>,
    effort: &str,
    boundary: &str,
    method: &str,
    feature_angle: f64,
    max_iterations: Option<usize>,
    threads: Option<usize>,
    progress: Option<Py<PyAny>>,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>, Bound<'py, PyAny>)> {
    let options = options(effort, boundary, method, feature_angle, max_iterations)?;
    if threads == Some(0) {
        return Err(PyValueError::new_err("threads: 0 is not a number of threads (a whole number >= 1)"));
    }
    let input = read_input(points, faces, fixed)?;
    let marked = match feature_edges {
        Some(e) if !e.is_none() => read_feature_edges(e)?,
        _ => Vec::new(),
    };
    let mut listener =
        Listener { callback: progress.filter(|c| !c.is_none(py)), error: None, declined: false };
    let outcome = py.detach(|| run_optimize(input, marked, &options, threads, &mut listener))?;
    // A KeyboardInterrupt that arrived after the last report is raised now.
    py.check_signals()?;
    let Some(Outcome { points: out, dim, report, quality, vertices, faces }) = outcome else {
        return Err(listener.stopped());
    };
    let report = match report {
        RunReport::Planar(r, moved) => {
            let moved = match moved {
                Some(m) => m,
                None => {
                    let now = out.as_slice();
                    dispatch!(
                        points,
                        PyArray2,
                        [f64, f32, i64, i32, i16, i8, u64, u32, u16, u8],
                        count_moved,
                        now
                    )
                    .unwrap_or(0)
                }
            };
            quadopt::json::optimize_report(&r, &options, moved, vertices, faces)
        }
        RunReport::Surface(r, moved, setup) => {
            quadopt::json::surface_optimize_report(&r, &options, moved, setup, vertices, faces)
        }
    };
    Ok((
        points_array(py, out, dim)?,
        to_python(py, &report)?,
        Array1::from(quality).into_pyarray(py).into_any(),
    ))
}

/// The quality: see `quadopt.quality`. Returns `(values, summary, verdict values or None)`.
#[pyfunction]
#[pyo3(signature = (points, faces, reference=None))]
fn quality<'py>(
    py: Python<'py>,
    points: &Bound<'py, PyAny>,
    faces: &Bound<'py, PyAny>,
    reference: Option<&Bound<'py, PyAny>>,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>, Bound<'py, PyAny>)> {
    let input = read_input(points, faces, None)?;
    let n = input.points.len();
    // The reference: the same faces at other positions (the input a mesh was optimized from).
    let reference = match reference {
        Some(r) if !r.is_none() => {
            let r = read_input(r, faces, None)?;
            if r.points.len() != n {
                return Err(PyValueError::new_err(format!(
                    "reference: {} vertices, but the mesh has {n} (the reference has the mesh's faces)",
                    r.points.len()
                )));
            }
            Some(r)
        }
        _ => None,
    };
    let measured = py.detach(|| -> PyResult<_> {
        match input.place().map_err(py_error)? {
            Placed::Planar { mesh, .. } => {
                if reference.is_some() {
                    return Err(PyValueError::new_err(
                        "reference measures a mesh on a curved surface; this mesh is planar",
                    ));
                }
                let values = mesh.quality_values();
                let summary = quadopt::json::quality_summary(&values, mesh.faces(), n, None);
                Ok((values, summary, None))
            }
            // As `quadopt quality` measures a mesh on a curved surface: against its own surface
            // (or the reference's, as `--reference` does), with the default feature angle and no
            // marked edge.
            Placed::Curved(mesh) => {
                let base = match reference {
                    None => None,
                    Some(r) => Some(match r.place().map_err(py_error)? {
                        Placed::Curved(s) => s,
                        Placed::Planar { mesh: planar, frame } => {
                            // A planar reference of a curved mesh, as the CLI reads one: in 3D.
                            let points: Vec<DVec3> = match frame {
                                Some((p, _)) => p.into_iter().map(DVec3::from_array).collect(),
                                None => planar.points().iter().map(|p| p.extend(0.0)).collect(),
                            };
                            SurfaceMesh::new(points, mesh.faces_as_given(), None).map_err(py_error)?
                        }
                    }),
                };
                let against_reference = base.is_some();
                let base = base.as_ref().unwrap_or(&mesh);
                if base.faces() != mesh.faces() {
                    return Err(mesh_error("the mesh does not have the faces of the reference".into()));
                }
                let optimizer = SurfaceOptimizer::new(base, Options::default().feature_angle_deg, &[])
                    .map_err(py_error)?;
                let m = optimizer.measure(mesh.points()).map_err(py_error)?;
                let on_surface = quadopt::json::SurfaceQuality { measure: &m, against_reference };
                let summary = quadopt::json::quality_summary(&m.values, mesh.faces(), n, Some(on_surface));
                Ok((m.values.clone(), summary, Some(m.verdict_values)))
            }
        }
    });
    let (values, summary, verdict) = measured?;
    let verdict = match verdict {
        Some(v) => Array1::from(v).into_pyarray(py).into_any(),
        None => py.None().into_bound(py),
    };
    Ok((Array1::from(values).into_pyarray(py).into_any(), to_python(py, &summary)?, verdict))
}

/// The Rust run alone, for the overhead benchmark (python/benchmarks/overhead.py): what a Rust
/// program does with the same planar mesh in memory. `points` (n, 2) and `faces` are read into
/// vectors outside the timing; then, `repeat` times, each on fresh copies of the vectors (made
/// before the clock starts), `Mesh::with_faces`, `Optimizer::new` and `Optimizer::run` with the
/// given effort are timed. Returns the seconds of each.
#[pyfunction]
fn _time_rust_run(
    py: Python<'_>,
    points: &Bound<'_, PyAny>,
    faces: &Bound<'_, PyAny>,
    effort: &str,
    repeat: usize,
) -> PyResult<Vec<f64>> {
    let options = options(effort, "auto", "ep", Options::default().feature_angle_deg, None)?;
    let Input { points: Points::Two(points), faces, .. } = read_input(points, faces, None)? else {
        return Err(PyValueError::new_err("the benchmark takes an (n, 2) array of points"));
    };
    py.detach(|| {
        (0..repeat)
            .map(|_| {
                let (p, f) = (points.clone(), faces.clone());
                let start = Instant::now();
                let mut mesh = Mesh::with_faces(p, f, None)?;
                let optimizer = Optimizer::new(&mesh);
                optimizer.run(&mut mesh, &options, None)?;
                Ok(start.elapsed().as_secs_f64())
            })
            .collect::<Result<Vec<f64>, Error>>()
    })
    .map_err(py_error)
}

thread_local! {
    /// The seconds of the last planar `optimize` call's Rust work on this thread: the mesh's
    /// construction (validation, planarity) and the optimizer's construction and run, for the
    /// overhead benchmark to tell the rest of the call (the arrays read and made, the quality,
    /// the report) from it within the same call.
    static LAST_RUN_SECONDS: std::cell::Cell<f64> = const { std::cell::Cell::new(f64::NAN) };
}

/// See `LAST_RUN_SECONDS`.
#[pyfunction]
fn _last_run_seconds() -> f64 {
    LAST_RUN_SECONDS.get()
}

/// The version of the Rust library the module was built with (the package's own version is
/// the same: python/tests/ checks it).
#[pyfunction]
fn _library_version() -> String {
    use quadopt::ffi::{QUADOPT_VERSION_MAJOR, QUADOPT_VERSION_MINOR, QUADOPT_VERSION_PATCH};
    format!("{QUADOPT_VERSION_MAJOR}.{QUADOPT_VERSION_MINOR}.{QUADOPT_VERSION_PATCH}")
}

/// The Rust half of `quadopt` (see the package's documentation).
#[pymodule]
fn _quadopt(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add_function(wrap_pyfunction!(optimize, m)?)?;
    m.add_function(wrap_pyfunction!(quality, m)?)?;
    m.add_function(wrap_pyfunction!(_time_rust_run, m)?)?;
    m.add_function(wrap_pyfunction!(_library_version, m)?)?;
    m.add_function(wrap_pyfunction!(_last_run_seconds, m)?)?;
    m.add_class::<PyProgress>()?;
    m.add("MeshError", py.get_type::<MeshError>())?;
    m.add("CancelledError", py.get_type::<CancelledError>())?;
    m.add("NO_VERTEX", NO_VERTEX)?;
    Ok(())
}
