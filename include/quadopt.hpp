// quadopt.hpp: header-only C++17 interface to quadopt (a thin layer over quadopt.h).
//
//   #include <quadopt.hpp>
//
//   std::vector<double> xy = ...;              // 2 (or 3) doubles per vertex
//   std::vector<std::uint32_t> quads = ...;    // 4 vertex indices per face
//   quadopt::Report r = quadopt::optimize(xy, 2, quads,
//       quadopt::Options().boundary(quadopt::Boundary::Slide).max_iterations(500));
//
// Faces: four indices per face, a quad as its four vertices and a triangle as its three
// followed by quadopt::no_vertex (QUADOPT_NO_VERTEX), so a quad-dominant mesh (quads and
// triangles) goes through the same arrays and calls as a quad mesh; triangles are kept as
// triangles. quadopt::triangle(a, b, c) gives a triangle's four slots; the report's input_quads,
// input_triangles, output_quads and output_triangles split the statistics by kind
// (quadopt::input_by_kind(), quadopt::output_by_kind(), quadopt::quality_by_kind()).
//
// Surfaces in 3D: quadopt::optimize_surface() optimizes a mesh on a curved surface (three
// doubles per vertex), keeping every vertex on the input surface and on its feature curves (the
// boundary, sharp edges and the edges the caller marks); optimize() with dim 3 does the same for
// a mesh whose z varies (a mesh with the same z everywhere is planar: z is never written). The
// report's surface fields (surface, input_verdict, output_verdict, max_distance,
// max_feature_distance, feature_curves, patches) say what it did.
//
// Every failure throws quadopt::Error, which carries the C status code and the library's
// detailed message; a mesh too large for the memory available is one too (status
// QUADOPT_STATUS_OUT_OF_MEMORY), not std::bad_alloc. Adapters for mesh libraries live in
// <quadopt/openmesh.hpp> and <quadopt/cgal.hpp>; include them only if you use those libraries.
//
// Thread safety: every function may be called from several threads at once; an Optimizer may
// be shared by threads (optimize() is const) as long as each thread passes its own coordinates.
// A process forked after using quadopt can use it in the child (see quadopt.h).
#ifndef QUADOPT_HPP
#define QUADOPT_HPP

#include "quadopt.h"

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace quadopt {

/// The C status codes (QUADOPT_STATUS_*).
using Status = QuadoptStatus;
/// Quality statistics of a mesh: min, avg, max scaled Jacobian and the inverted count.
using Quality = QuadoptQuality;
/// What a run did (see QuadoptReport in quadopt.h).
using Report = QuadoptReport;
/// What the progress callback receives after every sweep.
using Progress = QuadoptProgress;

/// The library version as a string, e.g. "0.1.0".
inline const char *version() noexcept { return quadopt_version(); }

/// The static description of a status code (any integer is accepted).
inline const char *status_string(int status) noexcept { return quadopt_status_string(status); }

/// A failed quadopt call: the status code and the detailed message of quadopt_last_error().
class Error : public std::runtime_error {
 public:
  /// An error with `status` and `message` (what() is "<status string>: <message>").
  Error(Status status, const std::string &message)
      : std::runtime_error(compose(status, message)), status_(status), message_(message) {}

  /// The C status code.
  Status status() const noexcept { return status_; }
  /// The detailed message alone (without the status description).
  const std::string &message() const noexcept { return message_; }

 private:
  static std::string compose(Status status, const std::string &message) {
    std::string s = quadopt_status_string(static_cast<int>(status));
    if (!message.empty()) {
      s += ": ";
      s += message;
    }
    return s;
  }
  Status status_;
  std::string message_;
};

/// Thrown by the mesh adapters for a face that is neither a triangle nor a quad (five or more
/// vertices; status QUADOPT_STATUS_INVALID_ARGUMENT): quadopt optimizes meshes of quads and
/// triangles. The message names the face ("OpenMesh face 7 has 5 vertices; ...").
class UnsupportedFace : public Error {
 public:
  /// Face `face` (the mesh library's face index) has `valence` vertices.
  UnsupportedFace(std::size_t face, std::size_t valence, const std::string &library)
      : Error(QUADOPT_STATUS_INVALID_ARGUMENT,
              library + " face " + std::to_string(face) + " has " + std::to_string(valence) +
                  " vertices; quadopt optimizes quads and triangles only"),
        face_(face),
        valence_(valence) {}
  /// The face's index in the mesh.
  std::size_t face() const noexcept { return face_; }
  /// Its number of vertices.
  std::size_t valence() const noexcept { return valence_; }

 private:
  std::size_t face_;
  std::size_t valence_;
};

/// The name of UnsupportedFace from when the adapters took quads only (code that catches it
/// keeps compiling and catches the same errors).
using NonQuadFace = UnsupportedFace;

/// The fourth index of a triangle in a face array (QUADOPT_NO_VERTEX): never a vertex.
constexpr std::uint32_t no_vertex = QUADOPT_NO_VERTEX;

/// The four slots of the triangle (a, b, c): {a, b, c, no_vertex}.
constexpr std::array<std::uint32_t, 4> triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c) noexcept {
  return {a, b, c, no_vertex};
}

