/* Pure C99 test of include/quadopt.h: defaults, hand-computed quality values, the optimizer on
 * a small patch, the reusable handle, growable structs, a quad-dominant patch (triangles as
 * three indices and QUADOPT_NO_VERTEX, the report's per-kind fields), a mesh on a curved
 * surface (quadopt_optimize_surface(), marked feature edges, the report's surface fields), and
 * every error status
 * that bad input can produce, each checked to leave the caller's buffers untouched.
 *
 * On POSIX systems also: a child forked after use, and (Linux) an input too large for an
 * address-space limit, which must give QUADOPT_STATUS_OUT_OF_MEMORY rather than abort.
 *
 * Built with -std=c99 -Wall -Wextra -Werror -pedantic (see CMakeLists.txt); linked once
 * against the shared and once against the static library. Prints "N passed, N failed". */
#if defined(__unix__) || defined(__APPLE__)
#define _POSIX_C_SOURCE 200809L /* fork, waitpid, alarm, setrlimit */
#define QUADOPT_TEST_POSIX 1
#endif
/* AddressSanitizer reserves terabytes of address space and aborts when malloc fails, so the
 * address-space limit test is left out of sanitizer builds. */
#if defined(__SANITIZE_ADDRESS__)
#define QUADOPT_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define QUADOPT_TEST_ASAN 1
#endif
#endif
#if defined(__linux__) && !defined(QUADOPT_TEST_ASAN)
#define QUADOPT_TEST_AS_LIMIT 1
#endif

#include "quadopt.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef QUADOPT_TEST_POSIX
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#endif

static int passed = 0;
static int failed = 0;

#define CHECK(cond)                                                          \
  do {                                                                       \
    if (cond) {                                                              \
      ++passed;                                                              \
    } else {                                                                 \
      ++failed;                                                              \
      fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond); \
    }                                                                        \
  } while (0)

#define CHECK_STATUS(call, expected)                                                           \
  do {                                                                                         \
    QuadoptStatus got_ = (call);                                                               \
    if (got_ == (expected)) {                                                                  \
      ++passed;                                                                                \
    } else {                                                                                   \
      ++failed;                                                                                \
      fprintf(stderr, "%s:%d: %s returned %d (%s), expected %d (%s); last error: %s\n",       \
              __FILE__, __LINE__, #call, (int)got_, quadopt_status_string((int)got_),         \
              (int)(expected), quadopt_status_string((int)(expected)), quadopt_last_error()); \
    }                                                                                          \
  } while (0)

/* A 3x3-vertex patch of four unit quads (counter-clockwise), vertex 4 in the middle. */
#define GRID_N 9
#define GRID_Q 4
static const uint32_t grid_quads[4 * GRID_Q] = {0, 1, 4, 3, 1, 2, 5, 4, 3, 4, 7, 6, 4, 5, 8, 7};

static void grid_coords(double *xy, double cx, double cy) {
  int i, j;
  for (j = 0; j < 3; ++j) {
    for (i = 0; i < 3; ++i) {
      xy[2 * (3 * j + i)] = (double)i;
      xy[2 * (3 * j + i) + 1] = (double)j;
    }
  }
  xy[8] = cx;
  xy[9] = cy;
}

/* The signed scaled Jacobian of a quad, computed independently of the library: the minimum
 * over the corners of the cross product of the two normalized edges leaving the corner. */
static double scaled_jacobian(const double *xy, unsigned dim, const uint32_t *q) {
  double best = 1.0;
  int c;
  for (c = 0; c < 4; ++c) {
    const double *p = xy + dim * q[c];
    const double *a = xy + dim * q[(c + 1) % 4];
    const double *b = xy + dim * q[(c + 3) % 4];
    double ux = a[0] - p[0], uy = a[1] - p[1], vx = b[0] - p[0], vy = b[1] - p[1];
    double sj = (ux * vy - uy * vx) / (sqrt(ux * ux + uy * uy) * sqrt(vx * vx + vy * vy));
    if (sj < best) best = sj;
  }
  return best;
}

static int last_error_mentions(const char *word) {
  const char *e = quadopt_last_error();
  return e != NULL && strstr(e, word) != NULL;
}

static void test_version_and_strings(void) {
  uint32_t major = 99, minor = 99, patch = 99;
  char expected[64];
  int s;
  quadopt_version_numbers(&major, &minor, &patch);
  CHECK(major == QUADOPT_VERSION_MAJOR && minor == QUADOPT_VERSION_MINOR && patch == QUADOPT_VERSION_PATCH);
  sprintf(expected, "%u.%u.%u", (unsigned)major, (unsigned)minor, (unsigned)patch);
  CHECK(strcmp(quadopt_version(), expected) == 0);
  quadopt_version_numbers(NULL, NULL, NULL); /* each may be NULL */
  quadopt_version_numbers(NULL, &minor, NULL);
  CHECK(minor == QUADOPT_VERSION_MINOR);

  /* Every status has its own non-empty string; anything else is "unknown status". */
  for (s = 0; s <= 14; ++s) {
    int t;
    CHECK(quadopt_status_string(s) != NULL && quadopt_status_string(s)[0] != '\0');
    CHECK(strcmp(quadopt_status_string(s), "unknown status") != 0);
    for (t = 0; t < s; ++t) CHECK(strcmp(quadopt_status_string(s), quadopt_status_string(t)) != 0);
  }
  CHECK(strcmp(quadopt_status_string(QUADOPT_STATUS_OK), "ok") == 0);
  CHECK(strcmp(quadopt_status_string(-1), "unknown status") == 0);
  CHECK(strcmp(quadopt_status_string(16), "unknown status") == 0);
  CHECK(strcmp(quadopt_status_string(2147483647), "unknown status") == 0);
  /* The enum values are the agreed ABI. */
  CHECK(QUADOPT_STATUS_OK == 0 && QUADOPT_STATUS_NULL_POINTER == 1 && QUADOPT_STATUS_INVALID_ARGUMENT == 2);
  CHECK(QUADOPT_STATUS_INVALID_OPTION == 3 && QUADOPT_STATUS_NO_QUADS == 4 && QUADOPT_STATUS_INDEX_OUT_OF_RANGE == 5);
  CHECK(QUADOPT_STATUS_REPEATED_VERTEX == 6 && QUADOPT_STATUS_NON_MANIFOLD == 7);
  CHECK(QUADOPT_STATUS_NON_FINITE_COORDINATE == 8 && QUADOPT_STATUS_NON_ORIENTABLE == 9);
  CHECK(QUADOPT_STATUS_MISMATCH == 10 && QUADOPT_STATUS_CANCELLED == 11 && QUADOPT_STATUS_PANIC == 12);
  CHECK(QUADOPT_STATUS_NOT_PLANAR == 13 && QUADOPT_STATUS_OUT_OF_MEMORY == 14);
  CHECK(strcmp(quadopt_status_string(QUADOPT_STATUS_OUT_OF_MEMORY), "out of memory") == 0);
  CHECK(QUADOPT_STATUS_CLOSED_MESH == 15);
  CHECK(strcmp(quadopt_status_string(QUADOPT_STATUS_CLOSED_MESH), "closed mesh") == 0);
  CHECK(QUADOPT_METHOD_EMBEDDED_POLYGON == 0 && QUADOPT_METHOD_LAPLACIAN == 1 && QUADOPT_METHOD_COTANGENT == 2 &&
        QUADOPT_METHOD_ANGLE_BASED == 3);
  CHECK(QUADOPT_BOUNDARY_AUTO == 0 && QUADOPT_BOUNDARY_FIXED == 1 && QUADOPT_BOUNDARY_SLIDE == 2 &&
        QUADOPT_BOUNDARY_SNAP == 3);
}

