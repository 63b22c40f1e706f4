// vcglib's polygon-mesh smoothers, as QuadWild uses them, as a peer for tools/bench_surfaces.py.
// Benchmark-only (see README.md here): it never links into quadopt's library.
// SPDX-License-Identifier: GPL-3.0-or-later (LICENSE here; vcglib's headers: GPL-2.0-or-later)
//
//   vcglib_polygonal IN.off OUT.xyz --method laplacian|pca [--iters N] [--damp D] [--repeat R]
//                    [--features DEG]
//
// Reads IN.off (ASCII OFF: triangles and quads, kept as they are in a vcglib polygon mesh,
// vertices in file order; this file's own reader), then R times: puts the input positions and
// flags back, and times (std::chrono::steady_clock) one call of
//   laplacian: vcg::PolygonalAlgorithm<PMesh>::LaplacianReproject(m, N, D, true)
//     N steps of area-weighted Laplace (each vertex moves by 1 - D towards the area-weighted mean
//     of its faces' other vertices) and of a reprojection halfway (vcglib's fixed 0.5) towards the
//     closest point of the guide surface, the input fan-triangulated around each face's
//     barycentre (built, with its grid, inside the call); only selected vertices move
//     (OnlyOnSelected, as QuadWild's QuadRetopology calls it: all selected but the held ones).
//   pca: vcg::PolygonalAlgorithm<PMesh>::SmoothReprojectPCA(m, N, true, D, 0, false, true)
//     N steps of SmoothPCA ("Statics Aware Grid Shells": each face's ideal template polygon
//     fitted and rotated onto the face, averaged per vertex with weight 1/area, blended with 0.1
//     Laplace, damped by D), each followed by a reprojection halfway (D) to the guide surface;
//     fixS (selected vertices held), SharpDeg 0 (vcglib's own sharp-edge handling, which lets
//     vertices slide along the line of a sharp edge, off), WeightByQuality false, FixB true.
// Held: boundary vertices, and with --features DEG every vertex on an edge whose dihedral angle
// (between the two faces' Newell normals) exceeds DEG degrees, as tools/peers/openmesh_jacobi.cpp
// holds them; marking them is set-up, outside the timer. Writes the positions of the last run to
// OUT.xyz, one vertex a line ("x y z", %.17g), and one JSON line on stdout:
// {"seconds": median, "times": [...], ...}.
#include <vcg/complex/complex.h>
#include <vcg/complex/algorithms/polygonal_algorithms.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <string>
#include <utility>
#include <vector>

class PVertex;
class PFace;

struct PUsedTypes : public vcg::UsedTypes<vcg::Use<PVertex>::AsVertexType, vcg::Use<PFace>::AsFaceType> {};

// The components QuadWild's polygon mesh has that these two algorithms use.
class PVertex : public vcg::Vertex<PUsedTypes, vcg::vertex::Coord3d, vcg::vertex::Normal3d, vcg::vertex::Mark,
                                   vcg::vertex::BitFlags, vcg::vertex::Qualityd> {};

class PFace : public vcg::Face<PUsedTypes, vcg::face::PolyInfo, vcg::face::PFVAdj, vcg::face::PFFAdj,
                               vcg::face::BitFlags, vcg::face::Normal3d, vcg::face::Qualityd, vcg::face::Mark> {};

class PMesh : public vcg::tri::TriMesh<std::vector<PVertex>, std::vector<PFace>> {};

typedef vcg::Point3d Vec;

static void die(const std::string& msg) {
  std::fprintf(stderr, "vcglib_polygonal: %s\n", msg.c_str());
  std::exit(1);
}

static Vec newell(const std::vector<Vec>& p, const std::vector<size_t>& f) {
  Vec n(0, 0, 0);
  for (size_t j = 0; j < f.size(); ++j) n += p[f[j]] ^ p[f[(j + 1) % f.size()]];
  return n;
}