/// Whether the face whose four slots start at `face` is a triangle (its fourth is no_vertex).
constexpr bool is_triangle(const std::uint32_t *face) noexcept { return face[3] == no_vertex; }

/// Quality statistics of the faces of one kind: count, min and avg (NaN when count is 0).
using FaceKindQuality = QuadoptFaceKindQuality;

/// Quality statistics of a mesh's quads and of its triangles, apart.
struct ByFaceKind {
  FaceKindQuality quads;      ///< over the quads
  FaceKindQuality triangles;  ///< over the triangles (count 0, NaN min and avg in a quad mesh)
};

/// The report's input statistics by kind (input_quads, input_triangles).
inline ByFaceKind input_by_kind(const Report &r) noexcept { return {r.input_quads, r.input_triangles}; }
/// The report's output statistics by kind (output_quads, output_triangles).
inline ByFaceKind output_by_kind(const Report &r) noexcept { return {r.output_quads, r.output_triangles}; }

/// Throws Error(status, quadopt_last_error()) unless status is QUADOPT_STATUS_OK.
inline void check(Status status) {
  if (status != QUADOPT_STATUS_OK) {
    const char *msg = quadopt_last_error();
    throw Error(status, msg ? msg : "");
  }
}

/// Interior smoothing method.
enum class Method : std::uint32_t {
  EmbeddedPolygon = QUADOPT_METHOD_EMBEDDED_POLYGON,  ///< the paper's method (default)
  Laplacian = QUADOPT_METHOD_LAPLACIAN,               ///< uniform Laplacian
  Cotangent = QUADOPT_METHOD_COTANGENT,               ///< cotangent-weighted Laplacian
  AngleBased = QUADOPT_METHOD_ANGLE_BASED,            ///< Xu and Newman's angle-based smoothing
};

/// Boundary treatment (corners and fixed vertices never move).
enum class Boundary : std::uint32_t {
  Auto = QUADOPT_BOUNDARY_AUTO,    ///< the better of Slide and Snap, per vertex and sweep (default)
  Fixed = QUADOPT_BOUNDARY_FIXED,  ///< boundary vertices never move
  Slide = QUADOPT_BOUNDARY_SLIDE,  ///< move along the original boundary polyline
  Snap = QUADOPT_BOUNDARY_SNAP,    ///< bisect, then project back onto the original boundary
};

/// How much work a run spends on quality (the options' other fields apply on top).
enum class Effort : std::uint32_t {
  Balanced = QUADOPT_EFFORT_BALANCED,  ///< the default: sweeps, then a max-min stage that stops when it stops paying
  Fast = QUADOPT_EFFORT_FAST,          ///< a few guarded sweeps with untangling, no max-min stage
  Best = QUADOPT_EFFORT_BEST,          ///< the highest quality, at more time
};