static void test_defaults(void) {
  QuadoptOptions o, v;
  QuadoptReport r;
  const unsigned char *bytes;
  size_t i;
  int zero = 1;
  memset(&o, 0xAB, sizeof o);
  CHECK_STATUS(quadopt_options_init(&o, sizeof o), QUADOPT_STATUS_OK);
  CHECK_STATUS(quadopt_options_init(NULL, sizeof o), QUADOPT_STATUS_NULL_POINTER);
  CHECK(o.struct_size == sizeof(QuadoptOptions));
  CHECK(o.method == QUADOPT_METHOD_EMBEDDED_POLYGON);
  CHECK(o.boundary == QUADOPT_BOUNDARY_AUTO);
  CHECK(o.max_iterations == 1000);
  CHECK(o.lambda == 1.0);
  CHECK(o.tau == 1e-7);
  CHECK(o.feature_angle_deg == 45.0);
  CHECK(o.guard_floor == 0.05);
  CHECK(o.max_boundary_deviation < 0.0);
  CHECK(o.tau_absolute == 0 && o.guard == 1 && o.untangle == 1 && o.keep_best == 1);
  CHECK(o.progress == NULL && o.progress_user_data == NULL);
  /* The same defaults whatever the struct held before. */
  memset(&v, 0x00, sizeof v);
  CHECK_STATUS(quadopt_options_init(&v, sizeof v), QUADOPT_STATUS_OK);
  CHECK(v.struct_size == o.struct_size && v.method == o.method && v.boundary == o.boundary &&
        v.max_iterations == o.max_iterations && v.lambda == o.lambda && v.tau == o.tau &&
        v.feature_angle_deg == o.feature_angle_deg && v.guard_floor == o.guard_floor &&
        v.max_boundary_deviation == o.max_boundary_deviation && v.tau_absolute == o.tau_absolute &&
        v.guard == o.guard && v.untangle == o.untangle && v.keep_best == o.keep_best && v.progress == NULL);

  /* quadopt_options_init: the same defaults, for exactly the caller's struct size. */
  {
    union {
      QuadoptOptions o;
      unsigned char bytes[sizeof(QuadoptOptions) + 16];
    } big;
    QuadoptOptions w;
    int tail_untouched = 1;
    memset(&big, 0xEE, sizeof big);
    CHECK_STATUS(quadopt_options_init(&big.o, sizeof big), QUADOPT_STATUS_OK);
    CHECK(big.o.struct_size == sizeof(QuadoptOptions)); /* what the library filled */
    CHECK(big.o.lambda == o.lambda && big.o.tau == o.tau && big.o.max_iterations == o.max_iterations &&
          big.o.guard == o.guard && big.o.progress == NULL);
    for (i = sizeof(QuadoptOptions); i < sizeof big; ++i) tail_untouched = tail_untouched && big.bytes[i] == 0xEE;
    CHECK(tail_untouched);
    memset(&w, 0xEE, sizeof w);
    CHECK_STATUS(quadopt_options_init(&w, sizeof w), QUADOPT_STATUS_OK);
    CHECK(w.struct_size == sizeof w && w.feature_angle_deg == 45.0 && w.boundary == QUADOPT_BOUNDARY_AUTO);
    CHECK_STATUS(quadopt_options_init(NULL, sizeof w), QUADOPT_STATUS_NULL_POINTER);
    memset(&w, 0xEE, sizeof w);
    CHECK_STATUS(quadopt_options_init(&w, 8), QUADOPT_STATUS_INVALID_ARGUMENT);
    CHECK(w.struct_size == 0xEEEEEEEEu && w.method == 0xEEEEEEEEu); /* nothing written */
  }

  r = quadopt_report_init();
  CHECK(r.struct_size == sizeof(QuadoptReport));
  bytes = (const unsigned char *)&r;
  for (i = offsetof(QuadoptReport, converged); i < sizeof r; ++i) zero = zero && bytes[i] == 0;
  CHECK(zero);
}

static void test_quality(void) {
  double xy[2 * GRID_N], per_quad[GRID_Q + 1];
  double expected_min = 1.0, expected_max = -1.0, expected_sum = 0.0;
  size_t expected_inverted = 0;
  QuadoptQuality q;
  int k;
  grid_coords(xy, 1.6, 1.5);
  per_quad[GRID_Q] = -42.0; /* past quad_count: must not be written */
  CHECK_STATUS(quadopt_quality(xy, 2, GRID_N, grid_quads, GRID_Q, &q, per_quad, GRID_Q + 1), QUADOPT_STATUS_OK);
  for (k = 0; k < GRID_Q; ++k) {
    double sj = scaled_jacobian(xy, 2, grid_quads + 4 * k);
    CHECK(fabs(per_quad[k] - sj) <= 1e-15);
    if (sj < expected_min) expected_min = sj;
    if (sj > expected_max) expected_max = sj;
    expected_sum += sj;
    expected_inverted += sj <= 0.0;
  }
  CHECK(per_quad[GRID_Q] == -42.0);
  CHECK(fabs(q.min - expected_min) <= 1e-15 && fabs(q.max - expected_max) <= 1e-15);
  CHECK(fabs(q.avg - expected_sum / GRID_Q) <= 1e-15);
  /* Quad 3 = (1.6,1.5) (2,1) (2,2) (1,2) is concave at the centre: by hand, the corner there
   * has cross((0.4,-0.5), (-0.6,0.5)) = 0.2 - 0.3 < 0, so it counts as inverted. */
  CHECK(q.inverted == 1 && expected_inverted == 1 && per_quad[3] < 0.0);
  /* Quad 0 = (0,0) (1,0) (1.6,1.5) (0,1): the smallest corner is at (1.6,1.5), between the
   * edges to (0,1) = (-1.6,-0.5) and to (1,0) = (-0.6,-1.5). By hand:
   * cross((-0.6,-1.5), (-1.6,-0.5)) / (|..| |..|) = (0.3 - 2.4) / (sqrt(2.61) sqrt(2.81)). */
  CHECK(fabs(per_quad[0] - (0.6 * 0.5 * -1.0 + 1.5 * 1.6) / (sqrt(2.61) * sqrt(2.81))) <= 1e-15);

  /* The unit grid: every quad is a square. */
  grid_coords(xy, 1.0, 1.0);
  CHECK_STATUS(quadopt_quality(xy, 2, GRID_N, grid_quads, GRID_Q, &q, NULL, 0), QUADOPT_STATUS_OK);
  CHECK(q.min == 1.0 && q.max == 1.0 && q.avg == 1.0 && q.inverted == 0);

  /* Dragging the centre across the right-hand edge inverts quads 0 and 2. */
  grid_coords(xy, 2.5, 1.0);
  CHECK_STATUS(quadopt_quality(xy, 2, GRID_N, grid_quads, GRID_Q, &q, per_quad, GRID_Q), QUADOPT_STATUS_OK);
  CHECK(q.inverted == 2 && per_quad[1] <= 0.0 && per_quad[3] <= 0.0 && q.min <= 0.0);
}

static void test_optimize(void) {
  double xy[2 * GRID_N], xyz[3 * GRID_N], before[2 * GRID_N];
  QuadoptOptions o;
  QuadoptReport r;
  int i;
  grid_coords(xy, 1.6, 1.5);
  memcpy(before, xy, sizeof xy);
  CHECK_STATUS(quadopt_options_init(&o, sizeof o), QUADOPT_STATUS_OK);
  o.tau = 1e-14;
  r = quadopt_report_init();
  CHECK_STATUS(quadopt_optimize(xy, 2, GRID_N, grid_quads, GRID_Q, NULL, &o, &r), QUADOPT_STATUS_OK);
  /* The corners of the square never move; the 4 edge midpoints may slide along straight sides
   * and the centre goes back to (1, 1). */
  CHECK(memcmp(xy, before, 2 * sizeof(double)) == 0);
  CHECK(memcmp(xy + 4, before + 4, 2 * sizeof(double)) == 0);
  CHECK(memcmp(xy + 12, before + 12, 2 * sizeof(double)) == 0);
  CHECK(memcmp(xy + 16, before + 16, 2 * sizeof(double)) == 0);
  CHECK(fabs(xy[8] - 1.0) < 1e-3 && fabs(xy[9] - 1.0) < 1e-3);
  CHECK(xy[3] == 0.0 && xy[6] == 0.0 && xy[10] == 2.0 && xy[15] == 2.0); /* midpoints stay on the sides */
  CHECK(r.struct_size == sizeof(QuadoptReport));
  CHECK(r.corners == 4);
  CHECK(r.movable == 5);
  CHECK(r.input.min < 0.8 && r.output.min > 0.999 && r.output.inverted == 0);
  CHECK(r.iterations >= 1 && r.converged == 1);
  CHECK(r.loops_slide + r.loops_snap + r.loops_fixed == 1);

  /* dim 3 with the same z at every vertex (a planar mesh): the same x and y, z never written
     (a z that is one NaN everywhere is never even used). */
  grid_coords(xy, 1.6, 1.5);
  for (i = 0; i < GRID_N; ++i) {
    xyz[3 * i] = xy[2 * i];
    xyz[3 * i + 1] = xy[2 * i + 1];
    xyz[3 * i + 2] = NAN;
  }
  CHECK_STATUS(quadopt_optimize(xyz, 3, GRID_N, grid_quads, GRID_Q, NULL, &o, NULL), QUADOPT_STATUS_OK);
  CHECK_STATUS(quadopt_optimize(xy, 2, GRID_N, grid_quads, GRID_Q, NULL, &o, NULL), QUADOPT_STATUS_OK);
  for (i = 0; i < GRID_N; ++i) {
    CHECK(xyz[3 * i] == xy[2 * i] && xyz[3 * i + 1] == xy[2 * i + 1]);
    CHECK(isnan(xyz[3 * i + 2]));
  }

  /* A fixed centre stays where it is, bit for bit; NULL options are the defaults. */
  {
    uint8_t fixed[GRID_N] = {0, 0, 0, 0, 7, 0, 0, 0, 0};
    grid_coords(xy, 1.6, 1.5);
    CHECK_STATUS(quadopt_optimize(xy, 2, GRID_N, grid_quads, GRID_Q, fixed, NULL, NULL), QUADOPT_STATUS_OK);
    CHECK(xy[8] == 1.6 && xy[9] == 1.5);
  }
  /* With a fixed boundary only the centre moves. */
  grid_coords(xy, 1.6, 1.5);
  o.boundary = QUADOPT_BOUNDARY_FIXED;
  CHECK_STATUS(quadopt_optimize(xy, 2, GRID_N, grid_quads, GRID_Q, NULL, &o, &r), QUADOPT_STATUS_OK);
  CHECK(memcmp(xy, before, 8 * sizeof(double)) == 0 && memcmp(xy + 10, before + 10, 8 * sizeof(double)) == 0);
  CHECK(r.movable == 1 && fabs(xy[8] - 1.0) < 1e-3);
}

