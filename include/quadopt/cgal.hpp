// quadopt/cgal.hpp: optimize a CGAL::Surface_mesh of quads, or of quads and triangles, in place.
//
//   #include <CGAL/Simple_cartesian.h>
//   #include <CGAL/Surface_mesh.h>
//   #include <quadopt/cgal.hpp>
//
//   CGAL::Surface_mesh<CGAL::Simple_cartesian<double>::Point_2> mesh = ...;
//   quadopt::Report r = quadopt::cgal::optimize(mesh);   // throws quadopt::Error
//
// Points may be Point_2 or Point_3 of any kernel (exact ones are converted with
// CGAL::to_double and written back from doubles). A Point_3 mesh may lie in any plane, as
// with the command-line tool (see quadopt/planar.hpp): in a plane x, y or z = const the other
// two coordinates are optimized and the constant one is kept; in a tilted plane the mesh is
// optimized in an orthonormal frame of its best-fit plane and moved vertices are written back
// onto that plane. A mesh that is not planar throws quadopt::NotPlanar and is left unchanged.
// Only vertices whose position changed are written back, so fixed vertices, corners and
// vertices that did not move stay bit-identical.
//
// Fixed vertices: a vertex property map of bool named MeshOptions::fixed_property ("v:fixed"
// by default), if the mesh has one; true means the vertex never moves. Removed (garbage)
// vertices and faces are skipped.
//
// Faces: quads and triangles. Triangles are kept as triangles and optimized with the quads
// (four slots per face in the arrays, a triangle's fourth being quadopt::no_vertex). A face of
// five or more vertices throws quadopt::UnsupportedFace (formerly NonQuadFace, still a name for
// it) naming the face, and the mesh is left unchanged.
#ifndef QUADOPT_CGAL_HPP
#define QUADOPT_CGAL_HPP

#include "../quadopt.hpp"
#include "planar.hpp"