/// Optimization options: the library's defaults, changed by chainable setters.
///
///   quadopt::Options o = quadopt::Options().method(quadopt::Method::Laplacian).tau(1e-9);
///
/// A progress callback may be any callable `bool(const quadopt::Progress&)`; returning false
/// cancels the run (status QUADOPT_STATUS_CANCELLED, coordinates untouched). An exception
/// thrown by the callback cancels the run too and is rethrown to the caller of optimize().
class Options {
 public:
  /// A callable receiving progress; return false to cancel.
  using ProgressFn = std::function<bool(const Progress &)>;

  /// The library's defaults, filled by quadopt_options_init() for this header's struct size
  /// (safe when the program runs against another version of the library).
  Options() : raw_() { check(quadopt_options_init(&raw_, sizeof raw_)); }
  /// Takes a C options struct as it is (its progress callback included).
  explicit Options(const QuadoptOptions &raw) : raw_(raw) {}

  /// The effort preset (balanced by default); max_iterations and max_min still apply on top.
  Options &effort(Effort e) { raw_.effort = static_cast<std::uint32_t>(e); return *this; }
  /// Interior smoothing method.
  Options &method(Method m) { raw_.method = static_cast<std::uint32_t>(m); return *this; }
  /// Boundary treatment.
  Options &boundary(Boundary b) { raw_.boundary = static_cast<std::uint32_t>(b); return *this; }
  /// Iteration cap (>= 1).
  Options &max_iterations(std::uint32_t n) { raw_.max_iterations = n; return *this; }
  /// Step factor, in (0, 1].
  Options &lambda(double v) { raw_.lambda = v; return *this; }
  /// Stopping threshold on the energy change (per movable vertex unless tau_absolute), for the
  /// energy rule only (stop_rule(QUADOPT_STOP_RULE_ENERGY)); the default quality rule ignores it.
  Options &tau(double v) { raw_.tau = v; return *this; }
  /// Compare tau with the absolute energy change, as the paper does (energy rule only).
  Options &tau_absolute(bool on) { raw_.tau_absolute = on ? 1 : 0; return *this; }
  /// Boundary vertices turning by more than this (degrees, [0, 180]) are corners; on a surface,
  /// also the angle between two faces' normals above which their edge is a feature curve.
  Options &feature_angle_deg(double v) { raw_.feature_angle_deg = v; return *this; }
  /// Guarded moves on or off.
  Options &guard(bool on) { raw_.guard = on ? 1 : 0; return *this; }
  /// The guard's floor, in (0, 1].
  Options &guard_floor(double v) { raw_.guard_floor = v; return *this; }
  /// Untangle inverted quads first.
  Options &untangle(bool on) { raw_.untangle = on ? 1 : 0; return *this; }
  /// Return the best iterate seen rather than the last one.
  Options &keep_best(bool on) { raw_.keep_best = on ? 1 : 0; return *this; }
  /// Largest boundary deviation relative to the edge length; negative: unlimited.
  Options &max_boundary_deviation(double v) { raw_.max_boundary_deviation = v; return *this; }
  /// The max-min stage after the sweeps (raises the worst quad) on or off.
  Options &max_min(bool on) { raw_.max_min = on ? 1 : 0; return *this; }
  /// Stop when the quality stops improving (QUADOPT_STOP_RULE_QUALITY, the default) or on the
  /// energy change (QUADOPT_STOP_RULE_ENERGY, the paper's rule, with tau).
  Options &stop_rule(QuadoptStopRule rule) { raw_.stop_rule = static_cast<std::uint32_t>(rule); return *this; }
  /// A progress callback (an empty function removes it).
  Options &progress(ProgressFn fn) {
    progress_ = std::move(fn);
    raw_.progress = nullptr;
    raw_.progress_user_data = nullptr;
    return *this;
  }

