// End-to-end tests on real mesh files: OpenMesh loads them (OBJ and OFF), CGAL extracts the
// boundary cycles of a Surface_mesh built from them, and quadopt runs through the C header,
// the C++ wrapper and the OpenMesh and CGAL adapters. Checked:
//
// - corners and fixed vertices are bit-identical after optimization;
// - every boundary vertex lies within 1e-9 * bbox diagonal of its original boundary cycle
//   (point-to-segment distance); with a fixed boundary it does not move at all;
// - quality improves (fewer inverted quads, or a higher minimum), and the report agrees with
//   quadopt_quality() of the result;
// - the adapters give bit for bit what the C call gives on the same arrays (OpenMesh's locked
//   and feature status and CGAL's "v:fixed" map acting as the fixed mask);
// - the Rust CLI (`quadopt optimize IN -o OUT --json`) gives bit for bit the same coordinates
//   and the same report numbers for the same file and options.
//
// Quad-dominant files (mixed_grid.obj, .off: quads and triangles) go through every check above,
// and also: the triangles stay triangles in the OpenMesh and CGAL meshes (every face keeps its
// vertices), the report's per-kind fields (input_quads, input_triangles, output_quads,
// output_triangles) are what quadopt::quality_by_kind() measures, and the CLI's JSON has the
// same per-kind numbers.
//
// With --faces: mixed.obj (two quads and a triangle) is optimized by both adapters, the
// triangle kept; a face of five vertices is refused (quadopt::UnsupportedFace naming it, the
// mesh unchanged).
//
// With --planes: meshes in a tilted plane (z = x + y) and in x = const are optimized in their
// plane (they stay in it to 1e-12 of the extent, quality improves, the result equals the
// CLI's bit for bit); for a curved mesh to_arrays() and quality() throw quadopt::NotPlanar
// naming its farthest vertex, and optimize() optimizes it on its surface.
//
// With --surface: quarter_cylinder.obj (a mesh on a curved surface) through OpenMesh (double
// and float points) and CGAL: better, on the cylinder within the chordal tolerance, boundary
// vertices on the original boundary polyline, corners bit-identical, the same as the C call;
// feature edges from OpenMesh's edge status, CGAL's "e:is_feature" map and explicit lists.
//
// Usage: mesh_tests DATA_DIR CLI TMP_DIR MESH_FILE   (or MESH_FILE = --faces, --planes or
// --surface)
#include "test_support.hpp"

#include <quadopt.h>
#include <quadopt.hpp>
#include <quadopt/cgal.hpp>
#include <quadopt/openmesh.hpp>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>

#include <cmath>
#include <cstdio>
#include <type_traits>
#include <set>
#include <string>
#include <vector>

