// Tests of include/quadopt.hpp alone (no mesh library): the options builder, quadopt::Error,
// the move-only Optimizer, progress callbacks (cancellation and exceptions), and concurrent
// calls from several std::threads, with one shared handle and without; a quad-dominant mesh
// (quadopt::triangle, quadopt::no_vertex, the per-kind statistics of the report and of
// quadopt::quality_by_kind); a mesh on a curved surface (quadopt::optimize_surface, marked
// feature edges, the report's surface fields).
//
// Usage: cpp_wrapper_test DATA_DIR
#include "test_support.hpp"

#include <quadopt.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <stdexcept>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

namespace {

static_assert(!std::is_copy_constructible<quadopt::Optimizer>::value, "Optimizer is move-only");
static_assert(!std::is_copy_assignable<quadopt::Optimizer>::value, "Optimizer is move-only");
static_assert(std::is_nothrow_move_constructible<quadopt::Optimizer>::value, "Optimizer moves without throwing");
static_assert(std::is_nothrow_move_assignable<quadopt::Optimizer>::value, "Optimizer moves without throwing");
static_assert(std::is_base_of<std::runtime_error, quadopt::Error>::value, "Error is a std::runtime_error");

qt::Mesh g_plate;
qt::Mesh g_grid;
qt::Mesh g_mixed;
qt::Mesh g_cylinder;

static_assert(quadopt::no_vertex == UINT32_MAX && quadopt::no_vertex == QUADOPT_NO_VERTEX, "the sentinel");
static_assert(quadopt::triangle(3, 4, 6)[3] == quadopt::no_vertex && quadopt::triangle(3, 4, 6)[2] == 6,
              "a triangle's four slots");

void test_options() {
  QuadoptOptions d;
  CHECK(quadopt_options_init(&d, sizeof d) == QUADOPT_STATUS_OK);
  quadopt::Options o;
  CHECK(o.raw().struct_size == d.struct_size && o.raw().lambda == d.lambda && o.raw().tau == d.tau &&
        o.raw().max_iterations == d.max_iterations && o.raw().method == d.method && o.raw().boundary == d.boundary);
  o.method(quadopt::Method::Cotangent)
      .boundary(quadopt::Boundary::Snap)
      .max_iterations(17)
      .lambda(0.5)
      .tau(1e-9)
      .tau_absolute(true)
      .feature_angle_deg(30)
      .guard(false)
      .guard_floor(0.1)
      .untangle(false)
      .keep_best(false)
      .max_boundary_deviation(0.25)
      .max_min(false)
      .stop_rule(QUADOPT_STOP_RULE_QUALITY);
  const QuadoptOptions &r = o.raw();
  CHECK(r.max_min == 0 && r.stop_rule == QUADOPT_STOP_RULE_QUALITY);
  CHECK(quadopt::Options().raw().max_min == 1);
  CHECK(r.method == QUADOPT_METHOD_COTANGENT && r.boundary == QUADOPT_BOUNDARY_SNAP);
  CHECK(r.max_iterations == 17 && r.lambda == 0.5 && r.tau == 1e-9 && r.tau_absolute == 1);
  CHECK(r.feature_angle_deg == 30 && r.guard == 0 && r.guard_floor == 0.1 && r.untangle == 0 && r.keep_best == 0);
  CHECK(r.max_boundary_deviation == 0.25 && r.struct_size == sizeof(QuadoptOptions));
  CHECK(std::string(quadopt::version()) == quadopt_version());
  CHECK(std::string(quadopt::status_string(QUADOPT_STATUS_NO_QUADS)) == quadopt_status_string(4));
  // Out of memory is a quadopt::Error like any other failure (not std::bad_alloc).
  const quadopt::Error oom(QUADOPT_STATUS_OUT_OF_MEMORY, "cannot allocate 32 bytes for quads");
  CHECK(std::string(oom.what()) == "out of memory: cannot allocate 32 bytes for quads");
}

// The presets through the wrapper: the report says which ran; fast runs no max-min stage and at
// most 6 sweeps (Effort::FAST_SWEEPS); every preset's output has no inverted quad and a minimum above the input's;
// max_min(false) turns the stage off in every preset; an unknown effort is an invalid option.
void test_effort() {
  CHECK(quadopt::Options().raw().effort == QUADOPT_EFFORT_BALANCED);
  for (quadopt::Effort e : {quadopt::Effort::Fast, quadopt::Effort::Balanced, quadopt::Effort::Best}) {
    std::vector<double> xy = g_plate.xy();
    const quadopt::Report r = quadopt::optimize(xy, 2, g_plate.quads, quadopt::Options().effort(e));
    CHECK(r.effort == static_cast<std::uint32_t>(e));
    CHECK(r.output.inverted == 0 && r.output.min > r.input.min);
    if (e == quadopt::Effort::Fast) {
      CHECK(r.max_min == 0 && r.iterations <= 6);
    }
    std::vector<double> off = g_plate.xy();
    const quadopt::Report ro = quadopt::optimize(off, 2, g_plate.quads, quadopt::Options().effort(e).max_min(false));
    CHECK(ro.max_min == 0);
  }
  std::vector<double> xy = g_plate.xy();
  quadopt::Options bad;
  bad.raw().effort = 7;
  CHECK_THROWS_STATUS(quadopt::optimize(xy, 2, g_plate.quads, bad), QUADOPT_STATUS_INVALID_OPTION);
  CHECK(qt::same_bits(xy, g_plate.xy()));
}

void test_errors() {
  std::vector<double> xy = g_grid.xy();
  const std::vector<double> before = xy;
  // An invalid option: status, message naming the option, what() = "<status>: <message>".
  try {
    quadopt::optimize(xy, 2, g_grid.quads, quadopt::Options().lambda(0.0));
    CHECK_MSG(false, "no exception");
  } catch (const quadopt::Error &e) {
    CHECK(e.status() == QUADOPT_STATUS_INVALID_OPTION);
    CHECK(e.message().find("lambda") != std::string::npos);
    CHECK(std::string(e.what()) == std::string("invalid option: ") + e.message());
    CHECK(e.message() == quadopt_last_error());
  }
  CHECK(qt::same_bits(xy, before));
  std::vector<std::uint32_t> bad = g_grid.quads;
  bad[5] = static_cast<std::uint32_t>(g_grid.vertices());
  CHECK_THROWS_STATUS(quadopt::optimize(xy, 2, bad), QUADOPT_STATUS_INDEX_OUT_OF_RANGE);
  CHECK_THROWS_STATUS(quadopt::quality(xy, 2, bad), QUADOPT_STATUS_INDEX_OUT_OF_RANGE);
  std::vector<double> per_quad(3, 7.0);
  CHECK_THROWS_STATUS(quadopt::quality(xy, 2, bad, &per_quad), QUADOPT_STATUS_INDEX_OUT_OF_RANGE);
  CHECK(per_quad == std::vector<double>(3, 7.0));  // untouched on error
  CHECK_THROWS_STATUS(quadopt::Optimizer(xy, 2, bad), QUADOPT_STATUS_INDEX_OUT_OF_RANGE);
  // The wrapper's own checks of vector sizes.
  CHECK_THROWS_STATUS(quadopt::optimize(xy, 4, g_grid.quads), QUADOPT_STATUS_INVALID_ARGUMENT);
  std::vector<double> odd(xy.begin(), xy.end() - 1);
  CHECK_THROWS_STATUS(quadopt::optimize(odd, 2, g_grid.quads), QUADOPT_STATUS_INVALID_ARGUMENT);
  std::vector<std::uint32_t> ragged(g_grid.quads.begin(), g_grid.quads.end() - 1);
  CHECK_THROWS_STATUS(quadopt::quality(xy, 2, ragged), QUADOPT_STATUS_INVALID_ARGUMENT);
  CHECK_THROWS_STATUS(quadopt::optimize(xy, 2, g_grid.quads, quadopt::Options(), std::vector<std::uint8_t>(3, 0)),
                      QUADOPT_STATUS_INVALID_ARGUMENT);
  CHECK(qt::same_bits(xy, before));
}

void test_optimizer_handle() {
  const std::vector<double> start = g_plate.xy();
  std::vector<double> ref = start;
  const quadopt::Report rr = quadopt::optimize(ref, 2, g_plate.quads);
  CHECK(rr.output.min > rr.input.min && rr.output.inverted == 0);

  quadopt::Optimizer a(start, 2, g_plate.quads);
  CHECK(static_cast<bool>(a) && a.dim() == 2 && a.vertex_count() == g_plate.vertices());
  std::vector<double> xy = start;
  const quadopt::Report r = a.optimize(xy);
  CHECK(qt::same_bits(xy, ref));
  CHECK(r.iterations == rr.iterations && qt::same_bits(r.output.min, rr.output.min));

  // Move construction and assignment transfer the handle; the source is empty afterwards.
  quadopt::Optimizer b(std::move(a));
  CHECK(!a && static_cast<bool>(b) && b.get() != nullptr);
  xy = start;
  CHECK_THROWS_STATUS(a.optimize(xy), QUADOPT_STATUS_NULL_POINTER);
  CHECK(qt::same_bits(xy, start));
  b.optimize(xy);
  CHECK(qt::same_bits(xy, ref));
  quadopt::Optimizer c(g_grid.xy(), 2, g_grid.quads);
  c = std::move(b);  // frees c's grid handle (ASan/LSan check this)
  CHECK(!b && c.vertex_count() == g_plate.vertices());
  xy = start;
  c.optimize(xy);
  CHECK(qt::same_bits(xy, ref));
  // A coordinate set of another size: MISMATCH from the library.
  std::vector<double> grid_xy = g_grid.xy();
  CHECK_THROWS_STATUS(c.optimize(grid_xy), QUADOPT_STATUS_MISMATCH);

  // dim 3 through the wrapper, the same z everywhere (a planar mesh): same x, y; z untouched.
  std::vector<double> xyz = g_plate.xyz;
  for (std::size_t i = 0; i < g_plate.vertices(); ++i) xyz[3 * i + 2] = 0.5;
  quadopt::Optimizer d(xyz, 3, g_plate.quads);
  d.optimize(xyz);
  bool same = true;
  for (std::size_t i = 0; i < g_plate.vertices(); ++i) {
    same = same && qt::same_bits(xyz[3 * i], ref[2 * i]) && qt::same_bits(xyz[3 * i + 1], ref[2 * i + 1]) &&
           xyz[3 * i + 2] == 0.5;
  }
  CHECK(same);

  // quality() agrees with the report, and its per-quad values with its statistics.
  std::vector<double> per_quad;
  const quadopt::Quality q = quadopt::quality(ref, 2, g_plate.quads, &per_quad);
  CHECK(qt::same_bits(q.min, rr.output.min) && qt::same_bits(q.avg, rr.output.avg) && q.inverted == 0);
  double lo = 2;
  for (double v : per_quad) lo = std::fmin(lo, v);
  CHECK(per_quad.size() == g_plate.quad_count() && lo == q.min);
}

struct Boom : std::runtime_error {
  Boom() : std::runtime_error("boom") {}
};

void test_progress() {
  const std::vector<double> start = g_grid.xy();
  std::vector<double> xy = start;
  std::size_t calls = 0, last_iteration = 0;
  bool increasing = true;
  quadopt::Options o;
  o.progress([&](const quadopt::Progress &p) {
    ++calls;
    // Sweeps count up from 1; calls while untangling have iteration 0 and NaN energies.
    if (p.iteration == 0) {
      increasing = increasing && std::isnan(p.energy);
      return true;
    }
    increasing = increasing && (p.iteration > last_iteration || p.iteration == 1);
    last_iteration = p.iteration;
    return true;
  });
  quadopt::Report r = quadopt::optimize(xy, 2, g_grid.quads, o);
  CHECK(calls >= r.iterations && r.iterations > 0 && increasing);
  // The callback does not change the result.
  std::vector<double> plain = start;
  quadopt::optimize(plain, 2, g_grid.quads);
  CHECK(qt::same_bits(xy, plain));

  // Returning false cancels: CANCELLED, nothing written.
  xy = start;
  calls = 0;
  // The energy rule with tau = 0 never stops: the callback decides.
  o.stop_rule(QUADOPT_STOP_RULE_ENERGY).tau(0.0).progress([&](const quadopt::Progress &) { return ++calls < 2; });
  CHECK_THROWS_STATUS(quadopt::optimize(xy, 2, g_grid.quads, o), QUADOPT_STATUS_CANCELLED);
  CHECK(calls == 2 && qt::same_bits(xy, start));

  // An exception in the callback cancels the run and reaches the caller unchanged.
  o.progress([](const quadopt::Progress &p) -> bool {
    if (p.iteration >= 2) throw Boom();
    return true;
  });
  bool boom = false;
  try {
    quadopt::optimize(xy, 2, g_grid.quads, o);
  } catch (const Boom &) {
    boom = true;
  }
  CHECK(boom && qt::same_bits(xy, start));
  // The same through a shared handle.
  const quadopt::Optimizer h(start, 2, g_grid.quads);
  boom = false;
  try {
    h.optimize(xy, o);
  } catch (const Boom &) {
    boom = true;
  }
  CHECK(boom && qt::same_bits(xy, start));
}

/// Several threads optimizing at once give exactly the single-threaded results.
void test_concurrency() {
  const int threads = 8;
  const quadopt::Boundary modes[4] = {quadopt::Boundary::Auto, quadopt::Boundary::Slide, quadopt::Boundary::Snap,
                                      quadopt::Boundary::Fixed};
  std::vector<std::vector<double>> ref(4);
  for (int m = 0; m < 4; ++m) {
    ref[m] = g_plate.xy();
    quadopt::optimize(ref[m], 2, g_plate.quads, quadopt::Options().boundary(modes[m]));
  }
  std::vector<double> grid_ref = g_grid.xy();
  quadopt::optimize(grid_ref, 2, g_grid.quads);

  // Without a shared handle: each thread its own quadopt::optimize calls.
  std::atomic<bool> go{false};
  std::vector<int> ok(threads, 0);
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) {
    pool.emplace_back([&, t] {
      while (!go.load()) std::this_thread::yield();
      int good = 1;
      for (int rep = 0; rep < 3; ++rep) {
        const int m = (t + rep) % 4;
        std::vector<double> xy = g_plate.xy();
        quadopt::optimize(xy, 2, g_plate.quads, quadopt::Options().boundary(modes[m]));
        good &= qt::same_bits(xy, ref[m]) ? 1 : 0;
        std::vector<double> g = g_grid.xy();
        quadopt::optimize(g, 2, g_grid.quads);
        good &= qt::same_bits(g, grid_ref) ? 1 : 0;
      }
      ok[t] = good;
    });
  }
  go = true;
  for (auto &th : pool) th.join();
  for (int t = 0; t < threads; ++t) CHECK_MSG(ok[t] == 1, "thread " << t << " (own calls)");