static void test_handle(void) {
  double a[2 * GRID_N], b[2 * GRID_N], ref[2 * GRID_N];
  QuadoptOptimizer *h = NULL;
  QuadoptReport r1 = quadopt_report_init(), r2 = quadopt_report_init();
  grid_coords(a, 1.6, 1.5);
  CHECK_STATUS(quadopt_optimizer_create(a, 2, GRID_N, grid_quads, GRID_Q, NULL, &h), QUADOPT_STATUS_OK);
  CHECK(h != NULL);
  /* The handle gives what quadopt_optimize gives, for any coordinates of the connectivity. */
  grid_coords(ref, 0.7, 1.2);
  CHECK_STATUS(quadopt_optimize(ref, 2, GRID_N, grid_quads, GRID_Q, NULL, NULL, &r1), QUADOPT_STATUS_OK);
  grid_coords(b, 0.7, 1.2);
  CHECK_STATUS(quadopt_optimizer_optimize(h, b, 2, GRID_N, NULL, &r2), QUADOPT_STATUS_OK);
  CHECK(memcmp(b, ref, sizeof b) == 0);
  CHECK(r1.iterations == r2.iterations && r1.output.min == r2.output.min && r1.corners == r2.corners);
  /* ... and again: the handle is not changed by a run. */
  grid_coords(b, 0.7, 1.2);
  CHECK_STATUS(quadopt_optimizer_optimize(h, b, 2, GRID_N, NULL, NULL), QUADOPT_STATUS_OK);
  CHECK(memcmp(b, ref, sizeof b) == 0);
  quadopt_optimizer_free(h);
  quadopt_optimizer_free(NULL);
}

static void test_growable_structs(void) {
  /* A newer caller's larger structs: the library reads and writes only the prefix it knows. */
  union {
    QuadoptOptions o;
    unsigned char bytes[sizeof(QuadoptOptions) + 32];
  } big_o;
  union {
    QuadoptReport r;
    unsigned char bytes[sizeof(QuadoptReport) + 32];
  } big_r;
  double xy[2 * GRID_N];
  size_t i;
  int untouched = 1;
  memset(&big_o, 0x5A, sizeof big_o);
  CHECK_STATUS(quadopt_options_init(&big_o.o, sizeof big_o.o), QUADOPT_STATUS_OK);
  big_o.o.struct_size = (uint32_t)sizeof big_o;
  memset(&big_r, 0xC3, sizeof big_r);
  big_r.r.struct_size = (uint32_t)sizeof big_r;
  grid_coords(xy, 1.6, 1.5);
  CHECK_STATUS(quadopt_optimize(xy, 2, GRID_N, grid_quads, GRID_Q, NULL, &big_o.o, &big_r.r), QUADOPT_STATUS_OK);
  CHECK(big_r.r.struct_size == sizeof(QuadoptReport)); /* tells the caller how much was written */
  CHECK(big_r.r.corners == 4);
  for (i = sizeof(QuadoptReport); i < sizeof big_r; ++i) untouched = untouched && big_r.bytes[i] == 0xC3;
  CHECK(untouched);
}

/* The effort presets: the report says which ran; fast runs at most 6 sweeps (Effort::FAST_SWEEPS) and no max-min
   stage; a caller's struct from before `effort` (the previous size) runs balanced, and a report
   of that size is written without the field. */
static void test_effort(void) {
  double xy[2 * GRID_N], balanced[2 * GRID_N];
  QuadoptOptions o;
  QuadoptReport r;
  CHECK_STATUS(quadopt_options_init(&o, sizeof o), QUADOPT_STATUS_OK);
  CHECK(o.effort == QUADOPT_EFFORT_BALANCED && QUADOPT_EFFORT_BALANCED == 0);
  o.effort = QUADOPT_EFFORT_FAST;
  r = quadopt_report_init();
  grid_coords(xy, 1.6, 1.5);
  CHECK_STATUS(quadopt_optimize(xy, 2, GRID_N, grid_quads, GRID_Q, NULL, &o, &r), QUADOPT_STATUS_OK);
  CHECK(r.effort == QUADOPT_EFFORT_FAST && r.max_min == 0 && r.iterations <= 6);
  CHECK(r.output.inverted == 0 && r.output.min > r.input.min);
  o.effort = QUADOPT_EFFORT_BEST;
  r = quadopt_report_init();
  grid_coords(xy, 1.6, 1.5);
  CHECK_STATUS(quadopt_optimize(xy, 2, GRID_N, grid_quads, GRID_Q, NULL, &o, &r), QUADOPT_STATUS_OK);
  CHECK(r.effort == QUADOPT_EFFORT_BEST && r.output.min > r.input.min);
  /* The previous version's sizes: options end before `effort`, the report before its `effort`.
     The result must be balanced's, bit for bit. */
  o.effort = QUADOPT_EFFORT_BALANCED;
  grid_coords(balanced, 1.6, 1.5);
  CHECK_STATUS(quadopt_optimize(balanced, 2, GRID_N, grid_quads, GRID_Q, NULL, &o, NULL), QUADOPT_STATUS_OK);
  o.effort = QUADOPT_EFFORT_FAST; /* beyond the declared size: not read */
  o.struct_size = (uint32_t)offsetof(QuadoptOptions, effort);
  memset(&r, 0x3C, sizeof r);
  r.struct_size = (uint32_t)offsetof(QuadoptReport, effort);
  grid_coords(xy, 1.6, 1.5);
  CHECK_STATUS(quadopt_optimize(xy, 2, GRID_N, grid_quads, GRID_Q, NULL, &o, &r), QUADOPT_STATUS_OK);
  CHECK(r.struct_size == offsetof(QuadoptReport, effort));
  CHECK(r.effort == 0x3C3C3C3Cu); /* not written */
  CHECK(memcmp(xy, balanced, sizeof xy) == 0);
}

/* A run of quadopt_optimize that must fail with `expected`, writing nothing. */
static void expect_failure(QuadoptStatus expected, double *coords, uint32_t dim, size_t n, const uint32_t *quads,
                           size_t nq, const uint8_t *fixed, const QuadoptOptions *o, const char *mention, int line) {
  QuadoptReport r, r_before;
  double *before = NULL;
  size_t len = (coords != NULL && n < 1000) ? n * dim : 0;
  QuadoptStatus s;
  memset(&r, 0x77, sizeof r);
  r.struct_size = sizeof r;
  r_before = r;
  if (len) {
    before = (double *)malloc(len * sizeof(double));
    memcpy(before, coords, len * sizeof(double));
  }
  s = quadopt_optimize(coords, dim, n, quads, nq, fixed, o, &r);
  if (s != expected) {
    fprintf(stderr, "line %d: status %d (%s), expected %d (%s): %s\n", line, (int)s, quadopt_status_string((int)s),
            (int)expected, quadopt_status_string((int)expected), quadopt_last_error());
  }
  CHECK(s == expected);
  CHECK(memcmp(&r, &r_before, sizeof r) == 0);
  if (len) {
    CHECK(memcmp(coords, before, len * sizeof(double)) == 0);
  }
  CHECK(quadopt_last_error()[0] != '\0');
  if (mention && !last_error_mentions(mention)) {
    fprintf(stderr, "line %d: last error \"%s\" does not mention \"%s\"\n", line, quadopt_last_error(), mention);
    CHECK(0);
  }
  free(before);
}