namespace {

struct DoubleTraits : OpenMesh::DefaultTraits {
  typedef OpenMesh::Vec3d Point;
  typedef OpenMesh::Vec3d Normal;
};
using OMeshD = OpenMesh::PolyMesh_ArrayKernelT<DoubleTraits>;
using OMeshF = OpenMesh::PolyMesh_ArrayKernelT<>;  // the default traits: float points
using K = CGAL::Simple_cartesian<double>;
using SM3 = CGAL::Surface_mesh<K::Point_3>;
using Epick = CGAL::Exact_predicates_inexact_constructions_kernel;
using SM2 = CGAL::Surface_mesh<Epick::Point_2>;
namespace PMP = CGAL::Polygon_mesh_processing;

std::string g_data, g_cli, g_tmp;

template <class M>
M load(const std::string &path) {
  M m;
  OpenMesh::IO::Options opt;
  if (!OpenMesh::IO::read_mesh(m, path, opt)) throw std::runtime_error("OpenMesh cannot read " + path);
  return m;
}

/// A Surface_mesh with the same vertex indices as the arrays.
template <class SM, class MakePoint>
SM surface_mesh(const std::vector<double> &xy, const std::vector<std::uint32_t> &quads, MakePoint make) {
  SM sm;
  for (std::size_t i = 0; i < xy.size() / 2; ++i) sm.add_vertex(make(xy[2 * i], xy[2 * i + 1]));
  for (std::size_t q = 0; q < quads.size() / 4; ++q) {
    using V = typename SM::Vertex_index;
    const std::uint32_t *c = &quads[4 * q];
    const auto f = c[3] == QUADOPT_NO_VERTEX ? sm.add_face(V(c[0]), V(c[1]), V(c[2]))
                                             : sm.add_face(V(c[0]), V(c[1]), V(c[2]), V(c[3]));
    if (f == SM::null_face()) throw std::runtime_error("CGAL rejected face " + std::to_string(q));
  }
  return sm;
}

/// The four slots of every face of a Surface_mesh (vertex indices; a triangle's fourth is
/// QUADOPT_NO_VERTEX), in face order.
template <class SM>
std::vector<std::uint32_t> cgal_faces(const SM &sm) {
  std::vector<std::uint32_t> out;
  for (auto f : sm.faces()) {
    std::size_t k = 0;
    for (auto v : CGAL::vertices_around_face(sm.halfedge(f), sm)) {
      out.push_back(static_cast<std::uint32_t>(v));
      ++k;
    }
    if (k == 3) out.push_back(QUADOPT_NO_VERTEX);
  }
  return out;
}

/// The same of an OpenMesh mesh.
template <class M>
std::vector<std::uint32_t> openmesh_faces(const M &m) {
  std::vector<std::uint32_t> out;
  for (auto f : m.faces()) {
    std::size_t k = 0;
    for (auto v : m.fv_range(f)) {
      out.push_back(static_cast<std::uint32_t>(v.idx()));
      ++k;
    }
    if (k == 3) out.push_back(QUADOPT_NO_VERTEX);
  }
  return out;
}

SM3 surface_mesh3(const std::vector<double> &xy, const std::vector<std::uint32_t> &quads) {
  return surface_mesh<SM3>(xy, quads, [](double x, double y) { return K::Point_3(x, y, 0.0); });
}

/// Boundary cycles as vertex loops, from CGAL::Polygon_mesh_processing::extract_boundary_cycles.
std::vector<std::vector<std::uint32_t>> boundary_cycles(const SM3 &sm) {
  std::vector<SM3::Halfedge_index> starts;
  PMP::extract_boundary_cycles(sm, std::back_inserter(starts));
  std::vector<std::vector<std::uint32_t>> cycles;
  for (auto h : starts) {
    std::vector<std::uint32_t> c;
    for (auto hh : CGAL::halfedges_around_face(h, sm)) c.push_back(static_cast<std::uint32_t>(sm.source(hh)));
    cycles.push_back(c);
  }
  return cycles;
}

/// Turning angle (degrees, [0, 180]) of the boundary at each cycle vertex.
double turning_deg(const std::vector<double> &xy, std::uint32_t prev, std::uint32_t v, std::uint32_t next) {
  const double ax = xy[2 * v] - xy[2 * prev], ay = xy[2 * v + 1] - xy[2 * prev + 1];
  const double bx = xy[2 * next] - xy[2 * v], by = xy[2 * next + 1] - xy[2 * v + 1];
  return std::fabs(std::atan2(ax * by - ay * bx, ax * bx + ay * by)) * 180.0 / M_PI;
}

/// What a file looks like to the tests: arrays, boundary cycles, corners.
struct Case {
  std::string path;
  std::vector<double> xyz;  // as OpenMesh loaded them (z = 0 in our files)
  std::vector<double> xy;
  std::vector<std::uint32_t> quads;
  std::vector<std::vector<std::uint32_t>> cycles;
  std::vector<std::uint8_t> on_boundary;
  std::vector<std::uint32_t> corners;  // turning by more than 45 degrees
  double diag = 0;
  std::size_t n() const { return xy.size() / 2; }
  std::size_t nq() const { return quads.size() / 4; }
};

Case load_case(const std::string &file) {
  Case c;
  c.path = g_data + "/" + file;
  const OMeshD om = load<OMeshD>(c.path);
  for (auto v : om.vertices()) {
    const auto &p = om.point(v);
    c.xyz.insert(c.xyz.end(), {p[0], p[1], p[2]});
  }
  quadopt::openmesh::MeshOptions mo;
  const auto arrays = quadopt::openmesh::to_arrays(om, mo);
  c.xy = arrays.xy;
  c.quads = arrays.quads;
  CHECK(arrays.fixed.empty());
  // OpenMesh parses coordinates as float; the test files hold float values written with 17
  // digits, so the load is exact: compare with an exact parse of the OBJ twin of the file.
  const std::string obj = file.substr(0, file.rfind('.')) + ".obj";
  const qt::Mesh exact = qt::read_obj(g_data + "/" + obj);
  CHECK_MSG(qt::same_bits(c.xyz, exact.xyz), c.path << ": OpenMesh's coordinates differ from the file's");
  CHECK_MSG(c.quads == exact.quads, c.path << ": OpenMesh's face order differs from the file's");

  const SM3 sm = surface_mesh3(c.xy, c.quads);
  c.cycles = boundary_cycles(sm);
  c.on_boundary.assign(c.n(), 0);
  for (const auto &cyc : c.cycles) {
    for (std::size_t i = 0; i < cyc.size(); ++i) {
      const std::uint32_t prev = cyc[(i + cyc.size() - 1) % cyc.size()], v = cyc[i], next = cyc[(i + 1) % cyc.size()];
      c.on_boundary[v] = 1;
      const double t = turning_deg(c.xy, prev, v, next);
      CHECK_MSG(std::fabs(t - 45.0) > 1.0, "vertex " << v << " turns by " << t << " degrees, too close to call");
      if (t > 45.0) c.corners.push_back(v);
    }
  }
  c.diag = qt::bbox_diagonal(c.xy);
  return c;
}

/// Runs quadopt_optimize (C) on a dim-3 copy of the case's coordinates; returns x, y.
std::vector<double> run_c(const Case &c, const QuadoptOptions &o, const std::vector<std::uint8_t> &fixed,
                          QuadoptReport &report) {
  std::vector<double> xyz = c.xyz;
  for (std::size_t i = 0; i < c.n(); ++i) xyz[3 * i + 2] = -3.25;  // must come back untouched
  report = quadopt_report_init();
  const QuadoptStatus s = quadopt_optimize(xyz.data(), 3, c.n(), c.quads.data(), c.nq(),
                                           fixed.empty() ? nullptr : fixed.data(), &o, &report);
  CHECK_MSG(s == QUADOPT_STATUS_OK, c.path << ": " << quadopt_last_error());
  std::vector<double> xy(2 * c.n());
  bool z_ok = true;
  for (std::size_t i = 0; i < c.n(); ++i) {
    xy[2 * i] = xyz[3 * i];
    xy[2 * i + 1] = xyz[3 * i + 1];
    z_ok = z_ok && xyz[3 * i + 2] == -3.25;
  }
  CHECK(z_ok);
  return xy;
}

/// The properties every result must have.
void check_result(const Case &c, const std::string &what, const std::vector<double> &out, const QuadoptReport &r,
                  const std::vector<std::uint8_t> &fixed, bool fixed_boundary) {
  const std::string tag = c.path + " [" + what + "]";
  // Corners and fixed vertices: bit-identical.
  bool corners_ok = true;
  for (auto v : c.corners) {
    corners_ok = corners_ok && qt::same_bits(out[2 * v], c.xy[2 * v]) && qt::same_bits(out[2 * v + 1], c.xy[2 * v + 1]);
  }
  CHECK_MSG(corners_ok, tag << ": a corner moved");
  CHECK_MSG(r.corners == c.corners.size(), tag << ": report.corners " << r.corners << ", expected " << c.corners.size());
  std::size_t n_fixed = 0, n_moved = 0;
  bool fixed_ok = true;
  for (std::size_t i = 0; i < c.n(); ++i) {
    const bool same = qt::same_bits(out[2 * i], c.xy[2 * i]) && qt::same_bits(out[2 * i + 1], c.xy[2 * i + 1]);
    if (!fixed.empty() && fixed[i]) {
      ++n_fixed;
      fixed_ok = fixed_ok && same;
    }
    if (!same) ++n_moved;
    if (fixed_boundary && c.on_boundary[i]) fixed_ok = fixed_ok && same;
  }
  CHECK_MSG(fixed_ok, tag << ": a fixed vertex moved");
  CHECK_MSG(n_moved > 0, tag << ": nothing moved");
  // Boundary vertices stay on their original boundary cycle.
  double worst = 0;
  for (const auto &cyc : c.cycles) {
    for (auto v : cyc) {
      double d = HUGE_VAL;
      for (std::size_t i = 0; i < cyc.size(); ++i) {
        const std::uint32_t a = cyc[i], b = cyc[(i + 1) % cyc.size()];
        d = std::fmin(d, qt::point_segment_distance(out[2 * v], out[2 * v + 1], c.xy[2 * a], c.xy[2 * a + 1],
                                                    c.xy[2 * b], c.xy[2 * b + 1]));
      }
      worst = std::fmax(worst, d);
    }
  }
  CHECK_MSG(worst <= 1e-9 * c.diag, tag << ": a boundary vertex is " << worst << " off the original boundary");
  // Quality: the report is what quadopt_quality measures, and the result is better.
  QuadoptQuality before{}, after{};
  CHECK(quadopt_quality(c.xy.data(), 2, c.n(), c.quads.data(), c.nq(), &before, nullptr, 0) == QUADOPT_STATUS_OK);
  CHECK(quadopt_quality(out.data(), 2, c.n(), c.quads.data(), c.nq(), &after, nullptr, 0) == QUADOPT_STATUS_OK);
  CHECK_MSG(qt::same_bits(r.input.min, before.min) && qt::same_bits(r.input.avg, before.avg) &&
                r.input.inverted == before.inverted,
            tag << ": report.input differs from quadopt_quality");
  CHECK_MSG(qt::same_bits(r.output.min, after.min) && qt::same_bits(r.output.avg, after.avg) &&
                r.output.inverted == after.inverted,
            tag << ": report.output differs from quadopt_quality");
  const bool better = after.inverted < before.inverted || (after.inverted == before.inverted && after.min > before.min);
  CHECK_MSG(better, tag << ": min " << before.min << " -> " << after.min << ", inverted " << before.inverted << " -> "
                        << after.inverted);
  CHECK_MSG(after.inverted == 0, tag << ": " << after.inverted << " quads still inverted");
  CHECK_MSG(after.avg > before.avg, tag << ": average " << before.avg << " -> " << after.avg);
  (void)n_fixed;
}

/// The library's default options (quadopt_options_init for this header's struct).
QuadoptOptions default_options() {
  QuadoptOptions o;
  const QuadoptStatus s = quadopt_options_init(&o, sizeof o);
  CHECK_MSG(s == QUADOPT_STATUS_OK, "quadopt_options_init: " << quadopt_status_string(s));
  return o;
}

QuadoptOptions with_boundary(std::uint32_t b) {
  QuadoptOptions o = default_options();
  o.boundary = b;
  return o;
}

/// A fixed mask: every third interior vertex and the first vertex of each boundary cycle's
/// second half.
std::vector<std::uint8_t> some_fixed(const Case &c) {
  std::vector<std::uint8_t> f(c.n(), 0);
  std::size_t k = 0;
  for (std::size_t i = 0; i < c.n(); ++i) {
    if (!c.on_boundary[i] && k++ % 3 == 0) f[i] = 1;
  }
  for (const auto &cyc : c.cycles) f[cyc[cyc.size() / 2 + 1]] = 1;
  return f;
}

void test_c_api(const Case &c) {
  const std::uint32_t modes[4] = {QUADOPT_BOUNDARY_AUTO, QUADOPT_BOUNDARY_SLIDE, QUADOPT_BOUNDARY_SNAP,
                                  QUADOPT_BOUNDARY_FIXED};
  const char *names[4] = {"auto", "slide", "snap", "fixed"};
  for (int m = 0; m < 4; ++m) {
    QuadoptReport r;
    const auto out = run_c(c, with_boundary(modes[m]), {}, r);
    check_result(c, std::string("C, ") + names[m], out, r, {}, modes[m] == QUADOPT_BOUNDARY_FIXED);
    CHECK(r.loops_slide + r.loops_snap + r.loops_fixed == c.cycles.size());
    if (modes[m] == QUADOPT_BOUNDARY_SLIDE) CHECK(r.loops_slide == c.cycles.size());
    if (modes[m] == QUADOPT_BOUNDARY_SNAP) CHECK(r.loops_snap == c.cycles.size());
  }
  const auto fixed = some_fixed(c);
  QuadoptReport r;
  const auto out = run_c(c, default_options(), fixed, r);
  check_result(c, "C, fixed mask", out, r, fixed, false);
  // The C++ wrapper on dim-2 arrays gives the same as the C call on dim-3 arrays.
  std::vector<double> xy = c.xy;
  const quadopt::Report rw = quadopt::optimize(xy, 2, c.quads, quadopt::Options(), fixed);
  CHECK_MSG(qt::same_bits(xy, out), c.path << ": C++ wrapper differs from C at " << qt::first_difference(xy, out));
  CHECK(rw.iterations == r.iterations && qt::same_bits(rw.final_energy, r.final_energy));
}

void test_openmesh_adapter(const Case &c) {
  QuadoptReport ref_r;
  const auto ref = run_c(c, default_options(), {}, ref_r);

  // Double points: bit-identical to the C call.
  OMeshD om = load<OMeshD>(c.path);
  const quadopt::Report r = quadopt::openmesh::optimize(om);
  bool same = true, z_same = true;
  for (auto v : om.vertices()) {
    const auto i = static_cast<std::size_t>(v.idx());
    same = same && qt::same_bits(om.point(v)[0], ref[2 * i]) && qt::same_bits(om.point(v)[1], ref[2 * i + 1]);
    z_same = z_same && qt::same_bits(om.point(v)[2], c.xyz[3 * i + 2]);
  }
  CHECK_MSG(same, c.path << ": OpenMesh (double) adapter differs from the C call");
  CHECK(z_same && r.iterations == ref_r.iterations && r.corners == ref_r.corners);
  CHECK_MSG(openmesh_faces(om) == c.quads, c.path << ": the OpenMesh mesh's faces changed (triangles kept?)");
  const quadopt::Quality q = quadopt::openmesh::quality(om);
  CHECK(qt::same_bits(q.min, ref_r.output.min) && q.inverted == 0);

  // Float points (OpenMesh's default traits): the C result rounded to float; unmoved vertices
  // keep their bits (float -> double -> float is exact).
  OMeshF fm = load<OMeshF>(c.path);
  quadopt::openmesh::optimize(fm);
  same = true;
  for (auto v : fm.vertices()) {
    const auto i = static_cast<std::size_t>(v.idx());
    same = same && fm.point(v)[0] == static_cast<float>(ref[2 * i]) &&
           fm.point(v)[1] == static_cast<float>(ref[2 * i + 1]) && fm.point(v)[2] == 0.0f;
  }
  CHECK_MSG(same, c.path << ": OpenMesh (float) adapter is not the C result rounded to float");
  CHECK_MSG(openmesh_faces(fm) == c.quads, c.path << ": the OpenMesh (float) mesh's faces changed");

  // Locked and feature vertices are fixed.
  const auto mask = some_fixed(c);
  OMeshD locked = load<OMeshD>(c.path);
  locked.request_vertex_status();
  std::vector<std::uint8_t> locked_only(c.n(), 0);
  int k = 0;
  for (std::size_t i = 0; i < c.n(); ++i) {
    if (!mask[i]) continue;
    const OMeshD::VertexHandle vh(static_cast<int>(i));
    if (k++ % 2 == 0) {
      locked.status(vh).set_locked(true);
      locked_only[i] = 1;
    } else {
      locked.status(vh).set_feature(true);
    }
  }
  OMeshD locked2 = locked;
  quadopt::openmesh::optimize(locked);
  QuadoptReport rr;
  const auto want = run_c(c, default_options(), mask, rr);
  same = true;
  for (std::size_t i = 0; i < c.n(); ++i) {
    const auto &p = locked.point(OMeshD::VertexHandle(static_cast<int>(i)));
    same = same && qt::same_bits(p[0], want[2 * i]) && qt::same_bits(p[1], want[2 * i + 1]);
  }
  CHECK_MSG(same, c.path << ": locked + feature vertices are not treated as the fixed mask");
  std::vector<double> got(2 * c.n());
  for (std::size_t i = 0; i < c.n(); ++i) {
    const auto &p = locked.point(OMeshD::VertexHandle(static_cast<int>(i)));
    got[2 * i] = p[0];
    got[2 * i + 1] = p[1];
  }
  check_result(c, "OpenMesh locked/feature", got, rr, mask, false);
  // feature_is_fixed = false: only the locked ones.
  quadopt::openmesh::MeshOptions mo;
  mo.feature_is_fixed = false;
  quadopt::openmesh::optimize(locked2, quadopt::Options(), mo);
  const auto want2 = run_c(c, default_options(), locked_only, rr);
  same = true;
  for (std::size_t i = 0; i < c.n(); ++i) {
    const auto &p = locked2.point(OMeshD::VertexHandle(static_cast<int>(i)));
    same = same && qt::same_bits(p[0], want2[2 * i]) && qt::same_bits(p[1], want2[2 * i + 1]);
  }
  CHECK_MSG(same, c.path << ": feature_is_fixed = false still fixes feature vertices");

  // Options pass through the adapter.
  OMeshD slide = load<OMeshD>(c.path);
  quadopt::openmesh::optimize(slide, quadopt::Options().boundary(quadopt::Boundary::Slide).method(quadopt::Method::Laplacian));
  QuadoptOptions so = with_boundary(QUADOPT_BOUNDARY_SLIDE);
  so.method = QUADOPT_METHOD_LAPLACIAN;
  const auto want3 = run_c(c, so, {}, rr);
  same = true;
  for (std::size_t i = 0; i < c.n(); ++i) {
    const auto &p = slide.point(OMeshD::VertexHandle(static_cast<int>(i)));
    same = same && qt::same_bits(p[0], want3[2 * i]) && qt::same_bits(p[1], want3[2 * i + 1]);
  }
  CHECK_MSG(same, c.path << ": options did not reach the library through the OpenMesh adapter");
}

void test_cgal_adapter(const Case &c) {
  QuadoptReport ref_r;
  const auto ref = run_c(c, default_options(), {}, ref_r);

  // Surface_mesh<Point_3>, z kept.
  SM3 sm = surface_mesh<SM3>(c.xy, c.quads, [](double x, double y) { return K::Point_3(x, y, 2.5); });
  const quadopt::Report r = quadopt::cgal::optimize(sm);
  bool same = true;
  for (auto v : sm.vertices()) {
    const auto i = static_cast<std::size_t>(v);
    same = same && qt::same_bits(sm.point(v).x(), ref[2 * i]) && qt::same_bits(sm.point(v).y(), ref[2 * i + 1]) &&
           sm.point(v).z() == 2.5;
  }
  CHECK_MSG(same, c.path << ": CGAL Point_3 adapter differs from the C call");
  CHECK_MSG(cgal_faces(sm) == c.quads, c.path << ": the CGAL mesh's faces changed (triangles kept?)");
  CHECK(r.iterations == ref_r.iterations && qt::same_bits(quadopt::cgal::quality(sm).min, ref_r.output.min));

  // Surface_mesh<Point_2> of another kernel, with a removed (garbage) vertex in the middle of
  // the index range: skipped, and the result is unchanged.
  SM2 sm2;
  std::vector<SM2::Vertex_index> vs;
  SM2::Vertex_index extra;
  for (std::size_t i = 0; i < c.n(); ++i) {
    if (i == c.n() / 2) extra = sm2.add_vertex(Epick::Point_2(1e30, -1e30));
    vs.push_back(sm2.add_vertex(Epick::Point_2(c.xy[2 * i], c.xy[2 * i + 1])));
  }
  for (std::size_t q = 0; q < c.nq(); ++q) {
    const std::uint32_t *f = &c.quads[4 * q];
    if (f[3] == QUADOPT_NO_VERTEX) {
      sm2.add_face(vs[f[0]], vs[f[1]], vs[f[2]]);
    } else {
      sm2.add_face(vs[f[0]], vs[f[1]], vs[f[2]], vs[f[3]]);
    }
  }
  sm2.remove_vertex(extra);
  CHECK(sm2.has_garbage());
  quadopt::cgal::optimize(sm2);
  same = true;
  for (std::size_t i = 0; i < c.n(); ++i) {
    same = same && qt::same_bits(sm2.point(vs[i]).x(), ref[2 * i]) && qt::same_bits(sm2.point(vs[i]).y(), ref[2 * i + 1]);
  }
  CHECK_MSG(same, c.path << ": CGAL Point_2 adapter (with garbage) differs from the C call");

  // A "v:fixed" property map is the fixed mask.
  const auto mask = some_fixed(c);
  SM3 fm = surface_mesh3(c.xy, c.quads);
  auto fixed_map = fm.add_property_map<SM3::Vertex_index, bool>("v:fixed", false).first;
  for (std::size_t i = 0; i < c.n(); ++i) fixed_map[SM3::Vertex_index(static_cast<SM3::size_type>(i))] = mask[i] != 0;
  quadopt::cgal::optimize(fm, quadopt::Options().boundary(quadopt::Boundary::Snap));
  QuadoptReport rr;
  const auto want = run_c(c, with_boundary(QUADOPT_BOUNDARY_SNAP), mask, rr);
  same = true;
  std::vector<double> got(2 * c.n());
  for (std::size_t i = 0; i < c.n(); ++i) {
    const auto &p = fm.point(SM3::Vertex_index(static_cast<SM3::size_type>(i)));
    same = same && qt::same_bits(p.x(), want[2 * i]) && qt::same_bits(p.y(), want[2 * i + 1]);
    got[2 * i] = p.x();
    got[2 * i + 1] = p.y();
  }
  CHECK_MSG(same, c.path << ": the v:fixed map is not the fixed mask");
  check_result(c, "CGAL v:fixed, snap", got, rr, mask, false);
  // Another property name: the map is ignored unless named.
  SM3 pm = surface_mesh3(c.xy, c.quads);
  auto pin = pm.add_property_map<SM3::Vertex_index, bool>("v:pinned", false).first;
  for (std::size_t i = 0; i < c.n(); ++i) pin[SM3::Vertex_index(static_cast<SM3::size_type>(i))] = mask[i] != 0;
  SM3 pm2 = pm;
  quadopt::cgal::optimize(pm);  // "v:fixed" absent: nothing fixed
  quadopt::cgal::MeshOptions cmo;
  cmo.fixed_property = "v:pinned";
  quadopt::cgal::optimize(pm2, quadopt::Options(), cmo);
  const auto want_free = run_c(c, default_options(), {}, rr);
  const auto want_pinned = run_c(c, default_options(), mask, rr);
  bool same_free = true, same_pinned = true;
  for (std::size_t i = 0; i < c.n(); ++i) {
    const SM3::Vertex_index v(static_cast<SM3::size_type>(i));
    same_free = same_free && qt::same_bits(pm.point(v).x(), want_free[2 * i]);
    same_pinned = same_pinned && qt::same_bits(pm2.point(v).x(), want_pinned[2 * i]) &&
                  qt::same_bits(pm2.point(v).y(), want_pinned[2 * i + 1]);
  }
  CHECK(same_free && same_pinned);
}

struct CliCase {
  const char *args;
  QuadoptOptions options;
};

void test_cli(const Case &c) {
  std::vector<CliCase> cases;
  QuadoptOptions o = default_options();
  cases.push_back({"", o});
  cases.push_back({"--boundary slide", with_boundary(QUADOPT_BOUNDARY_SLIDE)});
  cases.push_back({"--boundary snap", with_boundary(QUADOPT_BOUNDARY_SNAP)});
  o = with_boundary(QUADOPT_BOUNDARY_FIXED);
  o.method = QUADOPT_METHOD_LAPLACIAN;
  cases.push_back({"--boundary fixed --method laplace", o});
  o = default_options();
  o.method = QUADOPT_METHOD_COTANGENT;
  o.max_iterations = 7;
  cases.push_back({"--method cotan --max-iter 7", o});
  o = default_options();
  o.method = QUADOPT_METHOD_ANGLE_BASED;
  o.lambda = 0.5;
  cases.push_back({"--method angle --lambda 0.5", o});
  o = with_boundary(QUADOPT_BOUNDARY_SLIDE);  // Options::paper() with --boundary slide
  o.stop_rule = QUADOPT_STOP_RULE_ENERGY;
  o.tau = 1e-4;
  o.tau_absolute = 1;
  o.guard = 0;
  o.untangle = 0;
  o.keep_best = 0;
  o.max_min = 0;
  cases.push_back({"--paper --boundary slide", o});
  o = default_options();
  o.guard = 0;
  o.stop_rule = QUADOPT_STOP_RULE_ENERGY;  // --tau implies the energy rule
  o.tau = 1e-9;
  o.feature_angle_deg = 30;
  o.max_boundary_deviation = 0.5;
  cases.push_back({"--no-guard --tau 1e-9 --feature-angle 30 --max-boundary-deviation 0.5", o});
  o = default_options();
  o.guard_floor = 0.2;
  o.untangle = 0;
  o.stop_rule = QUADOPT_STOP_RULE_ENERGY;
  o.tau_absolute = 1;
  o.tau = 1e-6;
  cases.push_back({"--guard-floor 0.2 --no-untangle --absolute-tau --tau 1e-6", o});

  const std::string base = c.path.substr(c.path.rfind('/') + 1);
  int k = 0;
  for (const auto &cc : cases) {
    const std::string out = g_tmp + "/cli_" + base + "_" + std::to_string(k) + ".obj";
    const std::string json_file = g_tmp + "/cli_" + base + "_" + std::to_string(k) + ".json";
    ++k;
    std::remove(out.c_str());
    const std::string cmd = "\"" + g_cli + "\" optimize \"" + c.path + "\" -o \"" + out + "\" --json " + cc.args;
    const int rc = qt::run(cmd, json_file);
    CHECK_MSG(rc == 0, cmd << " exited with " << rc);
    if (rc != 0) continue;
    const std::string json = qt::slurp(json_file);
    const qt::Mesh cli = qt::read_obj(out);
    QuadoptReport r;
    const auto mine = run_c(c, cc.options, {}, r);
    CHECK_MSG(cli.quads == c.quads, cmd << ": the CLI changed the connectivity");
    const auto cli_xy = cli.xy();
    CHECK_MSG(qt::same_bits(cli_xy, mine),
              cmd << ": coordinates differ from the C call, first at index " << qt::first_difference(cli_xy, mine));
    bool z_zero = true;
    for (std::size_t i = 0; i < cli.vertices(); ++i) z_zero = z_zero && cli.xyz[3 * i + 2] == 0.0;
    CHECK(z_zero);
    CHECK_MSG(qt::json_number(json, "iterations") == static_cast<double>(r.iterations),
              cmd << ": iterations " << qt::json_number(json, "iterations") << " vs " << r.iterations);
    CHECK(qt::json_number(json, "corners") == static_cast<double>(r.corners));
    CHECK(qt::json_number(json, "movable") == static_cast<double>(r.movable));
    CHECK(qt::same_bits(qt::json_number(json, "min", "output"), r.output.min));
    CHECK(qt::same_bits(qt::json_number(json, "avg", "output"), r.output.avg));
    CHECK(qt::same_bits(qt::json_number(json, "min", "input"), r.input.min));
    CHECK(qt::json_number(json, "inverted", "output") == static_cast<double>(r.output.inverted));
    CHECK((json.find("\"converged\":true") != std::string::npos) == (r.converged != 0));
    if (r.input_triangles.count > 0) {
      // The per-kind statistics: the same numbers as the C report's.
      for (const char *stage : {"input_by_kind", "output_by_kind"}) {
        const bool in = stage[0] == 'i';
        const QuadoptFaceKindQuality &kq = in ? r.input_quads : r.output_quads;
        const QuadoptFaceKindQuality &kt = in ? r.input_triangles : r.output_triangles;
        CHECK_MSG(qt::json_number_in(json, {stage, "quads"}, "count") == static_cast<double>(kq.count) &&
                      qt::same_bits(qt::json_number_in(json, {stage, "quads"}, "min"), kq.min) &&
                      qt::same_bits(qt::json_number_in(json, {stage, "quads"}, "avg"), kq.avg),
                  cmd << ": " << stage << ".quads differs from the C report");
        CHECK_MSG(qt::json_number_in(json, {stage, "triangles"}, "count") == static_cast<double>(kt.count) &&
                      qt::same_bits(qt::json_number_in(json, {stage, "triangles"}, "min"), kt.min) &&
                      qt::same_bits(qt::json_number_in(json, {stage, "triangles"}, "avg"), kt.avg),
                  cmd << ": " << stage << ".triangles differs from the C report");
      }
    }
  }
}

bool same_kind(const QuadoptFaceKindQuality &a, const QuadoptFaceKindQuality &b) {
  return a.count == b.count && qt::same_bits(a.min, b.min) && qt::same_bits(a.avg, b.avg);
}

/// A quad-dominant file: the report's per-kind fields through the C API, the C++ wrapper and
/// both adapters, and a run with every triangle's vertices fixed.
void test_face_kinds(const Case &c) {
  std::size_t nt = 0;
  for (std::size_t f = 0; f < c.nq(); ++f) nt += c.quads[4 * f + 3] == QUADOPT_NO_VERTEX ? 1 : 0;
  CHECK_MSG(nt > 0 && nt < c.nq(), c.path << ": " << nt << " triangles among " << c.nq() << " faces");
  QuadoptReport r;
  const auto out = run_c(c, default_options(), {}, r);
  const quadopt::ByFaceKind in_k = quadopt::quality_by_kind(c.xy, 2, c.quads);
  const quadopt::ByFaceKind out_k = quadopt::quality_by_kind(out, 2, c.quads);
  CHECK(r.input_quads.count == c.nq() - nt && r.input_triangles.count == nt);
  CHECK(r.output_quads.count == c.nq() - nt && r.output_triangles.count == nt);
  CHECK_MSG(same_kind(r.input_quads, in_k.quads) && same_kind(r.input_triangles, in_k.triangles),
            c.path << ": report input_* differ from quality_by_kind: quads " << r.input_quads.min << " vs "
                   << in_k.quads.min << ", triangles " << r.input_triangles.min << " vs " << in_k.triangles.min);
  CHECK_MSG(same_kind(r.output_quads, out_k.quads) && same_kind(r.output_triangles, out_k.triangles),
            c.path << ": report output_* differ from quality_by_kind");
  const quadopt::ByFaceKind ri = quadopt::input_by_kind(r), ro = quadopt::output_by_kind(r);
  CHECK(same_kind(ri.quads, r.input_quads) && same_kind(ri.triangles, r.input_triangles) &&
        same_kind(ro.quads, r.output_quads) && same_kind(ro.triangles, r.output_triangles));
  // The overall statistics are the two kinds together.
  CHECK(qt::same_bits(std::fmin(r.input_quads.min, r.input_triangles.min), r.input.min));
  CHECK(qt::same_bits(std::fmin(r.output_quads.min, r.output_triangles.min), r.output.min));
  const double avg = (r.output_quads.avg * static_cast<double>(r.output_quads.count) +
                      r.output_triangles.avg * static_cast<double>(nt)) /
                     static_cast<double>(c.nq());
  CHECK_MSG(std::fabs(avg - r.output.avg) <= 1e-12, c.path << ": per-kind averages " << avg << " vs " << r.output.avg);
  // make_data.py inverts a quad and a triangle; the result has neither.
  CHECK_MSG(r.input_quads.min <= 0 && r.input_triangles.min <= 0 && r.output_quads.min > 0 &&
                r.output_triangles.min > 0,
            c.path << ": quads " << r.input_quads.min << " -> " << r.output_quads.min << ", triangles "
                   << r.input_triangles.min << " -> " << r.output_triangles.min);

  // The adapters report the same, and measure the same afterwards.
  OMeshD om = load<OMeshD>(c.path);
  const quadopt::ByFaceKind om_before = quadopt::openmesh::quality_by_kind(om);
  const quadopt::Report omr = quadopt::openmesh::optimize(om);
  const quadopt::ByFaceKind om_after = quadopt::openmesh::quality_by_kind(om);
  CHECK(same_kind(om_before.quads, r.input_quads) && same_kind(om_before.triangles, r.input_triangles));
  CHECK(same_kind(omr.output_quads, r.output_quads) && same_kind(omr.output_triangles, r.output_triangles));
  CHECK(same_kind(om_after.quads, r.output_quads) && same_kind(om_after.triangles, r.output_triangles));
  SM3 sm = surface_mesh3(c.xy, c.quads);
  const quadopt::Report cr = quadopt::cgal::optimize(sm);
  CHECK(same_kind(cr.input_triangles, r.input_triangles) && same_kind(cr.output_triangles, r.output_triangles));
  CHECK(same_kind(quadopt::cgal::quality_by_kind(sm).triangles, r.output_triangles));

  // Every vertex of a triangle fixed: those vertices keep their bits, so the triangles keep
  // their quality exactly, and nothing gets more inverted.
  std::vector<std::uint8_t> tri_fixed(c.n(), 0);
  for (std::size_t f = 0; f < c.nq(); ++f) {
    if (c.quads[4 * f + 3] != QUADOPT_NO_VERTEX) continue;
    for (int k = 0; k < 3; ++k) tri_fixed[c.quads[4 * f + k]] = 1;
  }
  QuadoptReport rf;
  const auto fixed_out = run_c(c, default_options(), tri_fixed, rf);
  bool kept = true;
  for (std::size_t i = 0; i < c.n(); ++i) {
    if (tri_fixed[i]) {
      kept = kept && qt::same_bits(fixed_out[2 * i], c.xy[2 * i]) &&
             qt::same_bits(fixed_out[2 * i + 1], c.xy[2 * i + 1]);
    }
  }
  CHECK_MSG(kept, c.path << ": a vertex of a fixed triangle moved");
  CHECK(same_kind(rf.output_triangles, rf.input_triangles));
  CHECK_MSG(rf.output.inverted <= rf.input.inverted && rf.output_quads.avg > rf.input_quads.avg,
            c.path << ": triangles fixed: inverted " << rf.input.inverted << " -> " << rf.output.inverted
                   << ", quads' average " << rf.input_quads.avg << " -> " << rf.output_quads.avg);
}

template <class M>
std::vector<double> openmesh_points(const M &m);
std::vector<double> cgal_points(const SM3 &sm);

/// `fn` must throw quadopt::UnsupportedFace for face `face` of five vertices of `library`
/// ("<library> face <face> has 5 vertices"); it is also a NonQuadFace, the former name.
template <class Fn>
void expect_pentagon_refused(const std::string &what, Fn fn, std::size_t face, const std::string &library) {
  bool thrown = false;
  std::string message = "no exception";
  try {
    fn();
  } catch (const quadopt::NonQuadFace &e) {
    message = e.what();
    const std::string named = library + " face " + std::to_string(face) + " has 5 vertices";
    thrown = e.face() == face && e.valence() == 5 && e.status() == QUADOPT_STATUS_INVALID_ARGUMENT &&
             message.find(named) != std::string::npos;
  } catch (const std::exception &e) {
    message = e.what();
  }
  CHECK_MSG(thrown, what << ": expected UnsupportedFace for " << library << " face " << face << ", got: " << message);
}

void test_faces() {
  static_assert(std::is_same<quadopt::NonQuadFace, quadopt::UnsupportedFace>::value, "the former name");
  // mixed.obj: two quads and a triangle, every vertex on the boundary. Accepted by both
  // adapters, the triangle kept, the result the C call's.
  const std::string path = g_data + "/mixed.obj";
  const qt::Mesh exact = qt::read_obj(path);
  const std::vector<std::uint32_t> want_faces = {0, 1, 4, 3, 1, 2, 5, 4, 3, 4, 6, QUADOPT_NO_VERTEX};
  CHECK(exact.quads == want_faces);
  std::vector<double> ref = exact.xy();
  QuadoptReport ref_r = quadopt_report_init();
  CHECK(quadopt_optimize(ref.data(), 2, exact.vertices(), exact.quads.data(), exact.quad_count(), nullptr, nullptr,
                         &ref_r) == QUADOPT_STATUS_OK);
  CHECK(ref_r.input_quads.count == 2 && ref_r.input_triangles.count == 1 && ref_r.output_triangles.count == 1);
  CHECK(ref_r.output.inverted == 0 && ref_r.output.min >= ref_r.input.min);

  OMeshD om = load<OMeshD>(path);
  CHECK(om.n_faces() == 3);
  const quadopt::openmesh::Arrays arrays = quadopt::openmesh::to_arrays(om);
  CHECK(arrays.quads == want_faces);
  const quadopt::Report r = quadopt::openmesh::optimize(om);
  CHECK_MSG(openmesh_faces(om) == want_faces, "mixed.obj: the OpenMesh mesh's faces changed");
  bool same = true;
  for (auto v : om.vertices()) {
    const auto i = static_cast<std::size_t>(v.idx());
    same = same && qt::same_bits(om.point(v)[0], ref[2 * i]) && qt::same_bits(om.point(v)[1], ref[2 * i + 1]);
  }
  CHECK_MSG(same, "mixed.obj: the OpenMesh adapter differs from the C call");
  CHECK(r.input_triangles.count == 1 && same_kind(r.output_triangles, ref_r.output_triangles));
  OMeshF fm = load<OMeshF>(path);
  CHECK(quadopt::openmesh::quality(fm).inverted == 0);
  quadopt::openmesh::optimize(fm);
  CHECK(openmesh_faces(fm) == want_faces);

  SM3 sm = surface_mesh3(exact.xy(), exact.quads);
  const quadopt::Report cr = quadopt::cgal::optimize(sm);
  CHECK_MSG(cgal_faces(sm) == want_faces, "mixed.obj: the CGAL mesh's faces changed");
  same = true;
  for (auto v : sm.vertices()) {
    const auto i = static_cast<std::size_t>(v);
    same = same && qt::same_bits(sm.point(v).x(), ref[2 * i]) && qt::same_bits(sm.point(v).y(), ref[2 * i + 1]);
  }
  CHECK_MSG(same, "mixed.obj: the CGAL adapter differs from the C call");
  CHECK(cr.output_triangles.count == 1);

  // A pentagon as the third face (face 2): refused, naming it, the mesh unchanged.
  const std::vector<double> pts = {0, 0, 1, 0, 2, 0, 0, 1, 1, 1, 2, 1, 0.5, 2, 1.5, 2.5, 2, 2};
  OMeshD pm;
  std::vector<OMeshD::VertexHandle> vh;
  for (std::size_t i = 0; i < pts.size() / 2; ++i) {
    vh.push_back(pm.add_vertex(OMeshD::Point(pts[2 * i], pts[2 * i + 1], 0)));
  }
  pm.add_face(std::vector<OMeshD::VertexHandle>{vh[0], vh[1], vh[4], vh[3]});
  pm.add_face(std::vector<OMeshD::VertexHandle>{vh[1], vh[2], vh[5], vh[4]});
  pm.add_face(std::vector<OMeshD::VertexHandle>{vh[3], vh[4], vh[8], vh[7], vh[6]});
  pm.add_face(std::vector<OMeshD::VertexHandle>{vh[4], vh[5], vh[8]});
  CHECK(pm.n_faces() == 4 && pm.valence(OMeshD::FaceHandle(2)) == 5);
  const std::vector<double> om_before = openmesh_points(pm);
  expect_pentagon_refused("OpenMesh, optimize", [&] { quadopt::openmesh::optimize(pm); }, 2, "OpenMesh");
  expect_pentagon_refused("OpenMesh, quality", [&] { quadopt::openmesh::quality(pm); }, 2, "OpenMesh");
  CHECK_MSG(qt::same_bits(openmesh_points(pm), om_before), "OpenMesh: a refused mesh was changed");
  SM3 ps;
  std::vector<SM3::Vertex_index> sv;
  for (std::size_t i = 0; i < pts.size() / 2; ++i) {
    sv.push_back(ps.add_vertex(K::Point_3(pts[2 * i], pts[2 * i + 1], 0)));
  }
  ps.add_face(sv[0], sv[1], sv[4], sv[3]);
  ps.add_face(sv[1], sv[2], sv[5], sv[4]);
  ps.add_face(std::vector<SM3::Vertex_index>{sv[3], sv[4], sv[8], sv[7], sv[6]});
  ps.add_face(sv[4], sv[5], sv[8]);
  CHECK(ps.number_of_faces() == 4);
  const std::vector<double> cgal_before = cgal_points(ps);
  expect_pentagon_refused("CGAL, optimize", [&] { quadopt::cgal::optimize(ps); }, 2, "CGAL");
  expect_pentagon_refused("CGAL, quality", [&] { quadopt::cgal::quality(ps); }, 2, "CGAL");
  CHECK_MSG(qt::same_bits(cgal_points(ps), cgal_before), "CGAL: a refused mesh was changed");

  // A quad mesh whose fixed flags come with the wrong length.
  const Case c = load_case("plate_hole.obj");
  OMeshD plate = load<OMeshD>(c.path);
  quadopt::openmesh::MeshOptions mo;
  mo.fixed.assign(3, 1);
  CHECK_THROWS_STATUS(quadopt::openmesh::optimize(plate, quadopt::Options(), mo), QUADOPT_STATUS_INVALID_ARGUMENT);
  // Errors from the library surface as quadopt::Error through the adapters.
  CHECK_THROWS_STATUS(quadopt::openmesh::optimize(plate, quadopt::Options().lambda(2.0)), QUADOPT_STATUS_INVALID_OPTION);
  SM3 psm = surface_mesh3(c.xy, c.quads);
  CHECK_THROWS_STATUS(quadopt::cgal::optimize(psm, quadopt::Options().max_iterations(0)), QUADOPT_STATUS_INVALID_OPTION);
}

// --- Meshes in other planes (issue 8, item 9) ------------------------------------------------

/// An n x n grid of unit cells in 2D (s, t) with its interior vertices jittered by up to
/// `amount` (a fixed pseudo-random sequence), and its quads.
struct Grid2 {
  int n = 0;
  std::vector<double> st;
  std::vector<std::uint32_t> quads;
  std::size_t vertices() const { return st.size() / 2; }
  bool is_corner(std::size_t v) const {
    const std::size_t i = v % (n + 1), j = v / (n + 1);
    return (i == 0 || i == static_cast<std::size_t>(n)) && (j == 0 || j == static_cast<std::size_t>(n));
  }
  bool on_boundary(std::size_t v) const {
    const std::size_t i = v % (n + 1), j = v / (n + 1);
    return i == 0 || j == 0 || i == static_cast<std::size_t>(n) || j == static_cast<std::size_t>(n);
  }
};

Grid2 jittered_st(int n, double amount) {
  Grid2 g;
  g.n = n;
  std::uint64_t state = 12345;
  auto next = [&state]() {  // in [-1, 1)
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) / static_cast<double>(1ULL << 52) - 1.0;
  };
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const bool interior = i > 0 && j > 0 && i < n && j < n;
      const double ds = amount * next(), dt = amount * next();
      g.st.push_back(i + (interior ? ds : 0.0));
      g.st.push_back(j + (interior ? dt : 0.0));
    }
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const std::uint32_t a = static_cast<std::uint32_t>(j * (n + 1) + i);
      const std::uint32_t w = static_cast<std::uint32_t>(n) + 1;
      g.quads.insert(g.quads.end(), {a, a + 1, a + w + 1, a + w});
    }
  }
  return g;
}