  // One handle shared by every thread, with different options per thread.
  const quadopt::Optimizer shared(g_plate.xy(), 2, g_plate.quads);
  pool.clear();
  go = false;
  for (int t = 0; t < threads; ++t) {
    pool.emplace_back([&, t] {
      while (!go.load()) std::this_thread::yield();
      int good = 1;
      for (int rep = 0; rep < 3; ++rep) {
        const int m = (t + rep) % 4;
        std::vector<double> xy = g_plate.xy();
        shared.optimize(xy, quadopt::Options().boundary(modes[m]));
        good &= qt::same_bits(xy, ref[m]) ? 1 : 0;
      }
      ok[t] = good;
    });
  }
  go = true;
  for (auto &th : pool) th.join();
  for (int t = 0; t < threads; ++t) CHECK_MSG(ok[t] == 1, "thread " << t << " (shared handle)");

  // The last error is per thread: each thread sees its own failure's message even while the
  // others fail differently at the same time.
  pool.clear();
  go = false;
  std::vector<std::string> seen(threads);
  for (int t = 0; t < threads; ++t) {
    pool.emplace_back([&, t] {
      while (!go.load()) std::this_thread::yield();
      std::vector<double> xy = g_grid.xy();
      std::vector<std::uint32_t> bad = g_grid.quads;
      bad[4 * t + 1] = 1000000u + static_cast<std::uint32_t>(t);  // quad t, corner 1
      for (int rep = 0; rep < 20; ++rep) {
        const QuadoptStatus s = quadopt_optimize(xy.data(), 2, g_grid.vertices(), bad.data(), g_grid.quad_count(),
                                                 nullptr, nullptr, nullptr);
        std::this_thread::yield();
        seen[t] = s == QUADOPT_STATUS_INDEX_OUT_OF_RANGE ? quadopt_last_error() : "wrong status";
      }
    });
  }
  go = true;
  for (auto &th : pool) th.join();
  for (int t = 0; t < threads; ++t) {
    const std::string want = "quad " + std::to_string(t) + " corner 1 refers to vertex " + std::to_string(1000000 + t);
    CHECK_MSG(seen[t].find(want) != std::string::npos, "thread " << t << ": " << seen[t]);
  }
}