#define EXPECT_FAILURE(status, coords, dim, n, quads, nq, fixed, o, mention) \
  expect_failure(status, coords, dim, n, quads, nq, fixed, o, mention, __LINE__)

/* The patch with its upper right quad (4, 5, 8, 7) split into the triangles (4, 5, 8) and
 * (4, 8, 7): three quads and two triangles, a triangle's fourth index QUADOPT_NO_VERTEX. */
#define MIXED_F 5
static const uint32_t mixed_faces[4 * MIXED_F] = {0, 1, 4, 3, 1, 2, 5, 4, 3, 4, 7, 6,
                                                  4, 5, 8, QUADOPT_NO_VERTEX, 4, 8, 7, QUADOPT_NO_VERTEX};

/* Verdict's triangle scaled Jacobian, computed independently of the library: twice the signed
 * area over the largest product of two edge lengths, times 2/sqrt(3). */
static double triangle_scaled_jacobian(const double *xy, const uint32_t *t) {
  const double *a = xy + 2 * t[0], *b = xy + 2 * t[1], *c = xy + 2 * t[2];
  double cross = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
  double lab = hypot(b[0] - a[0], b[1] - a[1]), lbc = hypot(c[0] - b[0], c[1] - b[1]);
  double lca = hypot(a[0] - c[0], a[1] - c[1]);
  double m = lab * lbc;
  if (lbc * lca > m) m = lbc * lca;
  if (lca * lab > m) m = lca * lab;
  return cross / m * 2.0 / sqrt(3.0);
}

/* The statistics of the faces of one kind among `values`, summed in face order as the library
 * does (so the same bits). */
static QuadoptFaceKindQuality kind_stats(const double *values, const uint32_t *faces, size_t n, int triangles) {
  QuadoptFaceKindQuality k;
  double sum = 0.0;
  size_t f;
  k.count = 0;
  k.min = NAN;
  k.avg = NAN;
  for (f = 0; f < n; ++f) {
    if ((faces[4 * f + 3] == QUADOPT_NO_VERTEX) != (triangles != 0)) continue;
    if (k.count == 0 || values[f] < k.min) k.min = values[f];
    sum += values[f];
    ++k.count;
  }
  if (k.count > 0) k.avg = sum / (double)k.count;
  return k;
}

static int same_kind(QuadoptFaceKindQuality a, QuadoptFaceKindQuality b) {
  return a.count == b.count && memcmp(&a.min, &b.min, sizeof a.min) == 0 && memcmp(&a.avg, &b.avg, sizeof a.avg) == 0;
}

static void test_mixed(void) {
  double xy[2 * GRID_N], before[2 * GRID_N], again[2 * GRID_N], per_face[MIXED_F + 1], per_out[MIXED_F];
  QuadoptQuality q;
  QuadoptReport r;
  QuadoptOptimizer *h = NULL;
  int f, i;
  /* Quality, face by face: the quads as before, the triangles Verdict's. */
  grid_coords(xy, 1.6, 1.5);
  per_face[MIXED_F] = -42.0;
  CHECK_STATUS(quadopt_quality(xy, 2, GRID_N, mixed_faces, MIXED_F, &q, per_face, MIXED_F + 1), QUADOPT_STATUS_OK);
  CHECK(per_face[MIXED_F] == -42.0);
  for (f = 0; f < MIXED_F; ++f) {
    const uint32_t *face = mixed_faces + 4 * f;
    double want = face[3] == QUADOPT_NO_VERTEX ? triangle_scaled_jacobian(xy, face) : scaled_jacobian(xy, 2, face);
    CHECK(fabs(per_face[f] - want) <= 1e-15);
  }
  /* The unit patch: squares score 1, and each triangle is half a square, a right isosceles
   * triangle: (1 / sqrt(2)) * 2 / sqrt(3) = sqrt(2/3) by hand. */
  grid_coords(xy, 1.0, 1.0);
  CHECK_STATUS(quadopt_quality(xy, 2, GRID_N, mixed_faces, MIXED_F, &q, per_face, MIXED_F), QUADOPT_STATUS_OK);
  CHECK(per_face[0] == 1.0 && per_face[1] == 1.0 && per_face[2] == 1.0);
  CHECK(fabs(per_face[3] - sqrt(2.0 / 3.0)) <= 1e-15 && fabs(per_face[4] - sqrt(2.0 / 3.0)) <= 1e-15);
  CHECK(q.max == 1.0 && fabs(q.min - sqrt(2.0 / 3.0)) <= 1e-15 && q.inverted == 0);

  /* The centre dragged across the right-hand edge to (2.5, 1): quad (1, 2, 5, 4) and triangle
   * (4, 5, 8) are inverted (its signed area: cross((-0.5, 0), (-0.5, 1)) / 2 = -0.25). */
  grid_coords(xy, 2.5, 1.0);
  memcpy(before, xy, sizeof xy);
  CHECK_STATUS(quadopt_quality(xy, 2, GRID_N, mixed_faces, MIXED_F, &q, per_face, MIXED_F), QUADOPT_STATUS_OK);
  CHECK(per_face[1] <= 0.0 && per_face[3] <= 0.0 && q.inverted == 2);
  r = quadopt_report_init();
  CHECK_STATUS(quadopt_optimize(xy, 2, GRID_N, mixed_faces, MIXED_F, NULL, NULL, &r), QUADOPT_STATUS_OK);
  CHECK(r.struct_size == sizeof(QuadoptReport));
  /* Per kind: counts, and min and avg as the per-face values give them, bit for bit. */
  CHECK(r.input_quads.count == 3 && r.input_triangles.count == 2);
  CHECK(r.output_quads.count == 3 && r.output_triangles.count == 2);
  CHECK(same_kind(r.input_quads, kind_stats(per_face, mixed_faces, MIXED_F, 0)));
  CHECK(same_kind(r.input_triangles, kind_stats(per_face, mixed_faces, MIXED_F, 1)));
  CHECK(r.input.inverted == 2 && r.input_triangles.min <= 0.0 && r.input_quads.min <= 0.0);
  CHECK_STATUS(quadopt_quality(xy, 2, GRID_N, mixed_faces, MIXED_F, &q, per_out, MIXED_F), QUADOPT_STATUS_OK);
  CHECK(same_kind(r.output_quads, kind_stats(per_out, mixed_faces, MIXED_F, 0)));
  CHECK(same_kind(r.output_triangles, kind_stats(per_out, mixed_faces, MIXED_F, 1)));
  /* Untangled, the minimum raised, the square's corners where they were, the centre back
   * inside (the side midpoints may slide along the straight sides). */
  CHECK(r.output.inverted == 0 && q.inverted == 0 && r.output.min > r.input.min);
  CHECK(r.output_triangles.min > 0.0 && r.output_quads.min > 0.0);
  CHECK(r.output.min == q.min && r.output.min == fmin(r.output_quads.min, r.output_triangles.min));
  CHECK(memcmp(xy, before, 2 * sizeof(double)) == 0 && memcmp(xy + 4, before + 4, 2 * sizeof(double)) == 0);
  CHECK(memcmp(xy + 12, before + 12, 2 * sizeof(double)) == 0 && memcmp(xy + 16, before + 16, 2 * sizeof(double)) == 0);
  CHECK(xy[8] > 0.0 && xy[8] < 2.0 && xy[9] > 0.0 && xy[9] < 2.0);
  CHECK(xy[3] == 0.0 && xy[6] == 0.0 && xy[10] == 2.0 && xy[15] == 2.0);

  /* A fixed centre keeps its bits; only the four side midpoints may move. */
  {
    uint8_t fixed[GRID_N] = {0, 0, 0, 0, 1, 0, 0, 0, 0};
    grid_coords(xy, 1.3, 1.2);
    CHECK_STATUS(quadopt_optimize(xy, 2, GRID_N, mixed_faces, MIXED_F, fixed, NULL, &r), QUADOPT_STATUS_OK);
    CHECK(xy[8] == 1.3 && xy[9] == 1.2);
    CHECK(r.movable == 4 && r.output.min >= r.input.min);
  }

  /* The handle takes the same faces and gives the same result. */
  grid_coords(xy, 2.5, 1.0);
  CHECK_STATUS(quadopt_optimizer_create(xy, 2, GRID_N, mixed_faces, MIXED_F, NULL, &h), QUADOPT_STATUS_OK);
  memcpy(again, before, sizeof again);
  CHECK_STATUS(quadopt_optimize(again, 2, GRID_N, mixed_faces, MIXED_F, NULL, NULL, NULL), QUADOPT_STATUS_OK);
  r = quadopt_report_init();
  CHECK_STATUS(quadopt_optimizer_optimize(h, xy, 2, GRID_N, NULL, &r), QUADOPT_STATUS_OK);
  CHECK(memcmp(xy, again, sizeof xy) == 0 && r.output_triangles.count == 2);
  quadopt_optimizer_free(h);

  /* A quad mesh: no triangles, so count 0 and NaN statistics. */
  grid_coords(xy, 1.6, 1.5);
  r = quadopt_report_init();
  CHECK_STATUS(quadopt_optimize(xy, 2, GRID_N, grid_quads, GRID_Q, NULL, NULL, &r), QUADOPT_STATUS_OK);
  CHECK(r.input_quads.count == GRID_Q && r.output_quads.count == GRID_Q && r.output_quads.min == r.output.min);
  CHECK(r.input_triangles.count == 0 && isnan(r.input_triangles.min) && isnan(r.input_triangles.avg));
  CHECK(r.output_triangles.count == 0 && isnan(r.output_triangles.min) && isnan(r.output_triangles.avg));

  /* A report of the size before the per-kind fields (0.2): written up to there, not beyond. */
  {
    union {
      QuadoptReport r;
      unsigned char bytes[sizeof(QuadoptReport)];
    } old;
    const size_t old_size = offsetof(QuadoptReport, input_quads);
    size_t b;
    int untouched = 1;
    memset(&old, 0xC3, sizeof old);
    old.r.struct_size = (uint32_t)old_size;
    grid_coords(xy, 2.5, 1.0);
    CHECK_STATUS(quadopt_optimize(xy, 2, GRID_N, mixed_faces, MIXED_F, NULL, NULL, &old.r), QUADOPT_STATUS_OK);
    CHECK(old.r.struct_size == old_size && old.r.output.inverted == 0 && old.r.effort == QUADOPT_EFFORT_BALANCED);
    for (b = old_size; b < sizeof old; ++b) untouched = untouched && old.bytes[b] == 0xC3;
    CHECK(untouched);
  }

  /* QUADOPT_NO_VERTEX anywhere but in the fourth slot is an index out of range, and a face
   * given twice (as a triangle) is refused too; nothing written either way. */
  for (i = 0; i < 3; ++i) {
    uint32_t bad[4 * MIXED_F];
    memcpy(bad, mixed_faces, sizeof bad);
    bad[4 * 3 + i] = QUADOPT_NO_VERTEX;
    grid_coords(xy, 1.6, 1.5);
    EXPECT_FAILURE(QUADOPT_STATUS_INDEX_OUT_OF_RANGE, xy, 2, GRID_N, bad, MIXED_F, NULL, NULL, NULL);
  }
  {
    uint32_t bad[4 * MIXED_F];
    memcpy(bad, mixed_faces, sizeof bad);
    bad[4 * 4 + 1] = 4; /* (4, 4, 7): a repeated vertex */
    grid_coords(xy, 1.6, 1.5);
    EXPECT_FAILURE(QUADOPT_STATUS_REPEATED_VERTEX, xy, 2, GRID_N, bad, MIXED_F, NULL, NULL, NULL);
  }
}