/// The grid mapped into 3D by `f(s, t, out)`: x, y, z per vertex.
template <class F>
std::vector<double> embed(const Grid2 &g, F f) {
  std::vector<double> xyz(3 * g.vertices());
  for (std::size_t v = 0; v < g.vertices(); ++v) f(g.st[2 * v], g.st[2 * v + 1], &xyz[3 * v]);
  return xyz;
}

template <class M>
M openmesh_from(const std::vector<double> &xyz, const std::vector<std::uint32_t> &quads) {
  M m;
  using Scalar = std::decay_t<decltype(std::declval<typename M::Point &>()[0])>;
  std::vector<typename M::VertexHandle> vh;
  for (std::size_t i = 0; i < xyz.size() / 3; ++i) {
    vh.push_back(m.add_vertex(typename M::Point(static_cast<Scalar>(xyz[3 * i]), static_cast<Scalar>(xyz[3 * i + 1]),
                                                static_cast<Scalar>(xyz[3 * i + 2]))));
  }
  for (std::size_t q = 0; q < quads.size() / 4; ++q) {
    m.add_face(std::vector<typename M::VertexHandle>{vh[quads[4 * q]], vh[quads[4 * q + 1]], vh[quads[4 * q + 2]],
                                                     vh[quads[4 * q + 3]]});
  }
  return m;
}

