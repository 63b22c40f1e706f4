/* The downstream consumer's C program (also built with pkg-config by scripts/test-all). */
#include <quadopt.h>

#include <math.h>
#include <stdio.h>

int main(void) {
  double xy[18] = {0, 0, 1, 0, 2, 0, 0, 1, 1.6, 1.5, 2, 1, 0, 2, 1, 2, 2, 2};
  const uint32_t quads[16] = {0, 1, 4, 3, 1, 2, 5, 4, 3, 4, 7, 6, 4, 5, 8, 7};
  QuadoptOptions options;
  QuadoptReport report = quadopt_report_init();
  QuadoptStatus status;
  int ok;
  if (quadopt_options_init(&options, sizeof options) != QUADOPT_STATUS_OK) {
    printf("consumer_c: quadopt_options_init: %s\n", quadopt_last_error());
    return 1;
  }
  options.boundary = QUADOPT_BOUNDARY_FIXED;
  options.tau = 1e-12;
  status = quadopt_optimize(xy, 2, 9, quads, 4, NULL, &options, &report);
  if (status != QUADOPT_STATUS_OK) {
    printf("consumer_c: %s: %s\n", quadopt_status_string(status), quadopt_last_error());
    return 1;
  }
  ok = fabs(xy[8] - 1.0) < 1e-3 && fabs(xy[9] - 1.0) < 1e-3 && report.output.min > report.input.min;
  printf("quadopt %s: centre (%.6f, %.6f) after %zu iterations\n", quadopt_version(), xy[8], xy[9],
         report.iterations);
  printf("consumer_c: %d passed, %d failed\n", ok ? 1 : 0, ok ? 0 : 1);
  return ok ? 0 : 1;
}