  /// The C struct (without the C++ progress callback, which only the call helpers install).
  const QuadoptOptions &raw() const noexcept { return raw_; }
  /// The C struct, for fields this wrapper has no setter for.
  QuadoptOptions &raw() noexcept { return raw_; }
  /// The C++ progress callback, if any.
  const ProgressFn &progress_fn() const noexcept { return progress_; }

 private:
  QuadoptOptions raw_;
  ProgressFn progress_;
};

namespace detail {

/// Runs a C call with `options`, routing a C++ progress callback through a C trampoline that
/// never lets an exception cross into the library.
template <class Call>
Status with_options(const Options &options, Call &&call) {
  if (!options.progress_fn()) {
    return call(&options.raw());
  }
  struct Ctx {
    const Options::ProgressFn *fn;
    std::exception_ptr error;
  } ctx{&options.progress_fn(), nullptr};
  QuadoptOptions raw = options.raw();
  raw.progress = [](const QuadoptProgress *p, void *user) -> bool {
    Ctx *c = static_cast<Ctx *>(user);
    try {
      return (*c->fn)(*p);
    } catch (...) {
      c->error = std::current_exception();
      return false;
    }
  };
  raw.progress_user_data = &ctx;
  Status s = call(&raw);
  if (ctx.error) {
    std::rethrow_exception(ctx.error);
  }
  return s;
}

/// A zeroed report with this header's struct_size (what quadopt_report_init() returns, without
/// returning a struct by value across a library of possibly another version).
inline Report new_report() noexcept {
  Report r{};
  r.struct_size = static_cast<std::uint32_t>(sizeof r);
  return r;
}

inline std::size_t vertex_count(std::size_t coords, std::uint32_t dim) {
  if (dim != 2 && dim != 3) {
    throw Error(QUADOPT_STATUS_INVALID_ARGUMENT, "dimension " + std::to_string(dim) + " is not 2 or 3");
  }
  if (coords % dim != 0) {
    throw Error(QUADOPT_STATUS_INVALID_ARGUMENT, std::to_string(coords) +
                                                     " coordinates are not a whole number of " +
                                                     std::to_string(dim) + "-D points");
  }
  return coords / dim;
}

inline std::size_t quad_count(std::size_t indices) {
  if (indices % 4 != 0) {
    throw Error(QUADOPT_STATUS_INVALID_ARGUMENT,
                std::to_string(indices) + " face indices are not a multiple of 4");
  }
  return indices / 4;
}

/// Statistics of `values` (one per face of `faces`, four slots per face) split by kind, in face
/// order, as the library computes them (the same sum, so the same bits).
inline ByFaceKind split_by_kind(const std::uint32_t *faces, const std::vector<double> &values) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  FaceKindQuality q{0, nan, nan}, t{0, nan, nan};
  double sum_q = 0.0, sum_t = 0.0;
  for (std::size_t f = 0; f < values.size(); ++f) {
    FaceKindQuality &k = is_triangle(faces + 4 * f) ? t : q;
    double &sum = is_triangle(faces + 4 * f) ? sum_t : sum_q;
    const double v = values[f];
    k.min = k.count == 0 ? v : std::fmin(k.min, v);
    sum += v;
    ++k.count;
  }
  if (q.count > 0) q.avg = sum_q / static_cast<double>(q.count);
  if (t.count > 0) t.avg = sum_t / static_cast<double>(t.count);
  return {q, t};
}

inline const std::uint8_t *fixed_ptr(const std::vector<std::uint8_t> &fixed, std::size_t n) {
  if (fixed.empty()) {
    return nullptr;
  }
  if (fixed.size() != n) {
    throw Error(QUADOPT_STATUS_INVALID_ARGUMENT, std::to_string(fixed.size()) + " fixed flags for " +
                                                     std::to_string(n) + " vertices");
  }
  return fixed.data();
}

}  // namespace detail