template <class M>
std::vector<double> openmesh_points(const M &m) {
  std::vector<double> xyz;
  for (auto v : m.vertices()) {
    const auto &p = m.point(v);
    xyz.insert(xyz.end(), {static_cast<double>(p[0]), static_cast<double>(p[1]), static_cast<double>(p[2])});
  }
  return xyz;
}

SM3 cgal_from(const std::vector<double> &xyz, const std::vector<std::uint32_t> &quads) {
  SM3 sm;
  for (std::size_t i = 0; i < xyz.size() / 3; ++i) {
    sm.add_vertex(K::Point_3(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]));
  }
  for (std::size_t q = 0; q < quads.size() / 4; ++q) {
    using V = SM3::Vertex_index;
    sm.add_face(V(quads[4 * q]), V(quads[4 * q + 1]), V(quads[4 * q + 2]), V(quads[4 * q + 3]));
  }
  return sm;
}

std::vector<double> cgal_points(const SM3 &sm) {
  std::vector<double> xyz;
  for (auto v : sm.vertices()) xyz.insert(xyz.end(), {sm.point(v).x(), sm.point(v).y(), sm.point(v).z()});
  return xyz;
}

/// Distance from p to the segment [a, b] in 3D.
double distance3(const double *p, const double *a, const double *b) {
  double d[3], w[3];
  double dd = 0, wd = 0;
  for (int c = 0; c < 3; ++c) {
    d[c] = b[c] - a[c];
    w[c] = p[c] - a[c];
    dd += d[c] * d[c];
    wd += w[c] * d[c];
  }
  const double t = dd > 0 ? std::fmin(1.0, std::fmax(0.0, wd / dd)) : 0.0;
  double r = 0;
  for (int c = 0; c < 3; ++c) r += (w[c] - t * d[c]) * (w[c] - t * d[c]);
  return std::sqrt(r);
}

