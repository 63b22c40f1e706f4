/* The C examples of the user guide (docs/guide/c.md and the README's C quick start): each part
 * between "doc:begin NAME" and "doc:end" is shown in the docs as it is here (tests/docs.rs checks
 * that), and cpp_tests/ builds and runs this program (ctest: doc_example_c). */
#include <quadopt.h>

#include <math.h>
#include <stdio.h>

static int quick_start(void) {
    /* doc:begin quickstart */
    double xy[] = {0,0, 1,0, 2,0, 0,1, 1.6,1.5, 2,1, 0,2, 1,2, 2,2};
    uint32_t quads[] = {0,1,4,3, 1,2,5,4, 3,4,7,6, 4,5,8,7};
    QuadoptOptions options;                  /* or pass NULL for the defaults */
    quadopt_options_init(&options, sizeof options);
    options.boundary = QUADOPT_BOUNDARY_FIXED;
    QuadoptReport report = {0};              /* zeroed, with its size: safe across versions */
    report.struct_size = sizeof report;
    QuadoptStatus s = quadopt_optimize(xy, 2, 9, quads, 4, /*fixed*/ NULL, &options, &report);
    if (s != QUADOPT_STATUS_OK)
        fprintf(stderr, "%s: %s\n", quadopt_status_string(s), quadopt_last_error());
    else
        printf("min scaled Jacobian %.3f -> %.3f\n", report.input.min, report.output.min);
    /* doc:end */
    return s == QUADOPT_STATUS_OK && report.output.min > report.input.min && fabs(xy[8] - 1.0) < 0.05 ? 0 : 1;
}

static int triangles(void) {
    double xy[] = {0,0, 1,0, 2,0, 0,1, 1.6,1.5, 2,1, 0,2, 1,2, 2,2};
    QuadoptOptions options;
    quadopt_options_init(&options, sizeof options);
    QuadoptReport report = {0};
    report.struct_size = sizeof report;
    /* doc:begin triangles */
    uint32_t faces[] = {0,1,4,3,  1,2,5,4,  3,4,7,6,  4,5,8,QUADOPT_NO_VERTEX,  4,8,7,QUADOPT_NO_VERTEX};
    QuadoptStatus s = quadopt_optimize(xy, 2, 9, faces, 5, NULL, &options, &report);
    /* report.output_triangles.count == 2, report.output_triangles.min ... */
    /* doc:end */
    printf("triangles: %u, min %.3f -> %.3f\n", (unsigned)report.output_triangles.count, report.input.min,
           report.output.min);
    return s == QUADOPT_STATUS_OK && report.output_triangles.count == 2 && report.output.min >= report.input.min ? 0 : 1;
}

static int surface(void) {
    /* A 4x4 grid of quads on a cylinder of radius 2, one interior vertex pushed along it. */
    double xyz[25 * 3];
    uint32_t faces[16 * 4];
    size_t vertex_count = 25, face_count = 16;
    for (int j = 0; j < 5; ++j)
        for (int i = 0; i < 5; ++i) {
            double a = 0.25 * i + (i == 2 && j == 2 ? 0.1 : 0.0);
            xyz[3 * (5 * j + i)] = 2.0 * sin(a);
            xyz[3 * (5 * j + i) + 1] = 0.5 * j;
            xyz[3 * (5 * j + i) + 2] = 2.0 * cos(a);
        }
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
            uint32_t *f = faces + 4 * (4 * j + i), v = (uint32_t)(5 * j + i);
            f[0] = v; f[1] = v + 5; f[2] = v + 6; f[3] = v + 1;
        }
    QuadoptOptions options;
    quadopt_options_init(&options, sizeof options);
    QuadoptReport report = {0};
    report.struct_size = sizeof report;
    /* doc:begin surface */
    /* xyz: 3 doubles per vertex on a curved surface; creases: pairs of vertex indices. */
    uint32_t creases[] = {0, 1,  1, 2};
    QuadoptStatus s = quadopt_optimize_surface(xyz, vertex_count, faces, face_count, NULL,
                                               creases, 2, &options, &report);
    /* report.surface == 1; report.max_distance_relative < 1e-9; report.output_verdict.min ... */
    /* doc:end */
    printf("surface: %d, min %.3f -> %.3f, distance %.1e\n", (int)report.surface, report.input.min,
           report.output.min, report.max_distance_relative);
    if (s != QUADOPT_STATUS_OK) fprintf(stderr, "%s\n", quadopt_last_error());
    return s == QUADOPT_STATUS_OK && report.surface == 1 && report.max_distance_relative < 1e-9 &&
                   report.output.min >= report.input.min
               ? 0
               : 1;
}

int main(void) {
    int failed = quick_start() + triangles() + surface();
    printf("doc_example_c: %d passed, %d failed\n", 3 - failed, failed);
    return failed ? 1 : 0;
}