/// Optimizes `coords` (`dim` = 2 or 3 doubles per vertex) in place: a planar mesh (dim 2, or
/// dim 3 with the same z at every vertex) in its plane, x and y moved and z untouched; a dim 3
/// mesh whose z varies on its surface in 3D, as optimize_surface() with no marked edge. `quads` holds 4 indices per face (`quad_count` faces; a triangle's fourth is
/// no_vertex); `fixed` is empty or holds one flag per vertex (nonzero: the vertex never moves).
/// Throws Error on failure, leaving `coords` untouched.
inline Report optimize(double *coords, std::uint32_t dim, std::size_t vertex_count,
                       const std::uint32_t *quads, std::size_t quad_count,
                       const std::uint8_t *fixed = nullptr, const Options &options = Options()) {
  Report report = detail::new_report();
  check(detail::with_options(options, [&](const QuadoptOptions *o) {
    return quadopt_optimize(coords, dim, vertex_count, quads, quad_count, fixed, o, &report);
  }));
  return report;
}

/// optimize() on vectors: `coords.size()` must be a multiple of `dim`, `quads.size()` of 4
/// (quads and triangles, four slots per face).
inline Report optimize(std::vector<double> &coords, std::uint32_t dim, const std::vector<std::uint32_t> &quads,
                       const Options &options = Options(), const std::vector<std::uint8_t> &fixed = {}) {
  const std::size_t n = detail::vertex_count(coords.size(), dim);
  return optimize(coords.data(), dim, n, quads.data(), detail::quad_count(quads.size()),
                  detail::fixed_ptr(fixed, n), options);
}

/// A point in 3D.
using Point3 = std::array<double, 3>;
/// An edge as its two vertex indices (in either order).
using Edge = std::array<std::uint32_t, 2>;

/// Whether a report comes from a run on a surface in 3D (its `surface` field, when the library
/// that filled it knew the field).
inline bool on_surface(const Report &r) noexcept {
  return r.struct_size >= offsetof(Report, surface) + sizeof r.surface && r.surface != 0;
}

/// Optimizes a mesh on a curved surface in 3D in place (quadopt_optimize_surface()):
/// `coords` holds 3 doubles per vertex, `faces` 4 slots per face (a triangle's fourth is
/// no_vertex), `fixed` NULL or one flag per vertex, `feature_edges` NULL (with a count of 0)
/// or two vertex indices per marked feature edge. Every vertex stays on the input surface, a
/// vertex on a feature curve (the boundary, an edge sharper than the options'
/// feature_angle_deg, a marked edge) on that curve; corners and fixed vertices keep their
/// coordinates bit for bit. Throws Error on failure (a marked pair that is not an edge:
/// status QUADOPT_STATUS_INVALID_ARGUMENT, naming it), leaving `coords` untouched.
inline Report optimize_surface(double *coords, std::size_t vertex_count, const std::uint32_t *faces,
                               std::size_t face_count, const std::uint8_t *fixed = nullptr,
                               const std::uint32_t *feature_edges = nullptr, std::size_t feature_edge_count = 0,
                               const Options &options = Options()) {
  Report report = detail::new_report();
  check(detail::with_options(options, [&](const QuadoptOptions *o) {
    return quadopt_optimize_surface(coords, vertex_count, faces, face_count, fixed, feature_edges,
                                    feature_edge_count, o, &report);
  }));
  return report;
}

/// optimize_surface() on vectors of flat coordinates (3 doubles per vertex).
inline Report optimize_surface(std::vector<double> &xyz, const std::vector<std::uint32_t> &faces,
                               const Options &options = Options(), const std::vector<std::uint8_t> &fixed = {},
                               const std::vector<Edge> &feature_edges = {}) {
  const std::size_t n = detail::vertex_count(xyz.size(), 3);
  std::vector<std::uint32_t> edges;
  edges.reserve(2 * feature_edges.size());
  for (const Edge &e : feature_edges) {
    edges.push_back(e[0]);
    edges.push_back(e[1]);
  }
  return optimize_surface(xyz.data(), n, faces.data(), detail::quad_count(faces.size()), detail::fixed_ptr(fixed, n),
                          edges.empty() ? nullptr : edges.data(), feature_edges.size(), options);
}

