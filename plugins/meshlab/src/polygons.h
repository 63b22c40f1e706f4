// SPDX-License-Identifier: GPL-3.0-or-later
//
// polygons.h: the polygons of a MeshLab mesh, as quadopt's face arrays.
//
// MeshLab holds a polygon mesh as triangles whose inner edges are marked faux (vcglib's
// "bit polygons"): a quad is two triangles sharing a faux edge. read_polygons() joins the
// triangles across their faux edges and walks each polygon's outline, giving quadopt's four
// slots per face (a quad's four vertices, or a triangle's three and QUADOPT_NO_VERTEX) and, for
// each polygon, the triangles it is made of (to write its quality back to each of them).
//
// The order is the one a polygon mesh had before MeshLab triangulated it: polygons in the order
// of their first triangle, each starting at that triangle's first vertex along its first
// non-faux edge, in the triangles' orientation. vcglib's PolygonSupport::ImportFromPolyMesh
// (used by MeshLab's importers and pymeshlab.Mesh(face_list_of_indices=...)) triangulates a quad
// a, b, c, d as (a b c)(a c d) or (a b d)(b c d), so the quad comes back as a, b, c, d: the
// optimizer sees the faces it would see in the original file. (vcglib's own ExtractPolygon walks
// the other way round and needs face-face adjacency; this walk needs neither.)
//
// Every walk is bounded by the polygon's triangle count, so inconsistent faux flags give an
// error instead of a loop, and no index is used before it is checked.
#ifndef QUADOPT_MESHLAB_POLYGONS_H
#define QUADOPT_MESHLAB_POLYGONS_H

#include <quadopt.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace quadopt_meshlab {

/// A mesh that the filter refuses (the message says why and names the face).
class MeshError : public std::runtime_error {
 public:
  explicit MeshError(const std::string &what) : std::runtime_error(what) {}
};

/// The polygons of a mesh as quadopt's arrays.
struct Polygons {
  /// quadopt's vertex index -> index in the mesh's vertex vector (its live vertices, in order).
  std::vector<std::size_t> mesh_vertex;
  /// Four slots per polygon (a triangle's fourth is quadopt::no_vertex), in quadopt's indices.
  std::vector<std::uint32_t> faces;
  /// The mesh triangles of polygon p: triangles[first[p]] .. triangles[first[p + 1] - 1].
  std::vector<std::size_t> first;
  std::vector<std::size_t> triangles;
  std::size_t quads = 0;
  std::size_t plain_triangles = 0;

  std::size_t polygon_count() const noexcept { return faces.size() / 4; }
};

namespace detail {

constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();

inline std::uint64_t edge_key(std::uint32_t from, std::uint32_t to) noexcept {
  return (static_cast<std::uint64_t>(from) << 32) | to;
}

inline std::string face_list(const std::vector<std::size_t> &tris, std::size_t begin, std::size_t end) {
  std::string s;
  const std::size_t shown = 8;
  for (std::size_t i = begin; i < end && i < begin + shown; ++i) {
    s += (i == begin ? "" : ", ") + std::to_string(tris[i]);
  }
  if (end - begin > shown) s += ", ...";
  return s;
}

}  // namespace detail