static int cancel_calls = 0;
static bool cancel_at_third(const QuadoptProgress *p, void *user) {
  int *count = (int *)user;
  /* Sweeps count from 1; a call while untangling has iteration 0 and NaN energies. */
  CHECK(p != NULL && p->max_iterations == 1000 && p->pass >= 1 && p->pass <= p->passes);
  CHECK(p != NULL && (p->iteration >= 1 ? p->iteration <= 1000 : isnan(p->energy)));
  ++*count;
  ++cancel_calls;
  return *count < 3;
}

static void test_errors(void) {
  double xy[2 * GRID_N];
  QuadoptOptions o;
  QuadoptQuality q, q_before;
  QuadoptOptimizer *h = (QuadoptOptimizer *)&q; /* a sentinel that must not be overwritten */
  double per_quad[GRID_Q];
  grid_coords(xy, 1.6, 1.5);

  /* NULL pointers. */
  EXPECT_FAILURE(QUADOPT_STATUS_NULL_POINTER, NULL, 2, GRID_N, grid_quads, GRID_Q, NULL, NULL, "coords");
  EXPECT_FAILURE(QUADOPT_STATUS_NULL_POINTER, xy, 2, GRID_N, NULL, GRID_Q, NULL, NULL, "quads");
  memset(&q, 0x11, sizeof q);
  q_before = q;
  CHECK_STATUS(quadopt_quality(xy, 2, GRID_N, grid_quads, GRID_Q, NULL, NULL, 0), QUADOPT_STATUS_NULL_POINTER);
  CHECK_STATUS(quadopt_quality(NULL, 2, GRID_N, grid_quads, GRID_Q, &q, NULL, 0), QUADOPT_STATUS_NULL_POINTER);
  CHECK(memcmp(&q, &q_before, sizeof q) == 0);
  CHECK_STATUS(quadopt_optimizer_create(xy, 2, GRID_N, grid_quads, GRID_Q, NULL, NULL), QUADOPT_STATUS_NULL_POINTER);
  CHECK_STATUS(quadopt_optimizer_optimize(NULL, xy, 2, GRID_N, NULL, NULL), QUADOPT_STATUS_NULL_POINTER);
  CHECK(last_error_mentions("opt"));

  /* Invalid arguments: dimension, struct sizes, buffer length, overflowing counts. */
  EXPECT_FAILURE(QUADOPT_STATUS_INVALID_ARGUMENT, xy, 1, GRID_N, grid_quads, GRID_Q, NULL, NULL, "dim");
  EXPECT_FAILURE(QUADOPT_STATUS_INVALID_ARGUMENT, xy, 4, 4, grid_quads, 1, NULL, NULL, "dim");
  CHECK_STATUS(quadopt_options_init(&o, sizeof o), QUADOPT_STATUS_OK);
  o.struct_size = 0;
  EXPECT_FAILURE(QUADOPT_STATUS_INVALID_ARGUMENT, xy, 2, GRID_N, grid_quads, GRID_Q, NULL, &o, "struct_size");
  o.struct_size = (uint32_t)offsetof(QuadoptOptions, max_min) - 8; /* shorter than the first version */
  EXPECT_FAILURE(QUADOPT_STATUS_INVALID_ARGUMENT, xy, 2, GRID_N, grid_quads, GRID_Q, NULL, &o, "struct_size");
  {
    QuadoptReport small = quadopt_report_init();
    small.struct_size = (uint32_t)offsetof(QuadoptReport, iterations);
    CHECK_STATUS(quadopt_optimize(xy, 2, GRID_N, grid_quads, GRID_Q, NULL, NULL, &small),
                 QUADOPT_STATUS_INVALID_ARGUMENT);
    CHECK(small.struct_size == offsetof(QuadoptReport, iterations) && small.iterations == 0);
    CHECK(last_error_mentions("struct_size"));
  }
  CHECK_STATUS(quadopt_quality(xy, 2, GRID_N, grid_quads, GRID_Q, &q, per_quad, GRID_Q - 1),
               QUADOPT_STATUS_INVALID_ARGUMENT);
  CHECK(last_error_mentions("per_quad_len"));
  EXPECT_FAILURE(QUADOPT_STATUS_INVALID_ARGUMENT, xy, 3, SIZE_MAX / 2, grid_quads, GRID_Q, NULL, NULL, NULL);
  EXPECT_FAILURE(QUADOPT_STATUS_INVALID_ARGUMENT, xy, 2, GRID_N, grid_quads, SIZE_MAX / 3, NULL, NULL, NULL);

  /* Invalid options, each named in the message. */
#define BAD_OPTION(field, value)                                                                          \
  do {                                                                                                    \
    quadopt_options_init(&o, sizeof o);                                                                   \
    o.field = value;                                                                                      \
    EXPECT_FAILURE(QUADOPT_STATUS_INVALID_OPTION, xy, 2, GRID_N, grid_quads, GRID_Q, NULL, &o, #field); \
  } while (0)
  BAD_OPTION(lambda, 0.0);
  BAD_OPTION(lambda, 1.5);
  BAD_OPTION(lambda, NAN);
  BAD_OPTION(tau, -1.0);
  BAD_OPTION(tau, NAN);
  BAD_OPTION(tau, INFINITY);
  BAD_OPTION(max_iterations, 0);
  BAD_OPTION(feature_angle_deg, 181.0);
  BAD_OPTION(feature_angle_deg, -1.0);
  BAD_OPTION(guard_floor, 0.0);
  BAD_OPTION(guard_floor, 2.0);
  BAD_OPTION(method, 4);
  BAD_OPTION(boundary, 99);
  BAD_OPTION(max_boundary_deviation, NAN);
  BAD_OPTION(effort, 3);
#undef BAD_OPTION

  /* The mesh itself. */
  EXPECT_FAILURE(QUADOPT_STATUS_NO_QUADS, xy, 2, GRID_N, NULL, 0, NULL, NULL, NULL);
  EXPECT_FAILURE(QUADOPT_STATUS_NO_QUADS, xy, 2, GRID_N, grid_quads, 0, NULL, NULL, NULL);
  {
    uint32_t bad[4 * GRID_Q];
    memcpy(bad, grid_quads, sizeof bad);
    bad[6] = GRID_N; /* quad 1, corner 2 */
    EXPECT_FAILURE(QUADOPT_STATUS_INDEX_OUT_OF_RANGE, xy, 2, GRID_N, bad, GRID_Q, NULL, NULL, "quad 1");
    bad[6] = 0xFFFFFFFFu;
    EXPECT_FAILURE(QUADOPT_STATUS_INDEX_OUT_OF_RANGE, xy, 2, GRID_N, bad, GRID_Q, NULL, NULL, "4294967295");
    memcpy(bad, grid_quads, sizeof bad);
    bad[13] = bad[12]; /* quad 3 = 4 4 8 7 */
    EXPECT_FAILURE(QUADOPT_STATUS_REPEATED_VERTEX, xy, 2, GRID_N, bad, GRID_Q, NULL, NULL, "quad 3");
  }
  {
    /* Three quads on the edge (0, 1). */
    double p[2 * 8] = {0, 0, 1, 0, 1, 1, 0, 1, 1, -1, 0, -1, 0.5, 2, 0.5, -2};
    uint32_t nm[12] = {0, 1, 2, 3, 0, 5, 4, 1, 1, 0, 6, 7};
    EXPECT_FAILURE(QUADOPT_STATUS_NON_MANIFOLD, p, 2, 8, nm, 3, NULL, NULL, "(0, 1)");
  }
  {
    /* A Moebius strip of three quads: top t0 t1 t2 = 0 1 2, bottom b0 b1 b2 = 3 4 5; the last
     * quad joins t2-b2 to b0-t0 with a half twist. */
    double p[2 * 6] = {0, 1, 1, 1, 2, 1, 0, 0, 1, 0, 2, 0};
    uint32_t mq[12] = {0, 3, 4, 1, 1, 4, 5, 2, 2, 5, 0, 3};
    EXPECT_FAILURE(QUADOPT_STATUS_NON_ORIENTABLE, p, 2, 6, mq, 3, NULL, NULL, "orient");
  }
  {
    /* A closed mesh: a 6 x 6 grid whose quads wrap around in x and y (a torus, every vertex
     * interior). No orientation makes all its quads valid in the plane. */
    double p[2 * 36];
    uint32_t wq[4 * 36];
    uint32_t i, j;
    for (j = 0; j < 6; ++j) {
      for (i = 0; i < 6; ++i) {
        uint32_t *c = wq + 4 * (6 * j + i);
        p[2 * (6 * j + i)] = i;
        p[2 * (6 * j + i) + 1] = j;
        c[0] = 6 * j + i;
        c[1] = 6 * j + (i + 1) % 6;
        c[2] = 6 * ((j + 1) % 6) + (i + 1) % 6;
        c[3] = 6 * ((j + 1) % 6) + i;
      }
    }
    EXPECT_FAILURE(QUADOPT_STATUS_CLOSED_MESH, p, 2, 36, wq, 36, NULL, NULL, "the mesh is closed (it has no boundary edge)");
    CHECK_STATUS(quadopt_quality(p, 2, 36, wq, 36, &q, NULL, 0), QUADOPT_STATUS_CLOSED_MESH);
  }
  {
    double bad[2 * GRID_N];
    memcpy(bad, xy, sizeof bad);
    bad[9] = NAN;
    EXPECT_FAILURE(QUADOPT_STATUS_NON_FINITE_COORDINATE, bad, 2, GRID_N, grid_quads, GRID_Q, NULL, NULL, "vertex 4");
    bad[9] = 1.5;
    bad[14] = -INFINITY;
    EXPECT_FAILURE(QUADOPT_STATUS_NON_FINITE_COORDINATE, bad, 2, GRID_N, grid_quads, GRID_Q, NULL, NULL, "vertex 7");
    CHECK_STATUS(quadopt_quality(bad, 2, GRID_N, grid_quads, GRID_Q, &q, NULL, 0),
                 QUADOPT_STATUS_NON_FINITE_COORDINATE);
    CHECK(memcmp(&q, &q_before, sizeof q) == 0);
  }

  /* A handle used with another vertex count; creating from a bad mesh writes no handle. */
  {
    QuadoptOptimizer *good = NULL;
    double more[2 * (GRID_N + 1)];
    uint32_t bad[4 * GRID_Q];
    memcpy(bad, grid_quads, sizeof bad);
    bad[0] = 100;
    CHECK_STATUS(quadopt_optimizer_create(xy, 2, GRID_N, bad, GRID_Q, NULL, &h), QUADOPT_STATUS_INDEX_OUT_OF_RANGE);
    CHECK(h == (QuadoptOptimizer *)&q);
    CHECK_STATUS(quadopt_optimizer_create(xy, 2, GRID_N, grid_quads, GRID_Q, NULL, &good), QUADOPT_STATUS_OK);
    memcpy(more, xy, sizeof xy);
    more[2 * GRID_N] = more[2 * GRID_N + 1] = 5.0;
    CHECK_STATUS(quadopt_optimizer_optimize(good, more, 2, GRID_N + 1, NULL, NULL), QUADOPT_STATUS_MISMATCH);
    CHECK(last_error_mentions("10"));
    CHECK(more[8] == 1.6 && more[9] == 1.5);
    more[9] = NAN;
    CHECK_STATUS(quadopt_optimizer_optimize(good, more, 2, GRID_N, NULL, NULL), QUADOPT_STATUS_NON_FINITE_COORDINATE);
    CHECK_STATUS(quadopt_options_init(&o, sizeof o), QUADOPT_STATUS_OK);
    o.lambda = -1.0;
    CHECK_STATUS(quadopt_optimizer_optimize(good, xy, 2, GRID_N, &o, NULL), QUADOPT_STATUS_INVALID_OPTION);
    CHECK_STATUS(quadopt_optimizer_optimize(good, xy, 5, GRID_N, NULL, NULL), QUADOPT_STATUS_INVALID_ARGUMENT);
    CHECK_STATUS(quadopt_optimizer_optimize(good, NULL, 2, GRID_N, NULL, NULL), QUADOPT_STATUS_NULL_POINTER);
    quadopt_optimizer_free(good);
  }

  /* Cancellation by the progress callback: nothing written. */
  {
    int count = 0;
    CHECK_STATUS(quadopt_options_init(&o, sizeof o), QUADOPT_STATUS_OK);
    o.stop_rule = QUADOPT_STOP_RULE_ENERGY;
    o.tau = 0.0; /* the energy rule never stops: runs until cancelled */
    o.progress = cancel_at_third;
    o.progress_user_data = &count;
    EXPECT_FAILURE(QUADOPT_STATUS_CANCELLED, xy, 2, GRID_N, grid_quads, GRID_Q, NULL, &o, "cancel");
    CHECK(count == 3);
  }
  /* QUADOPT_STATUS_PANIC (a library bug) cannot be produced by input; its string was checked
   * above. QUADOPT_STATUS_NOT_PLANAR comes from a reusable handle given a curved mesh: see
   * test_surface and test_planarity. QUADOPT_STATUS_OUT_OF_MEMORY needs a memory limit: see
   * test_fork_and_memory_limits. */
}

#ifdef QUADOPT_TEST_POSIX
/* Runs `body` in a forked child that SIGALRM kills after 60 s (a call blocked forever);
 * returns whether the child exited with 0. */
static int child_succeeds(int (*body)(void)) {
  int status = 0;
  pid_t pid = fork();
  if (pid < 0) return 0;
  if (pid == 0) {
    alarm(60);
    _exit(body());
  }
  if (waitpid(pid, &status, 0) != pid) return 0;
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

/* The patch optimized in the parent before forking, to compare with the child's result. */
static double forked_expected[2 * GRID_N];

/* 0 when the call finishes with the parent's result. */
static int optimize_like_the_parent(void) {
  double xy[2 * GRID_N];
  grid_coords(xy, 1.6, 1.5);
  if (quadopt_optimize(xy, 2, GRID_N, grid_quads, GRID_Q, NULL, NULL, NULL) != QUADOPT_STATUS_OK) return 1;
  return memcmp(xy, forked_expected, sizeof xy) == 0 ? 0 : 2;
}

/* 0 when a child of the child (forked after the child's own calls) finishes too. */
static int optimize_then_fork_again(void) {
  int first = optimize_like_the_parent();
  return first != 0 ? first : child_succeeds(optimize_like_the_parent) ? 0 : 3;
}

#ifdef QUADOPT_TEST_AS_LIMIT
/* 20 million vertices (all but the first quad's unused: calloc'd pages never touched) under an
 * address-space limit of 64 MiB beyond the current size: too little for the library's copy
 * (320 MB), so every entry point returns QUADOPT_STATUS_OUT_OF_MEMORY instead of aborting. */
static int too_large_for_the_limit(void) {
  const size_t n = 20000000;
  double *xy = calloc(2 * n, sizeof(double));
  long pages = 0;
  FILE *statm = fopen("/proc/self/statm", "r");
  struct rlimit limit;
  QuadoptQuality q;
  QuadoptOptimizer *h = NULL;
  if (xy == NULL || statm == NULL || fscanf(statm, "%ld", &pages) != 1) return 10;
  fclose(statm);
  xy[2] = xy[7] = xy[8] = xy[9] = 1.0; /* quad 0 1 4 3 of grid_quads: the unit square */
  if (getrlimit(RLIMIT_AS, &limit) != 0) return 11;
  limit.rlim_cur = (rlim_t)pages * (rlim_t)sysconf(_SC_PAGESIZE) + ((rlim_t)64 << 20);
  if (setrlimit(RLIMIT_AS, &limit) != 0) return 12;
  if (quadopt_optimize(xy, 2, n, grid_quads, 1, NULL, NULL, NULL) != QUADOPT_STATUS_OUT_OF_MEMORY) return 1;
  if (strstr(quadopt_last_error(), "out of memory") == NULL) return 2;
  if (quadopt_quality(xy, 2, n, grid_quads, 1, &q, NULL, 0) != QUADOPT_STATUS_OUT_OF_MEMORY) return 3;
  if (quadopt_optimizer_create(xy, 2, n, grid_quads, 1, NULL, &h) != QUADOPT_STATUS_OUT_OF_MEMORY) return 4;
  if (h != NULL || xy[2] != 1.0) return 5;
  return 0;
}
#endif

static void test_fork_and_memory_limits(void) {
  /* The parent uses quadopt (starting its worker threads), then forks: the child's calls must
   * finish, with the same result, and so must a grandchild's. */
  grid_coords(forked_expected, 1.6, 1.5);
  CHECK_STATUS(quadopt_optimize(forked_expected, 2, GRID_N, grid_quads, GRID_Q, NULL, NULL, NULL),
               QUADOPT_STATUS_OK);
  CHECK(child_succeeds(optimize_then_fork_again));
  CHECK(optimize_like_the_parent() == 0);
#ifdef QUADOPT_TEST_AS_LIMIT
  CHECK(child_succeeds(too_large_for_the_limit));
#endif
}
#endif

/* A curved mesh: a 4 x 4 grid of quads on a quarter of the cylinder x^2 + y^2 = 1 (vertex
 * 5 j + i at angle i pi / 8, height 0.4 j), the centre vertex 12 pushed along the cylinder to
 * angle 2.6 pi / 8, optimized on its surface by quadopt_optimize_surface(). */
#define CYL_N 25
#define CYL_F 16
static const double kPi8 = 0.39269908169872414; /* pi / 8 */

static void cylinder_coords(double *xyz) {
  int i, j;
  for (j = 0; j < 5; ++j) {
    for (i = 0; i < 5; ++i) {
      xyz[3 * (5 * j + i)] = cos(i * kPi8);
      xyz[3 * (5 * j + i) + 1] = sin(i * kPi8);
      xyz[3 * (5 * j + i) + 2] = 0.4 * j;
    }
  }
  xyz[36] = cos(2.6 * kPi8);
  xyz[37] = sin(2.6 * kPi8);
}

static void cylinder_faces(uint32_t *faces) {
  uint32_t k;
  for (k = 0; k < CYL_F; ++k) {
    const uint32_t v = (k / 4) * 5 + k % 4;
    faces[4 * k] = v;
    faces[4 * k + 1] = v + 1;
    faces[4 * k + 2] = v + 6;
    faces[4 * k + 3] = v + 5;
  }
}

static void test_surface(void) {
  double xyz[3 * CYL_N], before[3 * CYL_N], again[3 * CYL_N];
  uint32_t faces[4 * CYL_F];
  uint8_t fixed[CYL_N];
  const uint32_t marked[8] = {1, 6, 6, 11, 16, 11, 16, 21}; /* the vertical line at angle pi / 8 */
  const uint32_t bad[4] = {1, 6, 0, 6};
  QuadoptReport r = quadopt_report_init(), r2 = quadopt_report_init(), sentinel;
  double tolerance = 0;
  int v, f, k, ok = 1;
  cylinder_coords(xyz);
  cylinder_faces(faces);
  memcpy(before, xyz, sizeof xyz);
  for (v = 0; v < CYL_N; ++v) fixed[v] = v < 5; /* the bottom row */
  /* The chordal tolerance: how far the faceted input is from the cylinder at most, the
   * sagitta of the widest face's angular span. */
  for (f = 0; f < CYL_F; ++f) {
    double lo = 10, hi = -10;
    for (k = 0; k < 4; ++k) {
      const double a = atan2(before[3 * faces[4 * f + k] + 1], before[3 * faces[4 * f + k]]);
      lo = a < lo ? a : lo;
      hi = a > hi ? a : hi;
    }
    if (1 - cos((hi - lo) / 2) > tolerance) tolerance = 1 - cos((hi - lo) / 2);
  }
  CHECK_STATUS(quadopt_optimize_surface(xyz, CYL_N, faces, CYL_F, fixed, NULL, 0, NULL, &r), QUADOPT_STATUS_OK);
  CHECK(r.struct_size == sizeof r && r.surface == 1);
  CHECK(r.output.min > r.input.min + 0.05 && r.output.inverted == 0);
  CHECK(r.output_verdict.min > r.input_verdict.min);
  CHECK(r.max_distance < 1e-9 && r.max_feature_distance < 1e-9 && r.corners >= 4 && r.feature_curves >= 1);
  for (v = 0; v < CYL_N; ++v) {
    const double off = hypot(xyz[3 * v], xyz[3 * v + 1]) - 1.0;
    ok = ok && off <= 1e-12 && -off <= tolerance + 1e-12;
    if (v < 5) ok = ok && memcmp(&xyz[3 * v], &before[3 * v], 3 * sizeof(double)) == 0;
  }
  CHECK(ok); /* on the cylinder within the chordal tolerance; fixed vertices bit for bit */
  /* Verdict's measure of the result, face by face: the report's output_verdict. */
  {
    QuadoptQuality vq;
    double per_face[CYL_F], lowest = 2;
    CHECK_STATUS(quadopt_verdict_quality(xyz, CYL_N, faces, CYL_F, &vq, per_face, CYL_F), QUADOPT_STATUS_OK);
    CHECK(vq.min == r.output_verdict.min && vq.avg == r.output_verdict.avg &&
          vq.inverted == r.output_verdict.inverted);
    for (f = 0; f < CYL_F; ++f) lowest = per_face[f] < lowest ? per_face[f] : lowest;
    CHECK(lowest == vq.min);
    CHECK_STATUS(quadopt_verdict_quality(xyz, CYL_N, faces, CYL_F, NULL, NULL, 0), QUADOPT_STATUS_NULL_POINTER);
    CHECK_STATUS(quadopt_verdict_quality(xyz, CYL_N, faces, CYL_F, &vq, per_face, CYL_F - 1),
                 QUADOPT_STATUS_INVALID_ARGUMENT);
  }
  /* quadopt_optimize with dim 3 takes the same path when z varies. */
  memcpy(again, before, sizeof before);
  CHECK_STATUS(quadopt_optimize(again, 3, CYL_N, faces, CYL_F, fixed, NULL, &r2), QUADOPT_STATUS_OK);
  CHECK(r2.surface == 1 && memcmp(again, xyz, sizeof xyz) == 0);
  /* The curve tolerance holds on a surface: with 0, no new edge along a curve leaves it, and
   * the report's boundary deviation measures the curves' new edges. */
  {
    QuadoptOptions o;
    CHECK_STATUS(quadopt_options_init(&o, sizeof o), QUADOPT_STATUS_OK);
    o.max_boundary_deviation = 0;
    memcpy(xyz, before, sizeof before);
    CHECK_STATUS(quadopt_optimize_surface(xyz, CYL_N, faces, CYL_F, NULL, NULL, 0, &o, &r), QUADOPT_STATUS_OK);
    CHECK(r.max_boundary_deviation < 1e-12 && r.max_boundary_deviation_relative < 1e-12);
    CHECK(r.output.min >= r.input.min && r.output.inverted <= r.input.inverted);
  }
  /* A marked line cuts the surface into two patches; its vertices stay on it. */
  memcpy(xyz, before, sizeof before);
  CHECK_STATUS(quadopt_optimize_surface(xyz, CYL_N, faces, CYL_F, NULL, marked, 4, NULL, &r), QUADOPT_STATUS_OK);
  CHECK(r.patches == 2);
  for (v = 6; v <= 16; v += 5) {
    CHECK(fabs(xyz[3 * v] - cos(kPi8)) < 1e-12 && fabs(xyz[3 * v + 1] - sin(kPi8)) < 1e-12);
  }
  /* Errors write nothing: a pair that is not an edge, NULL edges with a count. */
  memcpy(xyz, before, sizeof before);
  sentinel = quadopt_report_init();
  sentinel.iterations = 12345;
  r = sentinel;
  CHECK_STATUS(quadopt_optimize_surface(xyz, CYL_N, faces, CYL_F, NULL, bad, 2, NULL, &r),
               QUADOPT_STATUS_INVALID_ARGUMENT);
  CHECK(strstr(quadopt_last_error(), "feature edge 1, vertices (0, 6), is not an edge") != NULL);
  CHECK_STATUS(quadopt_optimize_surface(xyz, CYL_N, faces, CYL_F, NULL, NULL, 2, NULL, &r), QUADOPT_STATUS_NULL_POINTER);
  CHECK_STATUS(quadopt_optimize_surface(NULL, CYL_N, faces, CYL_F, NULL, NULL, 0, NULL, &r), QUADOPT_STATUS_NULL_POINTER);
  CHECK(memcmp(xyz, before, sizeof xyz) == 0 && memcmp(&r, &sentinel, sizeof r) == 0);
  /* A report of the size before the surface fields is filled up to that size only. */
  {
    const size_t old_size = offsetof(QuadoptReport, surface);
    QuadoptReport small = sentinel;
    small.struct_size = (uint32_t)old_size;
    small.surface = 77;
    small.max_distance = -5.0;
    CHECK_STATUS(quadopt_optimize_surface(xyz, CYL_N, faces, CYL_F, NULL, NULL, 0, NULL, &small), QUADOPT_STATUS_OK);
    CHECK(small.struct_size == old_size && small.surface == 77 && small.max_distance == -5.0);
    CHECK(small.output.min > small.input.min);
  }
  /* A reusable handle optimizes planar meshes only. */
  {
    QuadoptOptimizer *handle = NULL;
    CHECK_STATUS(quadopt_optimizer_create(before, 3, CYL_N, faces, CYL_F, NULL, &handle), QUADOPT_STATUS_NOT_PLANAR);
    CHECK(handle == NULL);
  }
}

/* The library's one planarity rule (quadopt_is_planar(), what quadopt_optimize() and the
 * handle decide with): a closed curved mesh given to a reusable handle is not planar, not
 * closed; a sheet whose z wobbles by 1e-4 is a surface (optimized on it, never flattened); an
 * exactly planar grid in a tilted plane is planar (optimized in its plane). */
#define SHEET_M 8
#define SHEET_N ((SHEET_M + 1) * (SHEET_M + 1))
#define SHEET_F (SHEET_M * SHEET_M)

static void sheet(double *xyz, uint32_t *faces, int tilted) {
  int i, j;
  for (j = 0; j <= SHEET_M; ++j) {
    for (i = 0; i <= SHEET_M; ++i) {
      double *p = &xyz[3 * (j * (SHEET_M + 1) + i)];
      p[0] = (double)i / SHEET_M;
      p[1] = (double)j / SHEET_M;
      if (i > 0 && i < SHEET_M && j > 0 && j < SHEET_M) {
        p[0] += 0.3 / SHEET_M * sin(7.0 * i + 3.0 * j);
        p[1] += 0.3 / SHEET_M * cos(5.0 * i - 2.0 * j);
      }
      p[2] = tilted ? 0.3 * p[0] + 0.7 * p[1] : 1e-4 * sin(8 * kPi8 * p[0]) * cos(8 * kPi8 * p[1]);
    }
  }
  for (j = 0; j < SHEET_F; ++j) {
    const uint32_t v = (uint32_t)((j / SHEET_M) * (SHEET_M + 1) + j % SHEET_M);
    faces[4 * j] = v;
    faces[4 * j + 1] = v + 1;
    faces[4 * j + 2] = v + SHEET_M + 2;
    faces[4 * j + 3] = v + SHEET_M + 1;
  }
}

static void test_planarity(void) {
  /* A cube of six quads, one corner pushed outward: closed and curved. */
  const double cube[24] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1.3, 1.3, 1.3, 0, 1, 1};
  const uint32_t sides[24] = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7};
  double xyz[3 * SHEET_N], before[3 * SHEET_N], again[3 * SHEET_N];
  uint32_t faces[4 * SHEET_F];
  QuadoptPlanarity p;
  QuadoptReport r = quadopt_report_init();
  QuadoptOptimizer *handle = NULL;
  double zmax = 0, off = 0;
  int v;
  CHECK_STATUS(quadopt_optimizer_create(cube, 3, 8, sides, 6, NULL, &handle), QUADOPT_STATUS_NOT_PLANAR);
  CHECK(handle == NULL && strstr(quadopt_last_error(), "quadopt_optimize_surface()") != NULL);
  CHECK_STATUS(quadopt_is_planar(cube, 8, sides, 6, &p), QUADOPT_STATUS_OK);
  CHECK(p.planar == 0 && p.distance > p.tolerance);
  CHECK_STATUS(quadopt_is_planar(cube, 8, sides, 6, NULL), QUADOPT_STATUS_NULL_POINTER);

  sheet(xyz, faces, 0);
  memcpy(before, xyz, sizeof xyz);
  CHECK_STATUS(quadopt_is_planar(xyz, SHEET_N, faces, SHEET_F, &p), QUADOPT_STATUS_OK);
  CHECK(p.planar == 0);
  CHECK_STATUS(quadopt_optimize(xyz, 3, SHEET_N, faces, SHEET_F, NULL, NULL, &r), QUADOPT_STATUS_OK);
  CHECK(r.surface == 1 && r.max_distance_relative <= 1e-9 && r.output.min > r.input.min);
  for (v = 0; v < SHEET_N; ++v) zmax = fabs(xyz[3 * v + 2]) > zmax ? fabs(xyz[3 * v + 2]) : zmax;
  CHECK(zmax > 0.5e-4); /* not flattened */
  CHECK_STATUS(quadopt_optimizer_create(before, 3, SHEET_N, faces, SHEET_F, NULL, &handle), QUADOPT_STATUS_NOT_PLANAR);

  sheet(xyz, faces, 1);
  memcpy(before, xyz, sizeof xyz);
  CHECK_STATUS(quadopt_is_planar(xyz, SHEET_N, faces, SHEET_F, &p), QUADOPT_STATUS_OK);
  CHECK(p.planar == 1);
  r = quadopt_report_init();
  CHECK_STATUS(quadopt_optimize(xyz, 3, SHEET_N, faces, SHEET_F, NULL, NULL, &r), QUADOPT_STATUS_OK);
  CHECK(r.surface == 0 && r.output.min > r.input.min);
  for (v = 0; v < SHEET_N; ++v) {
    const double d = fabs(0.3 * xyz[3 * v] + 0.7 * xyz[3 * v + 1] - xyz[3 * v + 2]);
    off = d > off ? d : off;
  }
  CHECK(off < 1e-14);                                          /* in the plane */
  CHECK(memcmp(xyz, before, 3 * sizeof(double)) == 0);         /* a corner is not written */
  memcpy(again, before, sizeof before);
  CHECK_STATUS(quadopt_optimizer_create(before, 3, SHEET_N, faces, SHEET_F, NULL, &handle), QUADOPT_STATUS_OK);
  CHECK_STATUS(quadopt_optimizer_optimize(handle, again, 3, SHEET_N, NULL, NULL), QUADOPT_STATUS_OK);
  CHECK(memcmp(again, xyz, sizeof xyz) == 0);
  quadopt_optimizer_free(handle);
}

int main(void) {
  /* Nothing failed on this thread yet. */
  CHECK(quadopt_last_error() != NULL && quadopt_last_error()[0] == '\0');
  test_version_and_strings();
  test_defaults();
  test_quality();
  test_optimize();
  test_handle();
  test_growable_structs();
  test_effort();
  test_errors();
  test_mixed();
  test_surface();
  test_planarity();
  CHECK(cancel_calls == 3);
#ifdef QUADOPT_TEST_POSIX
  test_fork_and_memory_limits();
#endif
  printf("c_api_test: %d passed, %d failed\n", passed, failed);
  return failed == 0 ? 0 : 1;
}