/// optimize_surface() on points: `points` is updated only on success.
inline Report optimize_surface(std::vector<Point3> &points, const std::vector<std::uint32_t> &faces,
                               const std::vector<std::uint8_t> &fixed = {}, const std::vector<Edge> &feature_edges = {},
                               const Options &options = Options()) {
  std::vector<double> xyz;
  xyz.reserve(3 * points.size());
  for (const Point3 &p : points) xyz.insert(xyz.end(), p.begin(), p.end());
  const Report r = optimize_surface(xyz, faces, options, fixed, feature_edges);
  for (std::size_t i = 0; i < points.size(); ++i) {
    points[i] = {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]};
  }
  return r;
}

/// Quality statistics of a mesh (every face); fills `per_quad` (resized to the face count) with
/// each face's signed scaled Jacobian when it is given (a triangle's is Verdict's triangle
/// scaled Jacobian). A dim 3 mesh whose z varies is measured on its surface (each corner
/// against the surface's normal there: what a surface run reports as its `input`). Throws
/// Error on an invalid mesh.
inline Quality quality(const double *coords, std::uint32_t dim, std::size_t vertex_count,
                       const std::uint32_t *quads, std::size_t quad_count,
                       std::vector<double> *per_quad = nullptr) {
  Quality q{};
  std::vector<double> values(per_quad ? quad_count : 0);
  check(quadopt_quality(coords, dim, vertex_count, quads, quad_count, &q, per_quad ? values.data() : nullptr,
                        values.size()));
  if (per_quad) {
    per_quad->swap(values);  // only on success: on error *per_quad is untouched
  }
  return q;
}

/// quality() on vectors.
inline Quality quality(const std::vector<double> &coords, std::uint32_t dim, const std::vector<std::uint32_t> &quads,
                       std::vector<double> *per_quad = nullptr) {
  return quality(coords.data(), dim, detail::vertex_count(coords.size(), dim), quads.data(),
                 detail::quad_count(quads.size()), per_quad);
}

/// Verdict's 3D scaled Jacobian of a mesh in 3D (3 doubles per vertex), as VTK, ParaView and
/// MeshLab compute it: statistics over every face, and each face's value in `per_face`
/// (resized to the face count) when it is given. The measure of a report's input_verdict and
/// output_verdict. Throws Error on an invalid mesh.
inline Quality verdict_quality(const double *xyz, std::size_t vertex_count, const std::uint32_t *faces,
                               std::size_t face_count, std::vector<double> *per_face = nullptr) {
  Quality q{};
  std::vector<double> values(per_face ? face_count : 0);
  check(quadopt_verdict_quality(xyz, vertex_count, faces, face_count, &q, per_face ? values.data() : nullptr,
                                values.size()));
  if (per_face) {
    per_face->swap(values);  // only on success: on error *per_face is untouched
  }
  return q;
}

/// verdict_quality() on vectors.
inline Quality verdict_quality(const std::vector<double> &xyz, const std::vector<std::uint32_t> &faces,
                               std::vector<double> *per_face = nullptr) {
  return verdict_quality(xyz.data(), detail::vertex_count(xyz.size(), 3), faces.data(),
                         detail::quad_count(faces.size()), per_face);
}

/// Quality statistics of a mesh's quads and of its triangles apart (count, min, avg of each,
/// the same numbers as a report's input_quads and input_triangles for these coordinates).
/// Throws Error on an invalid mesh.
inline ByFaceKind quality_by_kind(const std::vector<double> &coords, std::uint32_t dim,
                                  const std::vector<std::uint32_t> &faces) {
  std::vector<double> per_face;
  quality(coords, dim, faces, &per_face);
  return detail::split_by_kind(faces.data(), per_face);
}