#include <CGAL/Dimension.h>
#include <CGAL/Kernel_traits.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/number_utils.h>
#include <CGAL/version.h>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace quadopt {
namespace cgal {

/// How the adapter reads a Surface_mesh.
struct MeshOptions {
  /// Name of a vertex property map of bool marking fixed vertices (ignored when absent; empty
  /// for none).
  std::string fixed_property = "v:fixed";
};

/// The flat arrays quadopt takes, read from a mesh (vertices in the mesh's iteration order,
/// removed ones skipped).
template <class P>
struct Arrays {
  /// The mesh's vertices, in the order of `xy`.
  std::vector<typename CGAL::Surface_mesh<P>::Vertex_index> vertices;
  /// The 2D coordinates of every vertex in the mesh's plane (x, y for Point_2 and for a
  /// Point_3 mesh in a plane z = const).
  std::vector<double> xy;
  /// 4 slots per face, in the mesh's face order: a quad's four indices into `vertices`, or a
  /// triangle's three and quadopt::no_vertex.
  std::vector<std::uint32_t> quads;
  /// One flag per vertex (nonzero: fixed); empty when no vertex is fixed.
  std::vector<std::uint8_t> fixed;
  /// The mesh's plane and the 2D frame of `xy` in it (z = 0 for Point_2).
  planar::Frame frame;
};

namespace detail {

template <class P>
bool find_fixed_map(const CGAL::Surface_mesh<P> &mesh, const std::string &name,
                    typename CGAL::Surface_mesh<P>::template Property_map<typename CGAL::Surface_mesh<P>::Vertex_index, bool> &out) {
  using Mesh = CGAL::Surface_mesh<P>;
  if (name.empty()) {
    return false;
  }
#if CGAL_VERSION_NR >= 1060000000
  auto found = mesh.template property_map<typename Mesh::Vertex_index, bool>(name);
  if (!found) {
    return false;
  }
  out = *found;
  return true;
#else
  auto found = mesh.template property_map<typename Mesh::Vertex_index, bool>(name);
  if (!found.second) {
    return false;
  }
  out = found.first;
  return true;
#endif
}

/// `p` with the coordinates of the plane point `q` (in doubles) in place of those that the
/// frame's 2D coordinates come from; a constant coordinate of an axis-aligned plane is kept as
/// it is (exactly, in the kernel's number type).
template <class P>
P with_plane_point(const P &p, const double q[3], const planar::Frame &frame) {
  using FT = typename CGAL::Kernel_traits<P>::Kernel::FT;
  if constexpr (CGAL::Ambient_dimension<P>::value == 2) {
    (void)p;
    (void)frame;
    return P(FT(q[0]), FT(q[1]));
  } else {
    FT c[3] = {p.x(), p.y(), p.z()};
    for (int k = 0; k < 3; ++k) {
      if (k != frame.axis()) {
        c[k] = FT(q[k]);
      }
    }
    return P(c[0], c[1], c[2]);
  }
}

}  // namespace detail

/// Reads `mesh` into flat arrays; throws UnsupportedFace on a face of five or more vertices and
/// NotPlanar on a Point_3 mesh that does not lie in a plane.
template <class P>
Arrays<P> to_arrays(const CGAL::Surface_mesh<P> &mesh, const MeshOptions &mo = MeshOptions()) {
  using Mesh = CGAL::Surface_mesh<P>;
  using V = typename Mesh::Vertex_index;
  const std::size_t n = mesh.number_of_vertices();
  if (n > static_cast<std::size_t>(std::numeric_limits<std::uint32_t>::max())) {
    throw Error(QUADOPT_STATUS_INVALID_ARGUMENT, "the mesh has more vertices than 32-bit indices can address");
  }
  Arrays<P> a;
  // Index by the vertex's index in the mesh (removed vertices included), mapping to the
  // compact position in `a.vertices`.
  std::vector<std::uint32_t> compact(mesh.num_vertices(), 0);
  a.vertices.reserve(n);
  std::vector<double> xyz;
  xyz.reserve(3 * n);
  for (V v : mesh.vertices()) {
    compact[static_cast<std::size_t>(v)] = static_cast<std::uint32_t>(a.vertices.size());
    a.vertices.push_back(v);
    const P &p = mesh.point(v);
    xyz.push_back(CGAL::to_double(p.x()));
    xyz.push_back(CGAL::to_double(p.y()));
    if constexpr (CGAL::Ambient_dimension<P>::value == 2) {
      xyz.push_back(0.0);
    } else {
      xyz.push_back(CGAL::to_double(p.z()));
    }
  }
  a.quads.reserve(4 * mesh.number_of_faces());
  std::vector<std::uint8_t> used(a.vertices.size(), 0);
  for (auto f : mesh.faces()) {
    const std::size_t valence = mesh.degree(f);
    if (valence != 3 && valence != 4) {
      throw UnsupportedFace(static_cast<std::size_t>(f), valence, "CGAL");
    }
    for (V v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
      a.quads.push_back(compact[static_cast<std::size_t>(v)]);
      used[compact[static_cast<std::size_t>(v)]] = 1;
    }
    if (valence == 3) {
      a.quads.push_back(no_vertex);
    }
  }
  if constexpr (CGAL::Ambient_dimension<P>::value == 3) {
    std::vector<std::size_t> names(a.vertices.size());
    for (std::size_t i = 0; i < names.size(); ++i) {
      names[i] = static_cast<std::size_t>(a.vertices[i]);
    }
    a.frame = planar::Frame::fit(xyz, used, "CGAL", &names);
  }
  a.xy = a.frame.to_2d(xyz);
  typename Mesh::template Property_map<V, bool> fixed_map;
  if (detail::find_fixed_map(mesh, mo.fixed_property, fixed_map)) {
    bool any = false;
    std::vector<std::uint8_t> fixed(a.vertices.size(), 0);
    for (std::size_t i = 0; i < a.vertices.size(); ++i) {
      fixed[i] = get(fixed_map, a.vertices[i]) ? 1 : 0;
      any = any || fixed[i] != 0;
    }
    if (any) {
      a.fixed = std::move(fixed);
    }
  }
  return a;
}

/// Writes optimized 2D coordinates back: only vertices whose 2D position changed are set, to
/// their point of the mesh's plane.
template <class P>
void write_back(CGAL::Surface_mesh<P> &mesh, const Arrays<P> &a, const std::vector<double> &xy) {
  for (std::size_t i = 0; i < a.vertices.size(); ++i) {
    if (planar::same_bits(xy[2 * i], a.xy[2 * i]) && planar::same_bits(xy[2 * i + 1], a.xy[2 * i + 1])) {
      continue;
    }
    double q[3];
    a.frame.to_3d(&xy[2 * i], q);
    P &p = mesh.point(a.vertices[i]);
    p = detail::with_plane_point(p, q, a.frame);
  }
}

/// Optimizes `mesh` in place and returns the report (with per-kind statistics in input_quads,
/// input_triangles, output_quads, output_triangles). Throws Error (UnsupportedFace for a face of
/// five or more vertices, NotPlanar for a mesh that is not planar) and leaves the mesh
/// unchanged on any failure.
template <class P>
Report optimize(CGAL::Surface_mesh<P> &mesh, const Options &options = Options(), const MeshOptions &mo = MeshOptions()) {
  const Arrays<P> a = to_arrays(mesh, mo);
  std::vector<double> xy = a.xy;
  Report r = quadopt::optimize(xy, 2, a.quads, options, a.fixed);
  write_back(mesh, a, xy);
  return r;
}

/// Quality statistics of `mesh`, measured in its plane (and each face's scaled Jacobian in
/// `per_quad`, in face iteration order, when given). Throws as to_arrays() does.
template <class P>
Quality quality(const CGAL::Surface_mesh<P> &mesh, std::vector<double> *per_quad = nullptr) {
  MeshOptions mo;
  mo.fixed_property.clear();
  const Arrays<P> a = to_arrays(mesh, mo);
  return quadopt::quality(a.xy, 2, a.quads, per_quad);
}

/// The quality of `mesh`'s quads and of its triangles apart (count, min, avg of each), measured
/// in its plane. Throws as to_arrays() does.
template <class P>
ByFaceKind quality_by_kind(const CGAL::Surface_mesh<P> &mesh) {
  MeshOptions mo;
  mo.fixed_property.clear();
  const Arrays<P> a = to_arrays(mesh, mo);
  return quadopt::quality_by_kind(a.xy, 2, a.quads);
}

}  // namespace cgal
}  // namespace quadopt

#endif  // QUADOPT_CGAL_HPP
