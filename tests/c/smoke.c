/*
 * A C99 client of include/quadopt.h, compiled with -std=c99 -Wall -Wextra -Werror -pedantic
 * and linked against the cdylib by tests/bindgen.rs (c_client_compiles_links_and_runs).
 *
 * It drives every function once with a known answer and prints the struct layouts it was
 * compiled with ("layout NAME FIELD OFFSET" and "size NAME SIZE" lines) for the Rust side to
 * compare with src/ffi.rs. It prints "FAIL: ..." for each failed check and exits with the
 * number of failures; "ok" when every check passed.
 */
#include "quadopt.h"

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

static int failures = 0;

#define CHECK(cond)                                                                        \
    do {                                                                                   \
        if (!(cond)) {                                                                     \
            printf("FAIL: %s:%d: %s (last error: %s)\n", __FILE__, __LINE__, #cond,        \
                   quadopt_last_error());                                                  \
            failures++;                                                                    \
        }                                                                                  \
    } while (0)

#define LAYOUT(type, field) printf("layout %s %s %zu\n", #type, #field, offsetof(type, field))

/* A 2x2 patch of unit squares whose centre vertex 4 was dragged to (1.6, 1.5), with a z that
 * must never be written. */
static void patch(double coords[27]) {
    int i, j;
    for (j = 0; j < 3; j++) {
        for (i = 0; i < 3; i++) {
            coords[3 * (3 * j + i) + 0] = i;
            coords[3 * (3 * j + i) + 1] = j;
            coords[3 * (3 * j + i) + 2] = 100.0; /* planar: the same z everywhere */
        }
    }
    coords[12] = 1.6;
    coords[13] = 1.5;
}

static const uint32_t QUADS[16] = {0, 1, 4, 3, 1, 2, 5, 4, 3, 4, 7, 6, 4, 5, 8, 7};

static bool cancel_at_second(const QuadoptProgress *progress, void *user_data) {
    size_t *calls = (size_t *)user_data;
    /* Counts the sweeps; calls while untangling (iteration 0) come first. */
    if (progress->iteration >= 1) *calls += 1;
    return progress->iteration < 2;
}

