// The downstream consumer's program: optimize a 2x2 patch whose centre was dragged off-centre
// and check that the centre comes back to the middle.
#include <quadopt.hpp>

#include <cmath>
#include <cstdio>
#include <vector>

int main() {
  std::vector<double> xy;
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 3; ++i) {
      xy.push_back(i);
      xy.push_back(j);
    }
  }
  xy[8] = 1.6;  // vertex 4, the centre
  xy[9] = 1.5;
  const std::vector<std::uint32_t> quads = {0, 1, 4, 3, 1, 2, 5, 4, 3, 4, 7, 6, 4, 5, 8, 7};
  try {
    const quadopt::Report r =
        quadopt::optimize(xy, 2, quads, quadopt::Options().boundary(quadopt::Boundary::Fixed).tau(1e-12));
    const bool ok = std::fabs(xy[8] - 1.0) < 1e-3 && std::fabs(xy[9] - 1.0) < 1e-3 && r.output.min > r.input.min;
    std::printf("quadopt %s: centre (%.6f, %.6f), min scaled Jacobian %.4f -> %.4f\n", quadopt::version(), xy[8],
                xy[9], r.input.min, r.output.min);
    std::printf("consumer: %d passed, %d failed\n", ok ? 1 : 0, ok ? 0 : 1);
    return ok ? 0 : 1;
  } catch (const quadopt::Error &e) {
    std::printf("consumer: quadopt error: %s\n", e.what());
    return 1;
  }
}