/// Reads the polygons of `m` (a vcglib triangle mesh: CMeshO). Throws MeshError for a mesh
/// without faux edges (a plain triangle mesh), a polygon of five or more vertices (naming its
/// first face, after counting them all), a polygon that is not a disc, and faux flags that do
/// not pair up.
template <class Mesh>
Polygons read_polygons(const Mesh &m) {
  using detail::kNone;
  Polygons out;
  const std::size_t nv = m.vert.size();
  const std::size_t nf = m.face.size();

  // Live vertices get quadopt's indices, in the mesh's order (pymeshlab's vertex_matrix order).
  std::vector<std::uint32_t> index(nv, quadopt::no_vertex);
  for (std::size_t i = 0; i < nv; ++i) {
    if (m.vert[i].IsD()) continue;
    if (out.mesh_vertex.size() >= static_cast<std::size_t>(quadopt::no_vertex)) {
      throw MeshError("the mesh has more vertices than quadopt's 32-bit indices can address");
    }
    index[i] = static_cast<std::uint32_t>(out.mesh_vertex.size());
    out.mesh_vertex.push_back(i);
  }
  const auto *base = nv > 0 ? &m.vert[0] : nullptr;
  // corner[3 f + k]: quadopt's index of face f's k-th vertex.
  std::vector<std::uint32_t> corner(3 * nf, quadopt::no_vertex);
  std::size_t live_faces = 0;
  for (std::size_t f = 0; f < nf; ++f) {
    if (m.face[f].IsD()) continue;
    ++live_faces;
    for (int k = 0; k < 3; ++k) {
      const auto *v = m.face[f].cV(k);
      const std::ptrdiff_t i = (v && base) ? v - base : -1;
      if (i < 0 || static_cast<std::size_t>(i) >= nv || index[static_cast<std::size_t>(i)] == quadopt::no_vertex) {
        throw MeshError("face " + std::to_string(f) + " refers to a vertex that is not in the mesh (or is deleted)");
      }
      corner[3 * f + k] = index[static_cast<std::size_t>(i)];
    }
  }
  if (live_faces == 0) {
    throw MeshError("the mesh has no faces; the filter optimizes quad and quad-dominant surface meshes");
  }

  // Every faux edge, by its directed vertex pair: its twin (the same edge in the neighbouring
  // triangle of the polygon) runs the other way.
  std::unordered_map<std::uint64_t, std::size_t> faux;  // key -> 3 f + k
  faux.reserve(2 * live_faces);
  for (std::size_t f = 0; f < nf; ++f) {
    if (m.face[f].IsD()) continue;
    for (int k = 0; k < 3; ++k) {
      if (!m.face[f].IsF(k)) continue;
      const std::uint64_t key = detail::edge_key(corner[3 * f + k], corner[3 * f + (k + 1) % 3]);
      if (!faux.emplace(key, 3 * f + static_cast<std::size_t>(k)).second) {
        throw MeshError("face " + std::to_string(f) +
                        ": its faux edge is shared with another triangle running the same way (a non-manifold or "
                        "inconsistently oriented polygon)");
      }
    }
  }
  if (faux.empty()) {
    throw MeshError(
        "the mesh is a plain triangle mesh (no faux edges): this filter optimizes quad and quad-dominant meshes, "
        "which MeshLab holds as triangles joined by faux edges. Open a polygonal file (OBJ, PLY or OFF with quads), "
        "or make quads first (Remeshing > Turn into Quad-Dominant mesh, or Tri to Quad by smart triangle pairing)");
  }
  // The triangle across face f's faux edge k, and that edge's index there.
  auto twin = [&](std::size_t f, int k) -> std::pair<std::size_t, int> {
    const auto it = faux.find(detail::edge_key(corner[3 * f + (k + 1) % 3], corner[3 * f + k]));
    if (it == faux.end()) {
      throw MeshError("face " + std::to_string(f) +
                      ": a faux edge whose neighbour does not mark it faux (or no neighbour): the faux flags do "
                      "not describe polygons");
    }
    return {it->second / 3, static_cast<int>(it->second % 3)};
  };

  std::vector<std::size_t> polygon_of(nf, kNone);
  std::vector<std::size_t> stack;
  std::size_t big = 0;  // polygons of five or more vertices
  std::string first_big;
  out.first.push_back(0);
  for (std::size_t f0 = 0; f0 < nf; ++f0) {
    if (m.face[f0].IsD() || polygon_of[f0] != kNone) continue;
    const std::size_t p = out.polygon_count();
    const std::size_t begin = out.triangles.size();
    // The triangles of the polygon: those reached from f0 across faux edges.
    polygon_of[f0] = p;
    stack.assign(1, f0);
    while (!stack.empty()) {
      const std::size_t f = stack.back();
      stack.pop_back();
      out.triangles.push_back(f);
      for (int k = 0; k < 3; ++k) {
        if (!m.face[f].IsF(k)) continue;
        const std::size_t g = twin(f, k).first;
        if (polygon_of[g] == kNone) {
          polygon_of[g] = p;
          stack.push_back(g);
        }
      }
    }
    std::sort(out.triangles.begin() + static_cast<std::ptrdiff_t>(begin), out.triangles.end());
    const std::size_t tris = out.triangles.size() - begin;

    // Its outline: from the first triangle with an outer edge, along that edge, each next edge
    // found by turning around the edge's end vertex across faux edges.
    std::size_t start_f = kNone;
    int start_k = 0;
    for (std::size_t i = begin; i < out.triangles.size() && start_f == kNone; ++i) {
      const std::size_t f = out.triangles[i];
      for (int k = 0; k < 3; ++k) {
        if (!m.face[f].IsF(k)) {
          start_f = f;
          start_k = k;
          break;
        }
      }
    }
    if (start_f == kNone) {
      throw MeshError("face " + std::to_string(f0) + ": a polygon whose edges are all faux (no outline)");
    }
    std::vector<std::uint32_t> loop;
    std::size_t f = start_f;
    int k = start_k;
    do {
      // A disc of t triangles has t + 2 outline edges; more means the flags do not close up.
      if (loop.size() > tris + 2) break;
      loop.push_back(corner[3 * f + k]);
      k = (k + 1) % 3;  // the edge of f that starts where edge k ends
      for (std::size_t turns = 0; m.face[f].IsF(k); ++turns) {
        if (turns > tris) {
          throw MeshError("face " + std::to_string(f) + ": faux edges that turn around a vertex without end");
        }
        const auto t = twin(f, k);
        f = t.first;
        k = (t.second + 1) % 3;
      }
    } while (f != start_f || k != start_k);
    if (loop.size() != tris + 2) {
      throw MeshError("faces " + detail::face_list(out.triangles, begin, out.triangles.size()) +
                      ": a polygon that is not a disc (its faux edges enclose a hole, or it touches itself)");
    }
    if (loop.size() >= 5) {
      if (big++ == 0) {
        first_big = "polygon " + std::to_string(p) + " (counting from 0 in face order; MeshLab faces " +
                    detail::face_list(out.triangles, begin, out.triangles.size()) + ") has " +
                    std::to_string(loop.size()) + " vertices";
      }
      loop.resize(4);  // keep the arrays' shape; the mesh is refused below
    }
    if (loop.size() == 4) {
      ++out.quads;
    } else {
      ++out.plain_triangles;
      loop.push_back(quadopt::no_vertex);
    }
    out.faces.insert(out.faces.end(), loop.begin(), loop.end());
    out.first.push_back(out.triangles.size());
  }
  if (big > 0) {
    throw MeshError(first_big + (big > 1 ? " (and " + std::to_string(big - 1) + " more such polygons)" : "") +
                    ": quadopt optimizes quads and triangles only; split the polygons of five or more sides into quads "
                    "or triangles first");
  }
  return out;
}

}  // namespace quadopt_meshlab

#endif  // QUADOPT_MESHLAB_POLYGONS_H
