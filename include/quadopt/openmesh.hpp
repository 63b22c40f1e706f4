// quadopt/openmesh.hpp: optimize an OpenMesh polygon mesh of quads, or of quads and triangles,
// in place.
//
//   #include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
//   #include <quadopt/openmesh.hpp>
//
//   OpenMesh::PolyMesh_ArrayKernelT<> mesh;
//   OpenMesh::IO::read_mesh(mesh, "plate.obj");
//   quadopt::Report r = quadopt::openmesh::optimize(mesh);   // throws quadopt::Error
//
// Works with any OpenMesh mesh type whose points have two or three coordinates (float ones,
// the default traits, or double ones). A 3D mesh may lie in any plane, as with the
// command-line tool (see quadopt/planar.hpp): in a plane x, y or z = const the other two
// coordinates are optimized and the constant one is never changed; in a tilted plane the mesh
// is optimized in an orthonormal frame of its best-fit plane and moved vertices are written
// back onto that plane. A 3D mesh that is not planar lies on a curved surface: optimize()
// optimizes it on that surface in 3D (quadopt::optimize_surface(); the report's `surface` is
// 1): every vertex stays on the input surface and a vertex on a feature curve on that curve.
// Coordinates are copied into a double buffer and only the vertices whose position changed
// are written back, so fixed vertices, corners and vertices that did not move keep their
// coordinates bit for bit (with float points a moved vertex is rounded to float, which puts it
// within float precision of the plane or the surface).
//
// Feature curves (curved meshes only; the planar optimizer's only curve is the boundary): the
// boundary, edges whose faces' normals differ by more than the options' feature_angle_deg,
// and the marked edges: with edge status (mesh.request_edge_status()), the edges whose
// status is feature() (MeshOptions::feature_edges_from_status), and MeshOptions::feature_edges.
//
// Fixed vertices: with vertex status (mesh.request_vertex_status()), locked vertices and, by
// default, feature vertices (vertex status feature()) never move (on a curved mesh, set
// MeshOptions::feature_is_fixed to false to let them slide along their feature curves);
// MeshOptions::fixed adds a caller's flags. Deleted faces are skipped and deleted vertices are
// held fixed (call garbage_collection() first to drop them).
//
// Faces: quads and triangles (a quad-dominant PolyMesh). Triangles are kept as triangles and
// optimized with the quads; the arrays hold four slots per face, a triangle's fourth being
// quadopt::no_vertex. A face of five or more vertices throws
// quadopt::UnsupportedFace (formerly NonQuadFace, still a name for it) naming the face, and
// the mesh is left unchanged.
#ifndef QUADOPT_OPENMESH_HPP
#define QUADOPT_OPENMESH_HPP

#include "../quadopt.hpp"
#include "planar.hpp"