bool same_kind(const quadopt::FaceKindQuality &a, const quadopt::FaceKindQuality &b) {
  return a.count == b.count && qt::same_bits(a.min, b.min) && qt::same_bits(a.avg, b.avg);
}

void test_triangles() {
  // mixed_grid.obj: 51 quads and 26 triangles (cpp_tests/data/make_data.py), one of each inverted.
  CHECK(g_mixed.quad_count() == 77 && g_mixed.triangle_count() == 26);
  const std::array<std::uint32_t, 4> t = quadopt::triangle(12, 22, 21);
  bool found = false;
  for (std::size_t f = 0; f < g_mixed.quad_count(); ++f) {
    const std::uint32_t *face = &g_mixed.quads[4 * f];
    found = found || (quadopt::is_triangle(face) && face[0] == t[0] && face[1] == t[1] && face[2] == t[2]);
    CHECK(quadopt::is_triangle(face) == (face[3] == QUADOPT_NO_VERTEX));
  }
  CHECK(found);
  std::vector<double> xy = g_mixed.xy();
  const std::vector<double> start = xy;
  const quadopt::ByFaceKind in_k = quadopt::quality_by_kind(xy, 2, g_mixed.quads);
  CHECK(in_k.quads.count == 51 && in_k.triangles.count == 26);
  CHECK(in_k.quads.min <= 0.0 && in_k.triangles.min <= 0.0);
  // The statistics by kind are those of the per-face values (a triangle's is Verdict's).
  std::vector<double> per_face;
  const quadopt::Quality q = quadopt::quality(xy, 2, g_mixed.quads, &per_face);
  CHECK(per_face.size() == 77 && q.inverted == 2);
  CHECK(qt::same_bits(std::fmin(in_k.quads.min, in_k.triangles.min), q.min));
  const quadopt::Report r = quadopt::optimize(xy, 2, g_mixed.quads);
  CHECK(same_kind(quadopt::input_by_kind(r).quads, in_k.quads) &&
        same_kind(quadopt::input_by_kind(r).triangles, in_k.triangles));
  const quadopt::ByFaceKind out_k = quadopt::quality_by_kind(xy, 2, g_mixed.quads);
  CHECK(same_kind(quadopt::output_by_kind(r).quads, out_k.quads) &&
        same_kind(quadopt::output_by_kind(r).triangles, out_k.triangles));
  CHECK_MSG(r.output.inverted == 0 && out_k.triangles.min > 0.0 && out_k.quads.min > 0.0 && r.output.min > r.input.min,
            "mixed grid: quads " << in_k.quads.min << " -> " << out_k.quads.min << ", triangles " << in_k.triangles.min
                                 << " -> " << out_k.triangles.min);
  // The wrapper is the C call: the same coordinates, bit for bit.
  std::vector<double> c_xy = start;
  QuadoptReport cr = quadopt_report_init();
  CHECK(quadopt_optimize(c_xy.data(), 2, g_mixed.vertices(), g_mixed.quads.data(), g_mixed.quad_count(), nullptr,
                         nullptr, &cr) == QUADOPT_STATUS_OK);
  CHECK(qt::same_bits(c_xy, xy) && same_kind(cr.output_triangles, r.output_triangles));
  // The reusable optimizer on the same faces.
  const quadopt::Optimizer opt(start, 2, g_mixed.quads);
  std::vector<double> h_xy = start;
  const quadopt::Report hr = opt.optimize(h_xy);
  CHECK(qt::same_bits(h_xy, xy) && same_kind(hr.output_quads, r.output_quads));
  // A quad mesh: no triangles in the statistics.
  const quadopt::ByFaceKind quads_only = quadopt::quality_by_kind(g_grid.xy(), 2, g_grid.quads);
  CHECK(quads_only.quads.count == g_grid.quad_count() && quads_only.triangles.count == 0 &&
        std::isnan(quads_only.triangles.min) && std::isnan(quads_only.triangles.avg));
  // Built with quadopt::triangle: two quads and a triangle on top (cpp_tests/data/mixed.obj).
  std::vector<double> small = {0, 0, 1, 0, 2, 0, 0, 1, 1, 1, 2, 1, 1, 2};
  std::vector<std::uint32_t> faces = {0, 1, 4, 3, 1, 2, 5, 4};
  const auto top = quadopt::triangle(3, 4, 6);
  faces.insert(faces.end(), top.begin(), top.end());
  const quadopt::ByFaceKind sk = quadopt::quality_by_kind(small, 2, faces);
  // The triangle (0,1) (1,1) (1,2): a right isosceles one, sqrt(2/3) (see c_api_test.c).
  CHECK(sk.quads.count == 2 && sk.quads.min == 1.0 && sk.triangles.count == 1 &&
        std::fabs(sk.triangles.min - std::sqrt(2.0 / 3.0)) <= 1e-15 && sk.triangles.avg == sk.triangles.min);
  // The sentinel anywhere but in the fourth slot is an index out of range; coordinates untouched.
  std::vector<std::uint32_t> bad = faces;
  bad[9] = quadopt::no_vertex;
  const std::vector<double> small_before = small;
  CHECK_THROWS_STATUS(quadopt::optimize(small, 2, bad), QUADOPT_STATUS_INDEX_OUT_OF_RANGE);
  CHECK_THROWS_STATUS(quadopt::quality_by_kind(small, 2, bad), QUADOPT_STATUS_INDEX_OUT_OF_RANGE);
  CHECK(qt::same_bits(small, small_before));
  // Three slots for a triangle (no sentinel): not a whole number of faces.
  std::vector<std::uint32_t> short_faces(faces.begin(), faces.end() - 1);
  try {
    quadopt::quality(small, 2, short_faces);
    CHECK_MSG(false, "no exception for 11 face indices");
  } catch (const quadopt::Error &e) {
    CHECK(e.status() == QUADOPT_STATUS_INVALID_ARGUMENT &&
          e.message() == "11 face indices are not a multiple of 4");
  }
}

