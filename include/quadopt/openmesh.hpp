// quadopt/openmesh.hpp: optimize an OpenMesh polygon mesh of quads in place.
//
//   #include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
//   #include <quadopt/openmesh.hpp>
//
//   OpenMesh::PolyMesh_ArrayKernelT<> mesh;
//   OpenMesh::IO::read_mesh(mesh, "plate.obj");
//   quadopt::Report r = quadopt::openmesh::optimize(mesh);   // throws quadopt::Error
//
// Works with any OpenMesh mesh type whose points have at least two coordinates p[0], p[1]
// (float ones, the default traits, or double ones). The mesh must lie in a plane z = const: x and y are
// optimized, z is never changed. Coordinates are copied into a double buffer and only the
// vertices whose position changed are written back, so fixed vertices, corners and vertices
// that did not move keep their coordinates bit for bit (with float points a moved vertex is
// rounded to float).
//
// Fixed vertices: with vertex status (mesh.request_vertex_status()), locked vertices and, by
// default, feature vertices never move; MeshOptions::fixed adds a caller's flags. Deleted
// faces are skipped and deleted vertices are held fixed (call garbage_collection() first to
// drop them). Only pure quad meshes are accepted: another face throws quadopt::NonQuadFace.
#ifndef QUADOPT_OPENMESH_HPP
#define QUADOPT_OPENMESH_HPP

#include "../quadopt.hpp"

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
  /// x, y of every vertex (by OpenMesh vertex index).
  std::vector<double> xy;
  /// 4 vertex indices per non-deleted face, in the mesh's face order.
  std::vector<std::uint32_t> quads;
  /// One flag per vertex (nonzero: fixed); empty when no vertex is fixed.
  std::vector<std::uint8_t> fixed;
};

/// Reads `mesh` into flat arrays; throws NonQuadFace on a face that is not a quad, and Error on
/// a mesh too large for 32-bit indices or a `fixed` of the wrong length.
template <class Mesh>
Arrays to_arrays(const Mesh &mesh, const MeshOptions &mo = MeshOptions()) {
  const std::size_t n = mesh.n_vertices();
  if (n > static_cast<std::size_t>(std::numeric_limits<std::uint32_t>::max())) {
    throw Error(QUADOPT_STATUS_INVALID_ARGUMENT, "the mesh has more vertices than 32-bit indices can address");
  }
  if (!mo.fixed.empty() && mo.fixed.size() != n) {
    throw Error(QUADOPT_STATUS_INVALID_ARGUMENT, std::to_string(mo.fixed.size()) + " fixed flags for " +
                                                     std::to_string(n) + " vertices");
  }
  Arrays a;
  a.xy.resize(2 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto &p = mesh.point(typename Mesh::VertexHandle(static_cast<int>(i)));
    a.xy[2 * i] = static_cast<double>(p[0]);
    a.xy[2 * i + 1] = static_cast<double>(p[1]);
  }
  a.quads.reserve(4 * mesh.n_faces());
  for (std::size_t f = 0; f < mesh.n_faces(); ++f) {
    const typename Mesh::FaceHandle fh(static_cast<int>(f));
    if (mesh.has_face_status() && mesh.status(fh).deleted()) {
      continue;
    }
    const std::size_t valence = mesh.valence(fh);
    if (valence != 4) {
      throw NonQuadFace(f, valence, "OpenMesh");
    }
    for (auto vh : mesh.fv_range(fh)) {
      a.quads.push_back(static_cast<std::uint32_t>(vh.idx()));
    }
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

/// Writes the optimized `xy` back into `mesh`: only vertices whose x or y changed are set, and
/// only their x and y.
template <class Mesh>
void write_back(Mesh &mesh, const std::vector<double> &original_xy, const std::vector<double> &xy) {
  using Scalar = std::decay_t<decltype(std::declval<typename Mesh::Point &>()[0])>;
  const std::size_t n = mesh.n_vertices();
  for (std::size_t i = 0; i < n; ++i) {
    if (xy[2 * i] == original_xy[2 * i] && xy[2 * i + 1] == original_xy[2 * i + 1]) {
      continue;
    }
    const typename Mesh::VertexHandle vh(static_cast<int>(i));
    typename Mesh::Point p = mesh.point(vh);
    p[0] = static_cast<Scalar>(xy[2 * i]);
    p[1] = static_cast<Scalar>(xy[2 * i + 1]);
    mesh.set_point(vh, p);
  }
}

/// Optimizes `mesh` in place and returns the report. Throws Error (NonQuadFace for a face that
/// is not a quad) and leaves the mesh unchanged on any failure.
template <class Mesh>
Report optimize(Mesh &mesh, const Options &options = Options(), const MeshOptions &mo = MeshOptions()) {
  Arrays a = to_arrays(mesh, mo);
  std::vector<double> xy = a.xy;
  Report r = quadopt::optimize(xy, 2, a.quads, options, a.fixed);
  write_back(mesh, a.xy, xy);
  return r;
}

/// Quality statistics of `mesh` (and each quad's scaled Jacobian in `per_quad`, in the order
/// of the mesh's non-deleted faces, when given).
template <class Mesh>
Quality quality(const Mesh &mesh, std::vector<double> *per_quad = nullptr) {
  MeshOptions mo;
  mo.locked_is_fixed = false;
  mo.feature_is_fixed = false;
  const Arrays a = to_arrays(mesh, mo);
  return quadopt::quality(a.xy, 2, a.quads, per_quad);
}

}  // namespace openmesh
}  // namespace quadopt

#endif  // QUADOPT_OPENMESH_HPP