/// The grid's boundary loop (vertex indices, in order).
std::vector<std::uint32_t> grid_boundary(const Grid2 &g) {
  std::vector<std::uint32_t> loop;
  const std::uint32_t n = static_cast<std::uint32_t>(g.n), w = n + 1;
  for (std::uint32_t i = 0; i < n; ++i) loop.push_back(i);
  for (std::uint32_t j = 0; j < n; ++j) loop.push_back(j * w + n);
  for (std::uint32_t i = n; i > 0; --i) loop.push_back(n * w + i);
  for (std::uint32_t j = n; j > 0; --j) loop.push_back(j * w);
  return loop;
}

/// What a result in the plane z = x + y must satisfy: every vertex within `tol` (relative to
/// the extent) of the plane and of the original boundary (boundary vertices), corners
/// bit-identical, something moved.
void check_tilted(const std::string &tag, const Grid2 &g, const std::vector<double> &before,
                  const std::vector<double> &after, double extent, double tol) {
  double off_plane = 0;
  bool corners_same = true;
  std::size_t moved = 0;
  for (std::size_t v = 0; v < g.vertices(); ++v) {
    const double *p = &after[3 * v];
    off_plane = std::fmax(off_plane, std::fabs(p[2] - p[0] - p[1]) / std::sqrt(3.0));
    const bool same = qt::same_bits(p[0], before[3 * v]) && qt::same_bits(p[1], before[3 * v + 1]) &&
                      qt::same_bits(p[2], before[3 * v + 2]);
    if (g.is_corner(v)) corners_same = corners_same && same;
    moved += same ? 0 : 1;
  }
  CHECK_MSG(off_plane <= tol * extent,
            tag << ": a vertex is " << off_plane / extent << " (relative) off the plane z = x + y");
  CHECK_MSG(corners_same, tag << ": a corner moved");
  CHECK_MSG(moved > 0, tag << ": nothing moved");
  const auto loop = grid_boundary(g);
  double worst = 0;
  for (auto v : loop) {
    double d = HUGE_VAL;
    for (std::size_t i = 0; i < loop.size(); ++i) {
      d = std::fmin(d, distance3(&after[3 * v], &before[3 * loop[i]], &before[3 * loop[(i + 1) % loop.size()]]));
    }
    worst = std::fmax(worst, d);
  }
  CHECK_MSG(worst <= tol * extent,
            tag << ": a boundary vertex is " << worst / extent << " (relative) off the boundary");
}

