// quadopt.h and quadopt.hpp compile as strict C++17 (-Wall -Wextra -Werror -pedantic), and
// the C declarations link from C++ (extern "C" through cbindgen's cpp_compat).
#include <quadopt.h>
#include <quadopt.hpp>

#include <cstddef>
#include <cstdio>
#include <cstring>
#include <type_traits>

static_assert(std::is_standard_layout<QuadoptOptions>::value, "QuadoptOptions is a C struct");
static_assert(std::is_standard_layout<QuadoptReport>::value, "QuadoptReport is a C struct");
static_assert(std::is_trivially_copyable<QuadoptQuality>::value, "QuadoptQuality is a C struct");
static_assert(offsetof(QuadoptOptions, struct_size) == 0, "struct_size comes first");
static_assert(offsetof(QuadoptReport, struct_size) == 0, "struct_size comes first");
static_assert(sizeof(QuadoptOptions) % alignof(QuadoptOptions) == 0, "no trailing surprises");

int main() {
  int passed = 0, failed = 0;
  auto check = [&](bool ok, const char *what) {
    if (ok) {
      ++passed;
    } else {
      ++failed;
      std::fprintf(stderr, "CHECK failed: %s\n", what);
    }
  };
  const double xy[8] = {0, 0, 1, 0, 1, 1, 0, 1};
  const std::uint32_t quad[4] = {0, 1, 2, 3};
  QuadoptQuality q{};
  check(quadopt_quality(xy, 2, 4, quad, 1, &q, nullptr, 0) == QUADOPT_STATUS_OK, "quality of a square");
  check(q.min == 1.0 && q.max == 1.0 && q.inverted == 0, "a square's scaled Jacobian is 1");
  // Clockwise: the same square seen from below, still a perfect quad.
  const std::uint32_t cw[4] = {0, 3, 2, 1};
  check(quadopt_quality(xy, 2, 4, cw, 1, &q, nullptr, 0) == QUADOPT_STATUS_OK && q.min == 1.0 && q.inverted == 0,
        "a clockwise square's scaled Jacobian is 1");
  check(quadopt::quality(xy, 2, 4, quad, 1).avg == 1.0, "the C++ wrapper agrees");
  check(std::strcmp(quadopt::version(), quadopt_version()) == 0, "version");
  std::printf("header_cxx_test: %d passed, %d failed\n", passed, failed);
  return failed == 0 ? 0 : 1;
}