/// The quarter cylinder x^2 + y^2 = 4 of data/quarter_cylinder.obj (9 x 7 vertices, vertex
/// 9 j + i): optimize_surface() on points, with the bottom row fixed and the vertical line
/// i = 4 marked as a feature curve.
void test_surface() {
  std::vector<quadopt::Point3> points;
  for (std::size_t v = 0; v < g_cylinder.vertices(); ++v) {
    points.push_back({g_cylinder.xyz[3 * v], g_cylinder.xyz[3 * v + 1], g_cylinder.xyz[3 * v + 2]});
  }
  const std::vector<quadopt::Point3> before = points;
  std::vector<std::uint8_t> fixed(points.size(), 0);
  for (std::size_t v = 0; v < 9; ++v) fixed[v] = 1;
  std::vector<quadopt::Edge> line;
  for (std::uint32_t j = 0; j < 6; ++j) line.push_back({4 + 9 * j, 4 + 9 * (j + 1)});
  // The chordal tolerance: the sagitta of the widest face's angular span.
  double tolerance = 0;
  for (std::size_t f = 0; f < g_cylinder.quad_count(); ++f) {
    double lo = 10, hi = -10;
    for (int k = 0; k < 4; ++k) {
      const auto &p = before[g_cylinder.quads[4 * f + k]];
      lo = std::fmin(lo, std::atan2(p[1], p[0]));
      hi = std::fmax(hi, std::atan2(p[1], p[0]));
    }
    tolerance = std::fmax(tolerance, 2.0 * (1.0 - std::cos((hi - lo) / 2)));
  }
  const quadopt::Report r = quadopt::optimize_surface(points, g_cylinder.quads, fixed, line);
  CHECK(quadopt::on_surface(r) && r.output.min > r.input.min && r.output.inverted == 0);
  CHECK(r.patches == 2 && r.feature_curves >= 5 && r.max_distance < 1e-9 && r.max_feature_distance < 1e-9);
  bool on = true, still = true, line_ok = true;
  for (std::size_t v = 0; v < points.size(); ++v) {
    const double off = std::hypot(points[v][0], points[v][1]) - 2.0;
    on = on && off <= 1e-6 && -off <= tolerance + 1e-6;
    if (v < 9) still = still && qt::same_bits(points[v][0], before[v][0]) && qt::same_bits(points[v][1], before[v][1]) &&
                       qt::same_bits(points[v][2], before[v][2]);
    if (v % 9 == 4) line_ok = line_ok && std::fabs(points[v][0] - before[v][0]) < 1e-12 &&
                              std::fabs(points[v][1] - before[v][1]) < 1e-12;
  }
  CHECK_MSG(on, "a vertex left the cylinder (tolerance " << tolerance << ")");
  CHECK_MSG(still, "a fixed vertex moved");
  CHECK_MSG(line_ok, "a vertex of the marked line left it");
  // Verdict's measure of the input and of the result: the report's two Verdict statistics.
  {
    std::vector<double> xyz_before, xyz_after, per_face;
    for (std::size_t v = 0; v < points.size(); ++v) {
      for (int c = 0; c < 3; ++c) {
        xyz_before.push_back(before[v][c]);
        xyz_after.push_back(points[v][c]);
      }
    }
    const quadopt::Quality in = quadopt::verdict_quality(xyz_before, g_cylinder.quads);
    const quadopt::Quality out = quadopt::verdict_quality(xyz_after, g_cylinder.quads, &per_face);
    CHECK(in.min == r.input_verdict.min && in.avg == r.input_verdict.avg && in.inverted == r.input_verdict.inverted);
    CHECK(out.min == r.output_verdict.min && out.avg == r.output_verdict.avg &&
          out.inverted == r.output_verdict.inverted);
    CHECK(per_face.size() == g_cylinder.quad_count() &&
          *std::min_element(per_face.begin(), per_face.end()) == out.min);
    std::vector<std::uint32_t> bad = g_cylinder.quads;
    bad[5] = 100000;
    CHECK_THROWS_STATUS(quadopt::verdict_quality(xyz_after, bad), QUADOPT_STATUS_INDEX_OUT_OF_RANGE);
  }
  // The flat-vector overload and optimize() with dim 3 (no marked edge) agree bit for bit.
  std::vector<double> a = g_cylinder.xyz, b = g_cylinder.xyz;
  const quadopt::Report ra = quadopt::optimize_surface(a, g_cylinder.quads);
  const quadopt::Report rb = quadopt::optimize(b, 3, g_cylinder.quads);
  CHECK(qt::same_bits(a, b) && quadopt::on_surface(ra) && quadopt::on_surface(rb) && rb.patches == 1);
  // Errors leave the points untouched: a marked pair that is not an edge (a quad's diagonal),
  // an exception from the progress callback (rethrown).
  std::vector<quadopt::Point3> c = before;
  try {
    quadopt::optimize_surface(c, g_cylinder.quads, {}, {{0, 10}});
    CHECK_MSG(false, "a diagonal was accepted as a feature edge");
  } catch (const quadopt::Error &e) {
    CHECK(e.status() == QUADOPT_STATUS_INVALID_ARGUMENT);
    CHECK_MSG(e.message().find("feature edge 0, vertices (0, 10), is not an edge") != std::string::npos, e.message());
  }
  const quadopt::Options throwing = quadopt::Options().progress([](const quadopt::Progress &) -> bool {
    throw std::runtime_error("from the callback");
  });
  try {
    quadopt::optimize_surface(c, g_cylinder.quads, {}, {}, throwing);
    CHECK_MSG(false, "the callback's exception was lost");
  } catch (const std::runtime_error &e) {
    CHECK(std::string(e.what()) == "from the callback");
  }
  bool same = true;
  for (std::size_t v = 0; v < c.size(); ++v) same = same && c[v] == before[v];
  CHECK_MSG(same, "a failed call changed the points");
  // A handle refuses a curved mesh.
  CHECK_THROWS_STATUS(quadopt::Optimizer(g_cylinder.xyz, 3, g_cylinder.quads), QUADOPT_STATUS_NOT_PLANAR);
}

}  // namespace

int main(int argc, char **argv) {
  if (argc < 2) {
    std::cerr << "usage: cpp_wrapper_test DATA_DIR\n";
    return 2;
  }
  const std::string dir = argv[1];
  try {
    g_plate = qt::read_obj(dir + "/plate_hole.obj");
    g_grid = qt::read_obj(dir + "/jittered_grid.obj");
    g_mixed = qt::read_obj(dir + "/mixed_grid.obj");
    g_cylinder = qt::read_obj(dir + "/quarter_cylinder.obj");
    test_options();
    test_effort();
    test_errors();
    test_optimizer_handle();
    test_progress();
    test_concurrency();
    test_triangles();
    test_surface();
  } catch (const std::exception &e) {
    CHECK_MSG(false, "unexpected exception: " << e.what());
  }
  return qt::finish("cpp_wrapper_test");
}