/// A reusable optimizer: the connectivity (and the fixed flags) validated and its topology
/// built once, for optimizing many coordinate sets of the same mesh. Move-only; the handle is
/// freed by the destructor. optimize() is const and may run on several threads at once.
class Optimizer {
 public:
  /// Validates the mesh (`coords` are used for validation and orientation) and builds the
  /// topology. Throws Error on an invalid mesh. Planar meshes only: dim 3 coordinates whose z
  /// varies throw Error with status QUADOPT_STATUS_NOT_PLANAR (here and in optimize(); use
  /// quadopt::optimize() or optimize_surface() for a mesh on a curved surface).
  Optimizer(const double *coords, std::uint32_t dim, std::size_t vertex_count, const std::uint32_t *quads,
            std::size_t quad_count, const std::uint8_t *fixed = nullptr)
      : dim_(dim), vertex_count_(vertex_count) {
    check(quadopt_optimizer_create(coords, dim, vertex_count, quads, quad_count, fixed, &handle_));
  }

  /// The same from vectors.
  Optimizer(const std::vector<double> &coords, std::uint32_t dim, const std::vector<std::uint32_t> &quads,
            const std::vector<std::uint8_t> &fixed = {})
      : dim_(dim), vertex_count_(detail::vertex_count(coords.size(), dim)) {
    check(quadopt_optimizer_create(coords.data(), dim, vertex_count_, quads.data(),
                                   detail::quad_count(quads.size()), detail::fixed_ptr(fixed, vertex_count_),
                                   &handle_));
  }

  Optimizer(const Optimizer &) = delete;
  Optimizer &operator=(const Optimizer &) = delete;
  /// Takes over `other`'s handle; `other` becomes empty.
  Optimizer(Optimizer &&other) noexcept
      : handle_(std::exchange(other.handle_, nullptr)), dim_(other.dim_), vertex_count_(other.vertex_count_) {}
  /// Frees this handle and takes over `other`'s.
  Optimizer &operator=(Optimizer &&other) noexcept {
    if (this != &other) {
      quadopt_optimizer_free(handle_);
      handle_ = std::exchange(other.handle_, nullptr);
      dim_ = other.dim_;
      vertex_count_ = other.vertex_count_;
    }
    return *this;
  }
  ~Optimizer() { quadopt_optimizer_free(handle_); }

  /// Optimizes `coords` (`dim` doubles per vertex, `vertex_count` vertices: the same count as
  /// at construction) in place. Throws Error on failure (an empty, moved-from optimizer gives
  /// QUADOPT_STATUS_NULL_POINTER), leaving `coords` untouched.
  Report optimize(double *coords, std::uint32_t dim, std::size_t vertex_count, const Options &options = Options()) const {
    Report report = detail::new_report();
    check(detail::with_options(options, [&](const QuadoptOptions *o) {
      return quadopt_optimizer_optimize(handle_, coords, dim, vertex_count, o, &report);
    }));
    return report;
  }

  /// The same on a vector with the dimension given at construction.
  Report optimize(std::vector<double> &coords, const Options &options = Options()) const {
    return optimize(coords.data(), dim_, detail::vertex_count(coords.size(), dim_), options);
  }

  /// The C handle (owned by this object); null after a move.
  const QuadoptOptimizer *get() const noexcept { return handle_; }
  /// Whether this object holds a handle.
  explicit operator bool() const noexcept { return handle_ != nullptr; }
  /// The dimension given at construction.
  std::uint32_t dim() const noexcept { return dim_; }
  /// The vertex count given at construction.
  std::size_t vertex_count() const noexcept { return vertex_count_; }

 private:
  QuadoptOptimizer *handle_ = nullptr;
  std::uint32_t dim_ = 2;
  std::size_t vertex_count_ = 0;
};

}  // namespace quadopt

#endif  // QUADOPT_HPP