void write_obj(const std::string &path, const std::vector<double> &xyz, const std::vector<std::uint32_t> &quads) {
  std::FILE *f = std::fopen(path.c_str(), "w");
  if (!f) throw std::runtime_error("cannot write " + path);
  for (std::size_t i = 0; i < xyz.size() / 3; ++i) {
    std::fprintf(f, "v %.17g %.17g %.17g\n", xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
  }
  for (std::size_t q = 0; q < quads.size() / 4; ++q) {
    const std::uint32_t *c = &quads[4 * q];
    std::fprintf(f, "f %u %u %u %u\n", c[0] + 1, c[1] + 1, c[2] + 1, c[3] + 1);
  }
  std::fclose(f);
}

void test_tilted_plane() {
  const Grid2 g = jittered_st(8, 0.35);
  const auto tilted = [](double s, double t, double *p) {
    p[0] = s;
    p[1] = t;
    p[2] = s + t;
  };
  const std::vector<double> xyz = embed(g, tilted);
  const double extent = 8.0 * std::sqrt(3.0);

  // OpenMesh, double points: in the plane, better in the plane's own metric.
  OMeshD om = openmesh_from<OMeshD>(xyz, g.quads);
  const quadopt::Quality q0 = quadopt::openmesh::quality(om);
  const quadopt::Report r = quadopt::openmesh::optimize(om);
  const quadopt::Quality q1 = quadopt::openmesh::quality(om);
  const std::vector<double> om_out = openmesh_points(om);
  check_tilted("OpenMesh double, z = x + y", g, xyz, om_out, extent, 1e-12);
  CHECK_MSG(q0.inverted > 0 && q1.inverted == 0 && q1.min > 0.5 && q1.avg > q0.avg,
            "tilted plane: quality " << q0.min << "/" << q0.avg << " -> " << q1.min << "/" << q1.avg);
  CHECK_MSG(std::fabs(r.output.min - q1.min) < 1e-12 && std::fabs(r.input.min - q0.min) < 1e-12,
            "tilted plane: report " << r.input.min << " -> " << r.output.min << ", measured " << q0.min << " -> "
                                    << q1.min);

  // The same as the command-line tool, bit for bit.
  const std::string in = g_tmp + "/tilted_in.obj", out = g_tmp + "/tilted_out.obj";
  write_obj(in, xyz, g.quads);
  std::remove(out.c_str());
  const int rc = qt::run("\"" + g_cli + "\" optimize \"" + in + "\" -o \"" + out + "\"", g_tmp + "/tilted.log");
  CHECK_MSG(rc == 0, "the CLI failed on the tilted mesh");
  if (rc == 0) {
    const qt::Mesh cli = qt::read_obj(out);
    CHECK_MSG(qt::same_bits(cli.xyz, om_out), "tilted plane: the OpenMesh adapter differs from the CLI at coordinate "
                                                  << qt::first_difference(cli.xyz, om_out));
  }

  // CGAL Point_3: the same result.
  SM3 sm = cgal_from(xyz, g.quads);
  quadopt::cgal::optimize(sm);
  CHECK_MSG(qt::same_bits(cgal_points(sm), om_out), "tilted plane: CGAL differs from OpenMesh");
  CHECK(std::fabs(quadopt::cgal::quality(sm).min - q1.min) < 1e-12);

  // OpenMesh, float points: moved vertices rounded to float, so within float precision.
  OMeshF fm = openmesh_from<OMeshF>(xyz, g.quads);
  const std::vector<double> fxyz = openmesh_points(fm);
  quadopt::openmesh::optimize(fm);
  check_tilted("OpenMesh float, z = x + y", g, fxyz, openmesh_points(fm), extent, 1e-6);

  // At 1e150 and 1e-150 the same result, relative to the scale: the positions for the sweeps
  // (continuous in the coordinates), the quality for the default run, whose max-min stage can
  // take another greedy path after a rounding difference (the README's 1e-3).
  quadopt::Options sweeps;
  sweeps.max_min(false);
  OMeshD um = openmesh_from<OMeshD>(xyz, g.quads);
  quadopt::openmesh::optimize(um, sweeps);
  const std::vector<double> unit_sweeps = openmesh_points(um);
  for (double scale : {1e150, 1e-150}) {
    std::vector<double> big = xyz;
    for (auto &c : big) c *= scale;
    OMeshD bm = openmesh_from<OMeshD>(big, g.quads);
    quadopt::openmesh::optimize(bm, sweeps);
    const auto got = openmesh_points(bm);
    check_tilted("OpenMesh double, z = x + y, scaled", g, big, got, extent * scale, 1e-12);
    double worst = 0;
    for (std::size_t i = 0; i < got.size(); ++i)
      worst = std::fmax(worst, std::fabs(got[i] / scale - unit_sweeps[i]));
    CHECK_MSG(worst <= 1e-9, "tilted plane x" << scale << ": " << worst << " (relative) from the unit-scale result");
    OMeshD dm = openmesh_from<OMeshD>(big, g.quads);
    quadopt::openmesh::optimize(dm);
    check_tilted("OpenMesh double, z = x + y, scaled, default", g, big, openmesh_points(dm), extent * scale, 1e-12);
    const quadopt::Quality qd = quadopt::openmesh::quality(dm);
    CHECK_MSG(qd.inverted == q1.inverted && std::fabs(qd.min - q1.min) <= 1e-3 && std::fabs(qd.avg - q1.avg) <= 1e-3,
              "tilted plane x" << scale << ", default: " << qd.min << "/" << qd.avg << " vs " << q1.min << "/"
                               << q1.avg);
  }
}

void test_axis_planes() {
  // The plane x = 3: y and z are the 2D coordinates, exactly; x is never touched.
  const Grid2 g = jittered_st(6, 0.3);
  const std::vector<double> xyz = embed(g, [](double s, double t, double *p) {
    p[0] = 3.0;
    p[1] = s;
    p[2] = t;
  });
  OMeshD om = openmesh_from<OMeshD>(xyz, g.quads);
  quadopt::openmesh::optimize(om);
  SM3 sm = cgal_from(xyz, g.quads);
  quadopt::cgal::optimize(sm);
  std::vector<double> want = g.st;
  quadopt::optimize(want, 2, g.quads);
  bool same = true;
  const auto got = openmesh_points(om), got_cgal = cgal_points(sm);
  for (std::size_t v = 0; v < g.vertices(); ++v) {
    same = same && got[3 * v] == 3.0 && qt::same_bits(got[3 * v + 1], want[2 * v]) &&
           qt::same_bits(got[3 * v + 2], want[2 * v + 1]);
  }
  CHECK_MSG(same, "plane x = 3: the OpenMesh adapter is not the 2D optimization of (y, z)");
  CHECK_MSG(qt::same_bits(got, got_cgal), "plane x = 3: CGAL differs from OpenMesh");
}

/// `fn` must throw NotPlanar naming a vertex for which `expected` holds, in its message too.
template <class Fn, class Expected>
void expect_not_planar(const std::string &what, Fn fn, Expected expected) {
  bool thrown = false;
  std::string message = "no exception";
  try {
    fn();
  } catch (const quadopt::NotPlanar &e) {
    message = e.what();
    thrown = e.status() == QUADOPT_STATUS_NOT_PLANAR && expected(e.vertex()) && e.distance() > e.tolerance() &&
             message.find("not planar") != std::string::npos &&
             message.find("vertex " + std::to_string(e.vertex()) + " ") != std::string::npos;
  } catch (const std::exception &e) {
    message = e.what();
  }
  CHECK_MSG(thrown, what << ": expected NotPlanar naming the right vertex, got: " << message);
}

void test_curved() {
  const Grid2 g = jittered_st(6, 0.2);
  // A paraboloid cap: the best-fit plane is horizontal (by symmetry) at the mean height, about
  // 0.4 above the centre and 0.5 below the corners, so a corner is the farthest vertex.
  const std::vector<double> xyz = embed(g, [](double s, double t, double *p) {
    p[0] = s;
    p[1] = t;
    p[2] = 0.05 * ((s - 3) * (s - 3) + (t - 3) * (t - 3));
  });
  const auto corner = [&g](std::size_t v) { return g.is_corner(v); };
  // to_arrays() (the planar optimizer's arrays) and quality() refuse it; optimize() optimizes
  // it on its surface.
  OMeshD om = openmesh_from<OMeshD>(xyz, g.quads);
  expect_not_planar("OpenMesh, paraboloid", [&] { quadopt::openmesh::to_arrays(om); }, corner);
  CHECK_THROWS_STATUS(quadopt::openmesh::quality(om), QUADOPT_STATUS_NOT_PLANAR);
  CHECK_MSG(qt::same_bits(openmesh_points(om), xyz), "OpenMesh: a refused mesh was changed");
  const quadopt::Report ro = quadopt::openmesh::optimize(om);
  CHECK(quadopt::on_surface(ro) && ro.output.min >= ro.input.min && ro.max_distance < 1e-9);
  SM3 sm = cgal_from(xyz, g.quads);
  expect_not_planar("CGAL, paraboloid", [&] { quadopt::cgal::to_arrays(sm); }, corner);
  CHECK_THROWS_STATUS(quadopt::cgal::quality(sm), QUADOPT_STATUS_NOT_PLANAR);
  CHECK_MSG(qt::same_bits(cgal_points(sm), xyz), "CGAL: a refused mesh was changed");
  const quadopt::Report rc = quadopt::cgal::optimize(sm);
  CHECK(quadopt::on_surface(rc) && rc.output.min >= rc.input.min);
  CHECK_MSG(qt::same_bits(cgal_points(sm), openmesh_points(om)), "CGAL and OpenMesh differ on a surface");

  // The library's one planarity rule (quadopt_is_planar(), the CLI's and the C ABI's too): one
  // vertex 1e-4 or 1e-7 (as in float files) of the diagonal off the tilted plane is a surface,
  // refused by to_arrays() naming it and optimized on its surface by optimize(), never
  // flattened; 1e-14 (rounding) is planar.
  const std::vector<double> flat = embed(g, [](double s, double t, double *p) {
    p[0] = s;
    p[1] = t;
    p[2] = s + t;
  });
  const double diag = 6.0 * std::sqrt(3.0);
  const std::size_t bumped = 2 * 7 + 4;
  for (double off : {1e-4, 1e-7}) {
    std::vector<double> bump = flat;
    bump[3 * bumped + 2] += off * diag;
    OMeshD bm = openmesh_from<OMeshD>(bump, g.quads);
    expect_not_planar("OpenMesh, one vertex off the plane", [&] { quadopt::openmesh::to_arrays(bm); },
                      [bumped](std::size_t v) { return v == bumped; });
    SM3 bs = cgal_from(bump, g.quads);
    expect_not_planar("CGAL, one vertex off the plane", [&] { quadopt::cgal::to_arrays(bs); },
                      [bumped](std::size_t v) { return v == bumped; });
    const quadopt::Report rb = quadopt::openmesh::optimize(bm);
    CHECK_MSG(quadopt::on_surface(rb) && rb.max_distance_relative <= 1e-9,
              "a mesh " << off << " of its diagonal off its plane: surface " << quadopt::on_surface(rb)
                        << ", distance " << rb.max_distance_relative);
  }
  std::vector<double> noise = flat;
  noise[3 * bumped + 2] += 1e-14 * diag;
  OMeshD nm = openmesh_from<OMeshD>(noise, g.quads);
  bool accepted = true;
  try {
    quadopt::openmesh::to_arrays(nm);
  } catch (const std::exception &e) {
    accepted = false;
    std::cerr << e.what() << "\n";
  }
  CHECK_MSG(accepted, "a mesh 1e-14 of its diagonal off its plane (rounding) is not planar");
}

/// What a result on data/quarter_cylinder.obj (the cylinder x^2 + y^2 = 4, 9 x 7 vertices,
/// vertex 9 j + i) must satisfy: better, every vertex on the cylinder within the chordal
/// tolerance (the sagitta of the input's widest face) and `tol`, every boundary vertex on the
/// original boundary polyline (CGAL's boundary cycles) within `tol`, the four corners
/// bit-identical, something moved.
void check_on_cylinder(const std::string &tag, const std::vector<double> &before, const std::vector<double> &after,
                       const std::vector<std::uint32_t> &quads, const quadopt::Report &r, double tol) {
  CHECK_MSG(quadopt::on_surface(r), tag << ": not a surface run");
  CHECK_MSG(r.output.min > r.input.min && r.output.inverted == 0,
            tag << ": min " << r.input.min << " -> " << r.output.min << ", inverted " << r.output.inverted);
  double chord = 0;
  for (std::size_t f = 0; f < quads.size() / 4; ++f) {
    double lo = 10, hi = -10;
    for (int k = 0; k < 4; ++k) {
      const double *p = &before[3 * quads[4 * f + k]];
      lo = std::fmin(lo, std::atan2(p[1], p[0]));
      hi = std::fmax(hi, std::atan2(p[1], p[0]));
    }
    chord = std::fmax(chord, 2.0 * (1.0 - std::cos((hi - lo) / 2)));
  }
  const std::size_t n = before.size() / 3;
  bool on = true;
  for (std::size_t v = 0; v < n; ++v) {
    const double off = std::hypot(after[3 * v], after[3 * v + 1]) - 2.0;
    on = on && off <= tol && -off <= chord + tol;
  }
  CHECK_MSG(on, tag << ": a vertex left the cylinder (chordal tolerance " << chord << ")");
  const auto cycles = boundary_cycles(cgal_from(before, quads));
  CHECK_MSG(cycles.size() == 1 && cycles[0].size() == 28, tag << ": the boundary is not one loop of 28 vertices");
  double worst = 0;
  for (const auto &cyc : cycles) {
    for (std::uint32_t v : cyc) {
      double d = 1e300;
      for (std::size_t i = 0; i < cyc.size(); ++i) {
        d = std::fmin(d, distance3(&after[3 * v], &before[3 * cyc[i]], &before[3 * cyc[(i + 1) % cyc.size()]]));
      }
      worst = std::fmax(worst, d);
    }
  }
  CHECK_MSG(worst <= tol, tag << ": a boundary vertex is " << worst << " off the original boundary");
  for (std::uint32_t c : {0u, 8u, 54u, 62u}) {
    CHECK_MSG(qt::same_bits(after[3 * c], before[3 * c]) && qt::same_bits(after[3 * c + 1], before[3 * c + 1]) &&
                  qt::same_bits(after[3 * c + 2], before[3 * c + 2]),
              tag << ": corner " << c << " moved");
  }
  CHECK_MSG(!qt::same_bits(after, before), tag << ": nothing moved");
}

/// The OpenMesh and CGAL adapters on a mesh on a curved surface, read from an OBJ file.
void test_surface_meshes() {
  const std::string path = g_data + "/quarter_cylinder.obj";
  const qt::Mesh exact = qt::read_obj(path);
  const OMeshD loaded = load<OMeshD>(path);
  CHECK_MSG(qt::same_bits(openmesh_points(loaded), exact.xyz), "OpenMesh's coordinates differ from the file's");
  CHECK_MSG(openmesh_faces(loaded) == exact.quads, "OpenMesh's faces differ from the file's");

  // OpenMesh, double points.
  OMeshD om = loaded;
  const quadopt::Report ro = quadopt::openmesh::optimize(om);
  const std::vector<double> om_out = openmesh_points(om);
  check_on_cylinder("OpenMesh", exact.xyz, om_out, exact.quads, ro, 1e-9);
  CHECK(ro.patches == 1 && ro.corners == 4 && ro.max_distance < 1e-9);
  // The C call gives the same, bit for bit.
  std::vector<double> c_out = exact.xyz;
  const quadopt::Report rc = quadopt::optimize_surface(c_out, exact.quads);
  CHECK_MSG(qt::same_bits(c_out, om_out), "the OpenMesh adapter differs from the C call");
  CHECK(rc.iterations == ro.iterations && qt::same_bits(rc.output.min, ro.output.min));

  // OpenMesh, float points (the default traits): within float precision.
  OMeshF omf = load<OMeshF>(path);
  const quadopt::Report rf = quadopt::openmesh::optimize(omf);
  check_on_cylinder("OpenMesh float", exact.xyz, openmesh_points(omf), exact.quads, rf, 1e-6);

  // Edge status: the vertical line i = 4 marked feature() is a feature curve, its vertices
  // stay on it (and the surface is cut in two patches); locked vertices stay put.
  OMeshD marked = loaded;
  marked.request_edge_status();
  marked.request_vertex_status();
  for (auto eh : marked.edges()) {
    const auto h = marked.halfedge_handle(eh, 0);
    const int a = marked.from_vertex_handle(h).idx(), b = marked.to_vertex_handle(h).idx();
    if (a % 9 == 4 && b % 9 == 4) marked.status(eh).set_feature(true);
  }
  marked.status(OMeshD::VertexHandle(20)).set_locked(true);
  const quadopt::Report rm = quadopt::openmesh::optimize(marked);
  const std::vector<double> m_out = openmesh_points(marked);
  check_on_cylinder("OpenMesh, marked line", exact.xyz, m_out, exact.quads, rm, 1e-9);
  CHECK(rm.patches == 2);
  bool line = true;
  for (std::size_t v = 4; v < 63; v += 9) {
    line = line && std::fabs(m_out[3 * v] - exact.xyz[3 * v]) < 1e-12 &&
           std::fabs(m_out[3 * v + 1] - exact.xyz[3 * v + 1]) < 1e-12;
  }
  CHECK_MSG(line, "OpenMesh: a vertex of the marked line left it");
  CHECK(qt::same_bits(m_out[60], exact.xyz[60]) && qt::same_bits(m_out[62], exact.xyz[62]));
  // The same line as an explicit list, without edge status: the same result.
  OMeshD listed = loaded;
  quadopt::openmesh::MeshOptions lmo;
  lmo.fixed.assign(63, 0);
  lmo.fixed[20] = 1;
  for (std::uint32_t j = 0; j < 6; ++j) lmo.feature_edges.push_back({4 + 9 * j, 13 + 9 * j});
  quadopt::openmesh::optimize(listed, quadopt::Options(), lmo);
  CHECK_MSG(qt::same_bits(openmesh_points(listed), m_out), "OpenMesh: edge status and an explicit list differ");
  // A pair that is not an edge: an Error naming it, the mesh unchanged.
  OMeshD bad = loaded;
  quadopt::openmesh::MeshOptions bmo;
  bmo.feature_edges.push_back({0, 10});
  CHECK_THROWS_STATUS(quadopt::openmesh::optimize(bad, quadopt::Options(), bmo), QUADOPT_STATUS_INVALID_ARGUMENT);
  CHECK(std::string(quadopt_last_error()).find("feature edge 0, vertices (0, 10)") != std::string::npos);
  CHECK_MSG(qt::same_bits(openmesh_points(bad), exact.xyz), "OpenMesh: a refused mesh was changed");

  // CGAL Surface_mesh: the same result as OpenMesh's (the same vertices and faces).
  SM3 sm = cgal_from(exact.xyz, exact.quads);
  const quadopt::Report rs = quadopt::cgal::optimize(sm);
  check_on_cylinder("CGAL", exact.xyz, cgal_points(sm), exact.quads, rs, 1e-9);
  CHECK_MSG(qt::same_bits(cgal_points(sm), om_out), "the CGAL adapter differs from OpenMesh's");
  // The feature line as CGAL's "e:is_feature" map, and as an explicit list.
  SM3 smf = cgal_from(exact.xyz, exact.quads);
  auto is_feature = smf.add_property_map<SM3::Edge_index, bool>("e:is_feature", false).first;
  auto is_fixed = smf.add_property_map<SM3::Vertex_index, bool>("v:fixed", false).first;
  put(is_fixed, SM3::Vertex_index(20), true);
  for (auto e : smf.edges()) {
    const auto h = smf.halfedge(e);
    if (static_cast<std::size_t>(smf.source(h)) % 9 == 4 && static_cast<std::size_t>(smf.target(h)) % 9 == 4) {
      put(is_feature, e, true);
    }
  }
  const quadopt::Report rsf = quadopt::cgal::optimize(smf);
  CHECK(rsf.patches == 2);
  CHECK_MSG(qt::same_bits(cgal_points(smf), m_out), "CGAL's e:is_feature differs from OpenMesh's edge status");
  SM3 sml = cgal_from(exact.xyz, exact.quads);
  auto fixed_l = sml.add_property_map<SM3::Vertex_index, bool>("v:fixed", false).first;
  put(fixed_l, SM3::Vertex_index(20), true);
  quadopt::cgal::MeshOptions cmo;
  for (std::size_t j = 0; j < 6; ++j) cmo.feature_edges.push_back({4 + 9 * j, 13 + 9 * j});
  quadopt::cgal::optimize(sml, quadopt::Options(), cmo);
  CHECK_MSG(qt::same_bits(cgal_points(sml), m_out), "CGAL: an explicit list differs from OpenMesh's edge status");
  SM3 smb = cgal_from(exact.xyz, exact.quads);
  quadopt::cgal::MeshOptions cbad;
  cbad.feature_edges.push_back({0, 10});
  CHECK_THROWS_STATUS(quadopt::cgal::optimize(smb, quadopt::Options(), cbad), QUADOPT_STATUS_INVALID_ARGUMENT);
  cbad.feature_edges[0] = {0, 99};
  CHECK_THROWS_STATUS(quadopt::cgal::optimize(smb, quadopt::Options(), cbad), QUADOPT_STATUS_INDEX_OUT_OF_RANGE);
  CHECK_MSG(qt::same_bits(cgal_points(smb), exact.xyz), "CGAL: a refused mesh was changed");
}

}  // namespace

