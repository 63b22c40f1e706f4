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
// onto that plane. A Point_3 mesh that is not planar lies on a curved surface: optimize()
// optimizes it on that surface in 3D (quadopt::optimize_surface(); the report's `surface` is
// 1): every vertex stays on the input surface and a vertex on a feature curve on that curve.
// Only vertices whose position changed are written back, so fixed vertices, corners and
// vertices that did not move stay bit-identical.
//
// Feature curves (curved meshes only; the planar optimizer's only curve is the boundary): the
// boundary, edges whose faces' normals differ by more than the options' feature_angle_deg,
// and the marked edges: an edge property map of bool named MeshOptions::feature_property
// ("e:is_feature" by default, the map CGAL's get(CGAL::edge_is_feature, mesh) and
// Polygon_mesh_processing::detect_sharp_edges use), if the mesh has one, and
// MeshOptions::feature_edges.
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

#include <array>
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
  /// On a curved mesh: name of an edge property map of bool marking feature edges (ignored when
  /// absent; empty for none).
  std::string feature_property = "e:is_feature";
  /// On a curved mesh: more marked feature edges, as pairs of vertex indices of the mesh
  /// (std::size_t(vertex_index), in either order). A pair that is not an edge of the mesh
  /// throws Error with status QUADOPT_STATUS_INVALID_ARGUMENT naming it ("feature edge k" is
  /// its index here), a removed or out-of-range vertex QUADOPT_STATUS_INDEX_OUT_OF_RANGE.
  std::vector<std::array<std::size_t, 2>> feature_edges;
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
  /// Whether the mesh lies on a curved surface (only optimize() reads such a mesh; to_arrays()
  /// throws NotPlanar). Then `xy` is empty and `xyz` and `feature_edges` are filled.
  bool curved = false;
  /// For a curved mesh: x, y, z of every vertex, in the order of `vertices`.
  std::vector<double> xyz;
  /// For a curved mesh: the marked feature edges, two indices into `vertices` each
  /// (MeshOptions::feature_edges first, then the edges of the feature property map).
  std::vector<std::uint32_t> feature_edges;
};

namespace detail {

template <class P, class Key = typename CGAL::Surface_mesh<P>::Vertex_index>
bool find_fixed_map(const CGAL::Surface_mesh<P> &mesh, const std::string &name,
                    typename CGAL::Surface_mesh<P>::template Property_map<Key, bool> &out) {
  if (name.empty()) {
    return false;
  }
#if CGAL_VERSION_NR >= 1060000000
  auto found = mesh.template property_map<Key, bool>(name);
  if (!found) {
    return false;
  }
  out = *found;
  return true;
#else
  auto found = mesh.template property_map<Key, bool>(name);
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

/// to_arrays(), or with `allow_curved` a curved mesh read for optimize_surface().
template <class P>
Arrays<P> read(const CGAL::Surface_mesh<P> &mesh, const MeshOptions &mo, bool allow_curved) {
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
    try {
      a.frame = planar::Frame::fit(xyz, used, "CGAL", &names);
    } catch (const NotPlanar &) {
      if (!allow_curved) throw;
      a.curved = true;
    }
  }
  if (a.curved) {
    for (std::size_t k = 0; k < mo.feature_edges.size(); ++k) {
      for (std::size_t v : mo.feature_edges[k]) {
        if (v >= mesh.num_vertices() || mesh.is_removed(V(static_cast<typename V::size_type>(v)))) {
          throw Error(QUADOPT_STATUS_INDEX_OUT_OF_RANGE, "CGAL feature edge " + std::to_string(k) + " refers to vertex " +
                                                             std::to_string(v) + ", which is not a vertex of the mesh");
        }
        a.feature_edges.push_back(compact[v]);
      }
    }
    using E = typename Mesh::Edge_index;
    typename Mesh::template Property_map<E, bool> feature_map;
    if (find_fixed_map<P, E>(mesh, mo.feature_property, feature_map)) {
      for (E e : mesh.edges()) {
        if (!get(feature_map, e)) continue;
        const auto h = mesh.halfedge(e);
        a.feature_edges.push_back(compact[static_cast<std::size_t>(mesh.source(h))]);
        a.feature_edges.push_back(compact[static_cast<std::size_t>(mesh.target(h))]);
      }
    }
    a.xyz = std::move(xyz);
  } else {
    a.xy = a.frame.to_2d(xyz);
  }
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

}  // namespace detail

/// Reads `mesh` into flat arrays for the planar optimizer; throws UnsupportedFace on a face of
/// five or more vertices and NotPlanar on a Point_3 mesh that does not lie in a plane.
template <class P>
Arrays<P> to_arrays(const CGAL::Surface_mesh<P> &mesh, const MeshOptions &mo = MeshOptions()) {
  return detail::read(mesh, mo, false);
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

/// Writes the optimized 3D coordinates `xyz` of a curved mesh back: only vertices whose
/// position changed are set.
template <class P>
void write_back_surface(CGAL::Surface_mesh<P> &mesh, const Arrays<P> &a, const std::vector<double> &xyz) {
  using FT = typename CGAL::Kernel_traits<P>::Kernel::FT;
  if constexpr (CGAL::Ambient_dimension<P>::value == 3) {
    for (std::size_t i = 0; i < a.vertices.size(); ++i) {
      bool moved = false;
      for (std::size_t c = 0; c < 3; ++c) moved = moved || !planar::same_bits(xyz[3 * i + c], a.xyz[3 * i + c]);
      if (moved) mesh.point(a.vertices[i]) = P(FT(xyz[3 * i]), FT(xyz[3 * i + 1]), FT(xyz[3 * i + 2]));
    }
  } else {
    (void)mesh;
    (void)a;
    (void)xyz;
  }
}

/// Optimizes `mesh` in place and returns the report (with per-kind statistics in input_quads,
/// input_triangles, output_quads, output_triangles): a planar mesh in its plane, a curved one
/// on its surface in 3D (the report's `surface` is 1; feature curves as described above).
/// Throws Error (UnsupportedFace for a face of five or more vertices; status
/// QUADOPT_STATUS_INVALID_ARGUMENT for a marked feature edge that is not an edge) and leaves
/// the mesh unchanged on any failure.
template <class P>
Report optimize(CGAL::Surface_mesh<P> &mesh, const Options &options = Options(), const MeshOptions &mo = MeshOptions()) {
  const Arrays<P> a = detail::read(mesh, mo, true);
  if (a.curved) {
    std::vector<double> xyz = a.xyz;
    const Report r = quadopt::optimize_surface(
        xyz.data(), a.vertices.size(), a.quads.data(), a.quads.size() / 4, a.fixed.empty() ? nullptr : a.fixed.data(),
        a.feature_edges.empty() ? nullptr : a.feature_edges.data(), a.feature_edges.size() / 2, options);
    write_back_surface(mesh, a, xyz);
    return r;
  }
  std::vector<double> xy = a.xy;
  Report r = quadopt::optimize(xy, 2, a.quads, options, a.fixed);
  write_back(mesh, a, xy);
  return r;
}

/// Quality statistics of `mesh`, measured in its plane (and each face's scaled Jacobian in
/// `per_quad`, in face iteration order, when given). Throws as to_arrays() does (NotPlanar for a
/// curved mesh: its report from optimize() has its quality).
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
