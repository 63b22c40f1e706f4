// The C++ example of the user guide (docs/guide/cpp.md and the README's C++ quick start): the part
// between "doc:begin" and "doc:end" is shown in the docs as it is here (tests/docs.rs checks that);
// cpp_tests/ builds and runs this program (ctest: doc_example_cpp).
#include <quadopt.hpp>

#include <cmath>
#include <cstdint>
#include <iostream>
#include <vector>

int main() {
  // doc:begin quickstart
  std::vector<double> xy = {0, 0, 1, 0, 2, 0, 0, 1, 1.6, 1.5, 2, 1, 0, 2, 1, 2, 2, 2};
  std::vector<std::uint32_t> quads = {0, 1, 4, 3, 1, 2, 5, 4, 3, 4, 7, 6, 4, 5, 8, 7};
  try {
    quadopt::Report r = quadopt::optimize(xy, 2, quads, quadopt::Options().boundary(quadopt::Boundary::Fixed));
    std::cout << "min scaled Jacobian " << r.input.min << " -> " << r.output.min << "\n";
  } catch (const quadopt::Error &e) {  // e.status(), e.message()
    std::cerr << e.what() << "\n";
    return 1;
  }
  // doc:end
  const bool ok = std::fabs(xy[8] - 1.0) < 0.05 && std::fabs(xy[9] - 1.0) < 0.05;
  std::cout << "doc_example_cpp: " << (ok ? 1 : 0) << " passed, " << (ok ? 0 : 1) << " failed\n";
  return ok ? 0 : 1;
}