#include <OpenMesh/Core/Utils/vector_traits.hh>

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace quadopt {
namespace openmesh {

/// How the adapter reads an OpenMesh mesh.
struct MeshOptions {
  /// Locked vertices (status().locked()) never move.
  bool locked_is_fixed = true;
  /// Feature vertices (status().feature()) never move (false: on a curved mesh they slide along
  /// their feature curves like any other vertex of a curve).
  bool feature_is_fixed = true;
  /// Optional extra flags, one per vertex index (nonzero: fixed); empty for none.
  std::vector<std::uint8_t> fixed;
  /// On a curved mesh: edges whose status is feature() (when the mesh has edge status) are
  /// feature curves (marked feature edges).
  bool feature_edges_from_status = true;
  /// On a curved mesh: more marked feature edges, as pairs of OpenMesh vertex indices (in
  /// either order). A pair that is not an edge of the mesh's faces throws Error with status
  /// QUADOPT_STATUS_INVALID_ARGUMENT naming it ("feature edge k" is its index here).
  std::vector<std::array<std::uint32_t, 2>> feature_edges;
};

/// The flat arrays quadopt takes, read from a mesh.
struct Arrays {
  /// The 2D coordinates of every vertex (by OpenMesh vertex index) in the mesh's plane: x, y
  /// for a mesh in a plane z = const or of 2D points.
  std::vector<double> xy;
  /// 4 slots per non-deleted face, in the mesh's face order: a quad's four vertex indices, or
  /// a triangle's three and quadopt::no_vertex.
  std::vector<std::uint32_t> quads;
  /// One flag per vertex (nonzero: fixed); empty when no vertex is fixed.
  std::vector<std::uint8_t> fixed;
  /// The mesh's plane and the 2D frame of `xy` in it.
  planar::Frame frame;
  /// Whether the mesh lies on a curved surface (only optimize() reads such a mesh; to_arrays()
  /// throws NotPlanar). Then `xy` is empty and `xyz` and `feature_edges` are filled.
  bool curved = false;
  /// For a curved mesh: x, y, z of every vertex (by OpenMesh vertex index).
  std::vector<double> xyz;
  /// For a curved mesh: the marked feature edges, two vertex indices each
  /// (MeshOptions::feature_edges first, then the edges with feature status).
  std::vector<std::uint32_t> feature_edges;
};

namespace detail {

/// to_arrays(), or with `allow_curved` a curved mesh read for optimize_surface().
template <class Mesh>
Arrays read(const Mesh &mesh, const MeshOptions &mo, bool allow_curved);

}  // namespace detail

/// Reads `mesh` into flat arrays for the planar optimizer; throws UnsupportedFace on a face of
/// five or more vertices, NotPlanar on a 3D mesh that does not lie in a plane, and Error on a
/// mesh too large for 32-bit indices or a `fixed` of the wrong length.
template <class Mesh>
Arrays to_arrays(const Mesh &mesh, const MeshOptions &mo = MeshOptions()) {
  return detail::read(mesh, mo, false);
}

namespace detail {

template <class Mesh>
Arrays read(const Mesh &mesh, const MeshOptions &mo, bool allow_curved) {
  constexpr std::size_t dim = OpenMesh::vector_traits<typename Mesh::Point>::size_;
  static_assert(dim == 2 || dim == 3, "quadopt::openmesh needs points with 2 or 3 coordinates");
  const std::size_t n = mesh.n_vertices();
  if (n > static_cast<std::size_t>(std::numeric_limits<std::uint32_t>::max())) {
    throw Error(QUADOPT_STATUS_INVALID_ARGUMENT, "the mesh has more vertices than 32-bit indices can address");
  }
  if (!mo.fixed.empty() && mo.fixed.size() != n) {
    throw Error(QUADOPT_STATUS_INVALID_ARGUMENT, std::to_string(mo.fixed.size()) + " fixed flags for " +
                                                     std::to_string(n) + " vertices");
  }
  Arrays a;
  a.quads.reserve(4 * mesh.n_faces());
  std::vector<std::uint8_t> used(n, 0);
  for (std::size_t f = 0; f < mesh.n_faces(); ++f) {
    const typename Mesh::FaceHandle fh(static_cast<int>(f));
    if (mesh.has_face_status() && mesh.status(fh).deleted()) {
      continue;
    }
    const std::size_t valence = mesh.valence(fh);
    if (valence != 3 && valence != 4) {
      throw UnsupportedFace(f, valence, "OpenMesh");
    }
    for (auto vh : mesh.fv_range(fh)) {
      a.quads.push_back(static_cast<std::uint32_t>(vh.idx()));
      used[static_cast<std::size_t>(vh.idx())] = 1;
    }
    if (valence == 3) {
      a.quads.push_back(no_vertex);
    }
  }
  std::vector<double> xyz(3 * n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const auto &p = mesh.point(typename Mesh::VertexHandle(static_cast<int>(i)));
    for (std::size_t c = 0; c < dim; ++c) {
      xyz[3 * i + c] = static_cast<double>(p[static_cast<int>(c)]);
    }
  }
  if (dim == 3) {
    try {
      a.frame = planar::Frame::fit(xyz, used, "OpenMesh");
    } catch (const NotPlanar &) {
      if (!allow_curved) throw;
      a.curved = true;
    }
  }
  if (a.curved) {
    for (const auto &e : mo.feature_edges) {
      a.feature_edges.push_back(e[0]);
      a.feature_edges.push_back(e[1]);
    }
    if (mo.feature_edges_from_status && mesh.has_edge_status()) {
      auto live = [&](typename Mesh::FaceHandle fh) {
        return fh.is_valid() && !(mesh.has_face_status() && mesh.status(fh).deleted());
      };
      for (auto eh : mesh.edges()) {
        if (!mesh.status(eh).feature() || mesh.status(eh).deleted()) continue;
        const auto h0 = mesh.halfedge_handle(eh, 0), h1 = mesh.halfedge_handle(eh, 1);
        // An edge of no face that quadopt sees is not an edge of its mesh.
        if (!live(mesh.face_handle(h0)) && !live(mesh.face_handle(h1))) continue;
        a.feature_edges.push_back(static_cast<std::uint32_t>(mesh.from_vertex_handle(h0).idx()));
        a.feature_edges.push_back(static_cast<std::uint32_t>(mesh.to_vertex_handle(h0).idx()));
      }
    }
    a.xyz = std::move(xyz);
  } else {
    a.xy = a.frame.to_2d(xyz);
  }
  bool any = false;
  std::vector<std::uint8_t> fixed(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    bool f = !mo.fixed.empty() && mo.fixed[i] != 0;
    if (mesh.has_vertex_status()) {
      const auto &st = mesh.status(typename Mesh::VertexHandle(static_cast<int>(i)));
      f = f || st.deleted() || (mo.locked_is_fixed && st.locked()) || (mo.feature_is_fixed && st.feature());
    }
    fixed[i] = f ? 1 : 0;
    any = any || f;
  }
  if (any) {
    a.fixed = std::move(fixed);
  }
  return a;
}

}  // namespace detail

/// Writes the optimized 2D coordinates `xy` back into `mesh` (the mesh `a` was read from):
/// only vertices whose 2D position changed are set, to their point of the mesh's plane (for
/// a plane x, y or z = const only the two in-plane coordinates are set).
template <class Mesh>
void write_back(Mesh &mesh, const Arrays &a, const std::vector<double> &xy) {
  using Scalar = std::decay_t<decltype(std::declval<typename Mesh::Point &>()[0])>;
  constexpr std::size_t dim = OpenMesh::vector_traits<typename Mesh::Point>::size_;
  const std::size_t n = mesh.n_vertices();
  for (std::size_t i = 0; i < n; ++i) {
    if (planar::same_bits(xy[2 * i], a.xy[2 * i]) && planar::same_bits(xy[2 * i + 1], a.xy[2 * i + 1])) {
      continue;
    }
    const typename Mesh::VertexHandle vh(static_cast<int>(i));
    typename Mesh::Point p = mesh.point(vh);
    double q[3];
    a.frame.to_3d(&xy[2 * i], q);
    for (int c = 0; c < static_cast<int>(dim); ++c) {
      if (c != a.frame.axis()) {
        p[c] = static_cast<Scalar>(q[c]);
      }
    }
    mesh.set_point(vh, p);
  }
}

/// Writes the optimized 3D coordinates `xyz` of a curved mesh back into `mesh` (the mesh `a`
/// was read from): only vertices whose position changed are set.
template <class Mesh>
void write_back_surface(Mesh &mesh, const Arrays &a, const std::vector<double> &xyz) {
  using Scalar = std::decay_t<decltype(std::declval<typename Mesh::Point &>()[0])>;
  constexpr std::size_t dim = OpenMesh::vector_traits<typename Mesh::Point>::size_;
  for (std::size_t i = 0; i < mesh.n_vertices(); ++i) {
    bool moved = false;
    for (std::size_t c = 0; c < 3; ++c) moved = moved || !planar::same_bits(xyz[3 * i + c], a.xyz[3 * i + c]);
    if (!moved) continue;
    const typename Mesh::VertexHandle vh(static_cast<int>(i));
    typename Mesh::Point p = mesh.point(vh);
    for (std::size_t c = 0; c < dim; ++c) p[static_cast<int>(c)] = static_cast<Scalar>(xyz[3 * i + c]);
    mesh.set_point(vh, p);
  }
}

/// Optimizes `mesh` in place and returns the report (with per-kind statistics in input_quads,
/// input_triangles, output_quads, output_triangles): a planar mesh in its plane, a curved one
/// on its surface in 3D (the report's `surface` is 1; feature curves as described above).
/// Throws Error (UnsupportedFace for a face of five or more vertices; status
/// QUADOPT_STATUS_INVALID_ARGUMENT for a marked feature edge that is not an edge) and leaves
/// the mesh unchanged on any failure.
template <class Mesh>
Report optimize(Mesh &mesh, const Options &options = Options(), const MeshOptions &mo = MeshOptions()) {
  const Arrays a = detail::read(mesh, mo, true);
  if (a.curved) {
    std::vector<double> xyz = a.xyz;
    const Report r = quadopt::optimize_surface(
        xyz.data(), mesh.n_vertices(), a.quads.data(), a.quads.size() / 4, a.fixed.empty() ? nullptr : a.fixed.data(),
        a.feature_edges.empty() ? nullptr : a.feature_edges.data(), a.feature_edges.size() / 2, options);
    write_back_surface(mesh, a, xyz);
    return r;
  }
  std::vector<double> xy = a.xy;
  Report r = quadopt::optimize(xy, 2, a.quads, options, a.fixed);
  write_back(mesh, a, xy);
  return r;
}

/// Quality statistics of `mesh` over every face, measured in its plane (and each face's scaled
/// Jacobian in `per_quad`, in the order of the mesh's non-deleted faces, when given). Throws as
/// to_arrays() does (NotPlanar for a curved mesh: its report from optimize() has its quality).
template <class Mesh>
Quality quality(const Mesh &mesh, std::vector<double> *per_quad = nullptr) {
  MeshOptions mo;
  mo.locked_is_fixed = false;
  mo.feature_is_fixed = false;
  const Arrays a = to_arrays(mesh, mo);
  return quadopt::quality(a.xy, 2, a.quads, per_quad);
}

/// The quality of `mesh`'s quads and of its triangles apart (count, min, avg of each), measured
/// in its plane. Throws as to_arrays() does.
template <class Mesh>
ByFaceKind quality_by_kind(const Mesh &mesh) {
  MeshOptions mo;
  mo.locked_is_fixed = false;
  mo.feature_is_fixed = false;
  const Arrays a = to_arrays(mesh, mo);
  return quadopt::quality_by_kind(a.xy, 2, a.quads);
}

}  // namespace openmesh
}  // namespace quadopt

#endif  // QUADOPT_OPENMESH_HPP
