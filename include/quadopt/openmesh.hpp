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
// back onto that plane. A mesh that is not planar throws quadopt::NotPlanar and is left
// unchanged. Coordinates are copied into a double buffer and only the vertices whose position
// changed are written back, so fixed vertices, corners and vertices that did not move keep
// their coordinates bit for bit (with float points a moved vertex is rounded to float, which
// puts it within float precision of the plane).
//
// Fixed vertices: with vertex status (mesh.request_vertex_status()), locked vertices and, by
// default, feature vertices never move; MeshOptions::fixed adds a caller's flags. Deleted
// faces are skipped and deleted vertices are held fixed (call garbage_collection() first to
// drop them).
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
  /// Feature vertices (status().feature()) never move.
  bool feature_is_fixed = true;
  /// Optional extra flags, one per vertex index (nonzero: fixed); empty for none.
  std::vector<std::uint8_t> fixed;
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
};

/// Reads `mesh` into flat arrays; throws UnsupportedFace on a face of five or more vertices,
/// NotPlanar on a 3D mesh that does not lie in a plane, and Error on a mesh too large for
/// 32-bit indices or a `fixed` of the wrong length.
template <class Mesh>
Arrays to_arrays(const Mesh &mesh, const MeshOptions &mo = MeshOptions()) {
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
    a.frame = planar::Frame::fit(xyz, used, "OpenMesh");
  }
  a.xy = a.frame.to_2d(xyz);
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

/// Optimizes `mesh` in place and returns the report (with per-kind statistics in input_quads,
/// input_triangles, output_quads, output_triangles). Throws Error (UnsupportedFace for a face of
/// five or more vertices, NotPlanar for a mesh that is not planar) and leaves the mesh
/// unchanged on any failure.
template <class Mesh>
Report optimize(Mesh &mesh, const Options &options = Options(), const MeshOptions &mo = MeshOptions()) {
  const Arrays a = to_arrays(mesh, mo);
  std::vector<double> xy = a.xy;
  Report r = quadopt::optimize(xy, 2, a.quads, options, a.fixed);
  write_back(mesh, a, xy);
  return r;
}

/// Quality statistics of `mesh` over every face, measured in its plane (and each face's scaled
/// Jacobian in `per_quad`, in the order of the mesh's non-deleted faces, when given). Throws as
/// to_arrays() does.
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