int main(int argc, char** argv) {
  if (argc < 3)
    die("usage: vcglib_polygonal IN.off OUT.xyz --method laplacian|pca [--iters N] [--damp D] [--repeat R] "
        "[--features DEG]");
  std::string method;
  int iters = 10, repeat = 5;
  double damp = 0.5, features = -1.0;
  for (int i = 3; i < argc; ++i) {
    std::string a = argv[i];
    if (i + 1 >= argc) die("missing value for " + a);
    if (a == "--method") method = argv[++i];
    else if (a == "--iters") iters = std::atoi(argv[++i]);
    else if (a == "--damp") damp = std::atof(argv[++i]);
    else if (a == "--repeat") repeat = std::max(1, std::atoi(argv[++i]));
    else if (a == "--features") features = std::atof(argv[++i]);
    else die("unknown option " + a);
  }
  if (method != "laplacian" && method != "pca") die("--method must be laplacian or pca");

  std::ifstream in(argv[1]);
  std::string magic;
  size_t nv, nf, ne;
  if (!(in >> magic) || magic != "OFF" || !(in >> nv >> nf >> ne)) die("not an OFF file");
  std::vector<Vec> start(nv);
  for (size_t i = 0; i < nv; ++i)
    if (!(in >> start[i][0] >> start[i][1] >> start[i][2])) die("short vertex list");
  std::vector<std::vector<size_t>> faces(nf);
  for (size_t f = 0; f < nf; ++f) {
    size_t k;
    if (!(in >> k) || k < 3) die("bad face");
    faces[f].resize(k);
    for (size_t j = 0; j < k; ++j)
      if (!(in >> faces[f][j]) || faces[f][j] >= nv) die("bad face vertex");
  }

  // Held vertices: on a boundary edge (one face) or, with --features, on a sharp edge.
  std::map<std::pair<size_t, size_t>, std::vector<size_t>> edge_faces;
  for (size_t f = 0; f < nf; ++f)
    for (size_t j = 0; j < faces[f].size(); ++j) {
      size_t a = faces[f][j], b = faces[f][(j + 1) % faces[f].size()];
      edge_faces[std::make_pair(std::min(a, b), std::max(a, b))].push_back(f);
    }
  std::vector<bool> held(nv, false);
  size_t sharp_edges = 0, nonmanifold_edges = 0;
  double c = std::cos(features * M_PI / 180.0);
  for (const auto& e : edge_faces) {
    bool hold = e.second.size() == 1;
    nonmanifold_edges += e.second.size() > 2;
    if (e.second.size() == 2 && features >= 0) {
      Vec n0 = newell(start, faces[e.second[0]]), n1 = newell(start, faces[e.second[1]]);
      double l = n0.Norm() * n1.Norm();
      bool sharp = l == 0 || (n0 * n1) < c * l;
      sharp_edges += sharp;
      hold = hold || sharp;
    }
    if (hold) held[e.first.first] = held[e.first.second] = true;
  }
  if (nonmanifold_edges) die(std::to_string(nonmanifold_edges) + " edges with more than two faces");

  PMesh m;
  vcg::tri::Allocator<PMesh>::AddVertices(m, nv);
  vcg::tri::Allocator<PMesh>::AddFaces(m, nf);
  for (size_t f = 0; f < nf; ++f) {
    m.face[f].Alloc((int)faces[f].size());
    for (size_t j = 0; j < faces[f].size(); ++j) m.face[f].V((int)j) = &m.vert[faces[f][j]];
  }

  std::vector<double> times;
  for (int r = 0; r < repeat; ++r) {
    for (size_t i = 0; i < nv; ++i) m.vert[i].P() = start[i];
    // The state a caller sets up before the call: bounding box, face-face adjacency, border
    // flags, face normals, the selection.
    vcg::tri::UpdateBounding<PMesh>::Box(m);
    vcg::tri::UpdateTopology<PMesh>::FaceFace(m);
    vcg::tri::UpdateFlags<PMesh>::VertexBorderFromFaceAdj(m);
    vcg::PolygonalAlgorithm<PMesh>::UpdateFaceNormals(m);
    // LaplacianReproject moves the selected vertices (OnlyOnSelected), SmoothReprojectPCA holds
    // them (fixS).
    bool select_held = method == "pca";
    vcg::tri::UpdateSelection<PMesh>::VertexClear(m);
    for (size_t i = 0; i < nv; ++i)
      if (held[i] == select_held) m.vert[i].SetS();
    auto t0 = std::chrono::steady_clock::now();
    if (method == "laplacian")
      vcg::PolygonalAlgorithm<PMesh>::LaplacianReproject(m, iters, damp, true);
    else
      vcg::PolygonalAlgorithm<PMesh>::SmoothReprojectPCA(m, iters, true, damp, 0.0, false, true);
    auto t1 = std::chrono::steady_clock::now();
    times.push_back(std::chrono::duration<double>(t1 - t0).count());
  }

  FILE* out = std::fopen(argv[2], "w");
  if (!out) die("cannot write the output");
  for (size_t i = 0; i < nv; ++i) {
    const Vec& p = m.vert[i].cP();
    std::fprintf(out, "%.17g %.17g %.17g\n", p[0], p[1], p[2]);
  }
  std::fclose(out);
  size_t n_held = std::count(held.begin(), held.end(), true);
  std::vector<double> s = times;
  std::sort(s.begin(), s.end());
  double med = s.size() % 2 ? s[s.size() / 2] : (s[s.size() / 2 - 1] + s[s.size() / 2]) / 2;
  std::printf("{\"seconds\": %.9g, \"times\": [", med);
  for (size_t i = 0; i < times.size(); ++i) std::printf("%s%.9g", i ? ", " : "", times[i]);
  std::printf("], \"method\": \"%s\", \"iters\": %d, \"damp\": %g, \"feature_edges\": %zu, \"held\": %zu, "
              "\"vertices\": %zu, \"faces\": %zu}\n",
              method.c_str(), iters, damp, sharp_edges, n_held, nv, nf);
  return 0;
}