int main(void) {
    double coords[27], before[27];
    QuadoptOptions options;
    QuadoptReport report;
    QuadoptQuality quality;
    QuadoptOptimizer *handle = NULL;
    QuadoptStatus status;
    uint32_t major = 99, minor = 99, patch_number = 99;
    char version[64];
    size_t calls = 0;
    int v;
    uint32_t bad_quads[16];

    /* Layouts. */
    printf("size QuadoptOptions %zu\n", sizeof(QuadoptOptions));
    printf("size QuadoptReport %zu\n", sizeof(QuadoptReport));
    printf("size QuadoptQuality %zu\n", sizeof(QuadoptQuality));
    printf("size QuadoptProgress %zu\n", sizeof(QuadoptProgress));
    printf("size QuadoptStatus %zu\n", sizeof(QuadoptStatus));
    LAYOUT(QuadoptOptions, lambda);
    LAYOUT(QuadoptOptions, max_boundary_deviation);
    LAYOUT(QuadoptOptions, tau_absolute);
    LAYOUT(QuadoptOptions, keep_best);
    LAYOUT(QuadoptOptions, stop_rule);
    LAYOUT(QuadoptOptions, progress);
    LAYOUT(QuadoptOptions, progress_user_data);
    LAYOUT(QuadoptReport, input);
    LAYOUT(QuadoptReport, output);
    LAYOUT(QuadoptReport, iterations);
    LAYOUT(QuadoptReport, tangled_quads);
    LAYOUT(QuadoptReport, initial_energy);
    LAYOUT(QuadoptReport, hausdorff_relative);
    LAYOUT(QuadoptReport, loops_fixed);
    LAYOUT(QuadoptOptions, max_min);
    LAYOUT(QuadoptReport, sweeps);
    LAYOUT(QuadoptProgress, energy_change);

    /* Version. */
    quadopt_version_numbers(&major, &minor, &patch_number);
    quadopt_version_numbers(NULL, NULL, NULL);
    CHECK(major == QUADOPT_VERSION_MAJOR && minor == QUADOPT_VERSION_MINOR &&
          patch_number == QUADOPT_VERSION_PATCH);
    snprintf(version, sizeof version, "%u.%u.%u", (unsigned)major, (unsigned)minor,
             (unsigned)patch_number);
    CHECK(strcmp(version, quadopt_version()) == 0);

    /* Status strings accept any integer. */
    CHECK(strcmp(quadopt_status_string(QUADOPT_STATUS_OK), "ok") == 0);
    CHECK(strcmp(quadopt_status_string(-5), "unknown status") == 0);
    CHECK(strcmp(quadopt_status_string(QUADOPT_STATUS_OUT_OF_MEMORY), "out of memory") == 0);

    /* Defaults. */
    CHECK(quadopt_options_init(&options, sizeof options) == QUADOPT_STATUS_OK);
    CHECK(quadopt_options_init(NULL, sizeof options) == QUADOPT_STATUS_NULL_POINTER);
    CHECK(options.struct_size == sizeof(QuadoptOptions));
    CHECK(options.method == QUADOPT_METHOD_EMBEDDED_POLYGON);
    CHECK(options.boundary == QUADOPT_BOUNDARY_AUTO);
    CHECK(options.max_iterations == 1000 && options.lambda == 1.0 && options.guard == 1);
    CHECK(options.progress == NULL && options.max_boundary_deviation < 0);
    CHECK(quadopt_options_init(&options, 8) == QUADOPT_STATUS_INVALID_ARGUMENT);
    CHECK(options.struct_size == sizeof(QuadoptOptions)); /* nothing written */

    /* Optimize with a fixed boundary: the centre returns to (1, 1), z is untouched. */
    patch(coords);
    options.boundary = QUADOPT_BOUNDARY_FIXED;
    options.tau = 1e-12;
    report = quadopt_report_init();
    CHECK(report.struct_size == sizeof(QuadoptReport) && report.iterations == 0);
    status = quadopt_optimize(coords, 3, 9, QUADS, 4, NULL, &options, &report);
    CHECK(status == QUADOPT_STATUS_OK);
    CHECK(fabs(coords[12] - 1.0) < 1e-3 && fabs(coords[13] - 1.0) < 1e-3);
    for (v = 0; v < 9; v++) {
        CHECK(coords[3 * v + 2] == 100.0);
    }
    CHECK(report.struct_size == sizeof(QuadoptReport));
    CHECK(report.input.inverted == 1 && report.output.inverted == 0 && report.output.min > 0.999);
    CHECK(report.movable == 1 && report.loops_fixed == 1 && report.converged == 1);

    /* Errors write nothing and say why. */
    patch(coords);
    memcpy(before, coords, sizeof coords);
    memcpy(bad_quads, QUADS, sizeof QUADS);
    bad_quads[6] = 9;
    report = quadopt_report_init();
    status = quadopt_optimize(coords, 3, 9, bad_quads, 4, NULL, &options, &report);
    CHECK(status == QUADOPT_STATUS_INDEX_OUT_OF_RANGE);
    CHECK(strstr(quadopt_last_error(), "quad 1 corner 2 refers to vertex 9") != NULL);
    CHECK(memcmp(before, coords, sizeof coords) == 0 && report.iterations == 0);
    CHECK(quadopt_optimize(NULL, 3, 9, QUADS, 4, NULL, NULL, NULL) == QUADOPT_STATUS_NULL_POINTER);
    {
        /* A closed mesh: a 6 x 6 grid whose quads wrap around in x and y (every vertex
         * interior, no boundary edge) cannot lie flat in a plane without folds. */
        double grid[2 * 36];
        uint32_t wrapped[4 * 36];
        uint32_t i, j;
        for (j = 0; j < 6; j++) {
            for (i = 0; i < 6; i++) {
                uint32_t *q = wrapped + 4 * (6 * j + i);
                grid[2 * (6 * j + i)] = i;
                grid[2 * (6 * j + i) + 1] = j;
                q[0] = 6 * j + i;
                q[1] = 6 * j + (i + 1) % 6;
                q[2] = 6 * ((j + 1) % 6) + (i + 1) % 6;
                q[3] = 6 * ((j + 1) % 6) + i;
            }
        }
        CHECK(quadopt_optimize(grid, 2, 36, wrapped, 36, NULL, NULL, NULL) ==
              QUADOPT_STATUS_CLOSED_MESH);
        CHECK(strcmp(quadopt_last_error(), "quadopt_optimize: the mesh is closed (it has no boundary "
                                           "edge): a closed surface cannot lie flat in a plane without "
                                           "folds") == 0);
        CHECK(quadopt_quality(grid, 2, 36, wrapped, 36, &quality, NULL, 0) ==
              QUADOPT_STATUS_CLOSED_MESH);
        CHECK(strcmp(quadopt_status_string(QUADOPT_STATUS_CLOSED_MESH), "closed mesh") == 0);
    }
    CHECK(quadopt_optimize(coords, 4, 9, QUADS, 4, NULL, NULL, NULL) ==
          QUADOPT_STATUS_INVALID_ARGUMENT);
    options.method = 42;
    CHECK(quadopt_optimize(coords, 3, 9, QUADS, 4, NULL, &options, NULL) ==
          QUADOPT_STATUS_INVALID_OPTION);
    CHECK(strstr(quadopt_last_error(), "invalid option method") != NULL);
    options.method = QUADOPT_METHOD_LAPLACIAN;

    /* Cancel from the progress callback. */
    options.progress = cancel_at_second;
    options.progress_user_data = &calls;
    options.stop_rule = QUADOPT_STOP_RULE_ENERGY;
    options.tau = 0.0; /* the energy rule never stops: the callback decides */
    CHECK(quadopt_optimize(coords, 3, 9, QUADS, 4, NULL, &options, &report) ==
          QUADOPT_STATUS_CANCELLED);
    CHECK(calls == 2 && memcmp(before, coords, sizeof coords) == 0 && report.iterations == 0);
    options.progress = NULL;
    options.tau = 1e-12;

    /* Quality of the patch as given: one inverted quad. */
    status = quadopt_quality(coords, 3, 9, QUADS, 4, &quality, NULL, 0);
    CHECK(status == QUADOPT_STATUS_OK && quality.inverted == 1 && quality.min < 0);
    CHECK(quadopt_quality(coords, 3, 9, QUADS, 4, NULL, NULL, 0) == QUADOPT_STATUS_NULL_POINTER);

    /* A handle, reused. */
    CHECK(quadopt_optimizer_create(coords, 3, 9, QUADS, 4, NULL, &handle) == QUADOPT_STATUS_OK);
    CHECK(handle != NULL);
    options.method = QUADOPT_METHOD_EMBEDDED_POLYGON;
    CHECK(quadopt_optimizer_optimize(handle, coords, 3, 9, &options, &report) == QUADOPT_STATUS_OK);
    CHECK(fabs(coords[12] - 1.0) < 1e-3 && fabs(coords[13] - 1.0) < 1e-3);
    CHECK(quadopt_optimizer_optimize(handle, coords, 3, 8, &options, &report) ==
          QUADOPT_STATUS_MISMATCH);
    quadopt_optimizer_free(handle);
    quadopt_optimizer_free(NULL);

    /* A curved patch: the same quads on the cylinder y^2 + z^2 = 16 (z = sqrt(16 - y^2)), the
       centre pushed off; optimized on its surface, every vertex stays on it (within the
       faceting) and the corners do not move. */
    patch(coords);
    for (v = 0; v < 9; v++) {
        coords[3 * v + 2] = sqrt(16.0 - coords[3 * v + 1] * coords[3 * v + 1]);
    }
    memcpy(before, coords, sizeof coords);
    CHECK(quadopt_options_init(&options, sizeof options) == QUADOPT_STATUS_OK);
    report = quadopt_report_init();
    CHECK(quadopt_optimize_surface(coords, 9, QUADS, 4, NULL, NULL, 0, &options, &report) ==
          QUADOPT_STATUS_OK);
    CHECK(report.surface == 1 && report.output.min > report.input.min);
    CHECK(report.max_distance < 1e-9 && report.corners == 4);
    for (v = 0; v < 9; v++) {
        double r = sqrt(coords[3 * v + 1] * coords[3 * v + 1] + coords[3 * v + 2] * coords[3 * v + 2]);
        CHECK(r <= 4.0 + 1e-12 && r > 3.8);
    }
    CHECK(memcmp(coords, before, 3 * sizeof(double)) == 0);
    {
        const uint32_t not_an_edge[2] = {0, 4};
        memcpy(coords, before, sizeof coords);
        CHECK(quadopt_optimize_surface(coords, 9, QUADS, 4, NULL, not_an_edge, 1, NULL, NULL) ==
              QUADOPT_STATUS_INVALID_ARGUMENT);
        CHECK(strstr(quadopt_last_error(), "feature edge 0, vertices (0, 4)") != NULL);
        CHECK(memcmp(coords, before, sizeof coords) == 0);
    }

    /* A closed curved mesh (a cube, one corner pushed out) given to a reusable handle: not
       planar (a handle is planar-only), pointing at quadopt_optimize_surface(); not "closed". */
    {
        const double cube[24] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1.3, 1.3, 1.3, 0, 1, 1};
        const uint32_t sides[24] = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7};
        QuadoptOptimizer *h = NULL;
        QuadoptPlanarity planarity;
        CHECK(quadopt_optimizer_create(cube, 3, 8, sides, 6, NULL, &h) == QUADOPT_STATUS_NOT_PLANAR);
        CHECK(h == NULL && strstr(quadopt_last_error(), "quadopt_optimize_surface()") != NULL);
        CHECK(quadopt_is_planar(cube, 8, sides, 6, &planarity) == QUADOPT_STATUS_OK);
        CHECK(planarity.planar == 0 && planarity.distance > planarity.tolerance);
        /* The patch in the tilted plane z = 0.5 x + 0.25 y is planar. */
        patch(coords);
        for (v = 0; v < 9; v++) {
            coords[3 * v + 2] = 0.5 * coords[3 * v] + 0.25 * coords[3 * v + 1];
        }
        CHECK(quadopt_is_planar(coords, 9, QUADS, 4, &planarity) == QUADOPT_STATUS_OK);
        CHECK(planarity.planar == 1);
    }

    if (failures == 0) {
        printf("ok\n");
    } else {
        printf("%d failures\n", failures);
    }
    return failures;
}
