// OpenMesh's JacobiLaplaceSmootherT as a peer for tools/bench_surfaces.py.
//
//   openmesh_jacobi IN.off OUT.xyz [--iters N] [--repeat R] [--features DEG]
//
// Reads IN.off (ASCII OFF: triangles and quads, kept as they are in an
// OpenMesh::PolyMesh_ArrayKernelT, vertices in file order; this file's own reader, so that no
// vertex is duplicated or dropped), then R times: puts the input positions back, and times
// (std::chrono::steady_clock) JacobiLaplaceSmootherT::initialize(Tangential, C0) + smooth(N):
// uniform-weight Laplace, each move projected onto the tangent plane of the vertex's original
// position (vertex normal of the input), boundary vertices held (OpenMesh never moves them).
// With --features DEG, edges whose dihedral angle (between the face normals) exceeds DEG
// degrees are marked as features and skip_features(true) holds every vertex on one (sharp edges
// and their corners stay). Writes the positions of the last run to OUT.xyz, one vertex a line
// ("x y z", %.17g), and one JSON line on stdout: {"seconds": median, "times": [...], ...}.
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Smoother/JacobiLaplaceSmootherT.hh>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

typedef OpenMesh::PolyMesh_ArrayKernelT<> Mesh;

static void die(const std::string& msg) {
  std::fprintf(stderr, "openmesh_jacobi: %s\n", msg.c_str());
  std::exit(1);
}

int main(int argc, char** argv) {
  if (argc < 3) die("usage: openmesh_jacobi IN.off OUT.xyz [--iters N] [--repeat R] [--features DEG]");
  unsigned iters = 10;
  int repeat = 5;
  double features = -1.0;
  for (int i = 3; i < argc; ++i) {
    std::string a = argv[i];
    if (i + 1 >= argc) die("missing value for " + a);
    if (a == "--iters") iters = (unsigned)std::atoi(argv[++i]);
    else if (a == "--repeat") repeat = std::max(1, std::atoi(argv[++i]));
    else if (a == "--features") features = std::atof(argv[++i]);
    else die("unknown option " + a);
  }

  std::ifstream in(argv[1]);
  std::string magic;
  size_t nv, nf, ne;
  if (!(in >> magic) || magic != "OFF" || !(in >> nv >> nf >> ne)) die("not an OFF file");
  Mesh mesh;
  std::vector<Mesh::VertexHandle> vh(nv);
  std::vector<Mesh::Point> start(nv);
  for (size_t i = 0; i < nv; ++i) {
    double x, y, z;
    if (!(in >> x >> y >> z)) die("short vertex list");
    start[i] = Mesh::Point(x, y, z);
    vh[i] = mesh.add_vertex(start[i]);
  }
  for (size_t f = 0; f < nf; ++f) {
    size_t k;
    if (!(in >> k) || k < 3) die("bad face");
    std::vector<Mesh::VertexHandle> fv(k);
    for (size_t j = 0; j < k; ++j) {
      size_t v;
      if (!(in >> v) || v >= nv) die("bad face vertex");
      fv[j] = vh[v];
    }
    if (!mesh.add_face(fv).is_valid()) die("OpenMesh refused face " + std::to_string(f) + " (non-manifold)");
  }

  mesh.request_vertex_status();
  mesh.request_edge_status();
  mesh.request_face_status();
  mesh.request_face_normals();

  std::vector<double> times;
  size_t held_features = 0;
  for (int r = 0; r < repeat; ++r) {
    for (size_t i = 0; i < nv; ++i) mesh.set_point(vh[i], start[i]);
    bool skip = false;
    if (features >= 0) {
      // Marking the features is setup, not smoothing: outside the timer.
      mesh.update_face_normals();
      double c = std::cos(features * M_PI / 180.0);
      held_features = 0;
      for (auto e : mesh.edges()) {
        bool sharp = false;
        if (!mesh.is_boundary(e)) {
          auto n0 = mesh.normal(mesh.face_handle(mesh.halfedge_handle(e, 0)));
          auto n1 = mesh.normal(mesh.face_handle(mesh.halfedge_handle(e, 1)));
          sharp = OpenMesh::dot(n0, n1) < c;
        }
        mesh.status(e).set_feature(sharp);
        held_features += sharp;
      }
      skip = true;
    }
    auto t0 = std::chrono::steady_clock::now();
    {
      OpenMesh::Smoother::JacobiLaplaceSmootherT<Mesh> smoother(mesh);
      smoother.skip_features(skip);
      smoother.initialize(OpenMesh::Smoother::JacobiLaplaceSmootherT<Mesh>::Tangential,
                          OpenMesh::Smoother::JacobiLaplaceSmootherT<Mesh>::C0);
      smoother.smooth(iters);
    }
    auto t1 = std::chrono::steady_clock::now();
    times.push_back(std::chrono::duration<double>(t1 - t0).count());
  }

  FILE* out = std::fopen(argv[2], "w");
  if (!out) die("cannot write the output");
  for (size_t i = 0; i < nv; ++i) {
    auto p = mesh.point(vh[i]);
    std::fprintf(out, "%.17g %.17g %.17g\n", p[0], p[1], p[2]);
  }
  std::fclose(out);
  std::vector<double> s = times;
  std::sort(s.begin(), s.end());
  double med = s.size() % 2 ? s[s.size() / 2] : (s[s.size() / 2 - 1] + s[s.size() / 2]) / 2;
  std::printf("{\"seconds\": %.9g, \"times\": [", med);
  for (size_t i = 0; i < times.size(); ++i) std::printf("%s%.9g", i ? ", " : "", times[i]);
  std::printf("], \"iters\": %u, \"feature_edges\": %zu, \"vertices\": %zu, \"faces\": %zu}\n", iters, held_features, nv, nf);
  return 0;
}