int main(int argc, char **argv) {
  if (argc < 5) {
    std::cerr << "usage: mesh_tests DATA_DIR CLI TMP_DIR MESH_FILE|--faces|--planes|--surface\n";
    return 2;
  }
  g_data = argv[1];
  g_cli = argv[2];
  g_tmp = argv[3];
  const std::string which = argv[4];
  try {
    if (which == "--faces") {
      test_faces();
    } else if (which == "--surface") {
      test_surface_meshes();
    } else if (which == "--planes") {
      test_tilted_plane();
      test_axis_planes();
      test_curved();
    } else {
      const Case c = load_case(which);
      CHECK(c.n() > 0 && c.nq() > 0 && !c.cycles.empty() && !c.corners.empty());
      test_c_api(c);
      test_openmesh_adapter(c);
      test_cgal_adapter(c);
      test_cli(c);
      bool any_triangle = false;
      for (std::size_t f = 0; f < c.nq(); ++f) any_triangle = any_triangle || c.quads[4 * f + 3] == QUADOPT_NO_VERTEX;
      CHECK_MSG(any_triangle == (which.rfind("mixed", 0) == 0), which << ": triangles where none were expected, or none");
      if (any_triangle) test_face_kinds(c);
    }
  } catch (const std::exception &e) {
    CHECK_MSG(false, "unexpected exception: " << e.what());
  }
  return qt::finish(("mesh_tests " + which).c_str());
}
