// Small helpers shared by the C++ tests: checks with a pass/fail count, bitwise comparison,
// an OBJ reader that parses doubles exactly (OpenMesh's readers parse float), geometry
// helpers, running the CLI, and reading numbers out of its one-line JSON.
#ifndef QUADOPT_TEST_SUPPORT_HPP
#define QUADOPT_TEST_SUPPORT_HPP

#include <quadopt.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#if defined(__unix__) || defined(__APPLE__)
#include <sys/wait.h>
#endif

namespace qt {

inline int &passed() {
  static int n = 0;
  return n;
}
inline int &failed() {
  static int n = 0;
  return n;
}

inline void record(bool ok, const char *file, int line, const std::string &what) {
  if (ok) {
    ++passed();
  } else {
    ++failed();
    std::cerr << file << ":" << line << ": CHECK failed: " << what << std::endl;
  }
}

#define CHECK(cond) ::qt::record(static_cast<bool>(cond), __FILE__, __LINE__, #cond)
#define CHECK_MSG(cond, msg)                                                          \
  do {                                                                                \
    std::ostringstream qt_os_;                                                        \
    qt_os_ << #cond << " -- " << msg;                                                 \
    ::qt::record(static_cast<bool>(cond), __FILE__, __LINE__, qt_os_.str());          \
  } while (0)
/// `expr` must throw quadopt::Error (or a subclass) with status `st`.
#define CHECK_THROWS_STATUS(expr, st)                                                            \
  do {                                                                                           \
    bool qt_ok_ = false;                                                                         \
    std::string qt_got_ = "no exception";                                                        \
    try {                                                                                        \
      (void)(expr);                                                                              \
    } catch (const quadopt::Error &qt_e_) {                                                      \
      qt_ok_ = qt_e_.status() == (st);                                                           \
      qt_got_ = qt_e_.what();                                                                    \
    }                                                                                            \
    ::qt::record(qt_ok_, __FILE__, __LINE__, std::string(#expr " throws " #st "; got: ") + qt_got_); \
  } while (0)

/// Prints the closing "N passed, N failed" line and returns the exit code.
inline int finish(const char *name) {
  std::cout << name << ": " << passed() << " passed, " << failed() << " failed" << std::endl;
  return failed() == 0 && passed() > 0 ? 0 : 1;
}

inline bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

inline bool same_bits(const std::vector<double> &a, const std::vector<double> &b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

/// Index of the first differing coordinate, or -1.
inline long first_difference(const std::vector<double> &a, const std::vector<double> &b) {
  if (a.size() != b.size()) return 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!same_bits(a[i], b[i])) return static_cast<long>(i);
  }
  return -1;
}

/// A mesh as flat arrays: x, y, z per vertex and 4 slots per face (a triangle's fourth is
/// QUADOPT_NO_VERTEX).
struct Mesh {
  std::vector<double> xyz;
  std::vector<std::uint32_t> quads;
  std::size_t vertices() const { return xyz.size() / 3; }
  std::size_t quad_count() const { return quads.size() / 4; }
  std::size_t triangle_count() const {
    std::size_t t = 0;
    for (std::size_t f = 0; f < quad_count(); ++f) t += quads[4 * f + 3] == QUADOPT_NO_VERTEX ? 1 : 0;
    return t;
  }
  /// x, y per vertex.
  std::vector<double> xy() const {
    std::vector<double> out(2 * vertices());
    for (std::size_t i = 0; i < vertices(); ++i) {
      out[2 * i] = xyz[3 * i];
      out[2 * i + 1] = xyz[3 * i + 1];
    }
    return out;
  }
};

/// Reads the `v` and the 3- and 4-vertex `f` lines of an OBJ file with strtod (exact to the last
/// bit); a triangle gets QUADOPT_NO_VERTEX fourth.
inline Mesh read_obj(const std::string &path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  Mesh m;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string key;
    s >> key;
    if (key == "v") {
      std::string c[3] = {"0", "0", "0"};
      s >> c[0] >> c[1] >> c[2];
      for (auto &t : c) m.xyz.push_back(std::strtod(t.c_str(), nullptr));
    } else if (key == "f") {
      std::string t;
      int n = 0;
      while (s >> t) {
        m.quads.push_back(static_cast<std::uint32_t>(std::stoul(t.substr(0, t.find('/'))) - 1));
        ++n;
      }
      if (n == 3) m.quads.push_back(QUADOPT_NO_VERTEX);
      if (n != 3 && n != 4) throw std::runtime_error(path + ": not a quad or a triangle: " + line);
    }
  }
  return m;
}

/// Distance from p to the segment [a, b] (2D).
inline double point_segment_distance(double px, double py, double ax, double ay, double bx, double by) {
  const double dx = bx - ax, dy = by - ay;
  const double len2 = dx * dx + dy * dy;
  double t = len2 > 0 ? ((px - ax) * dx + (py - ay) * dy) / len2 : 0.0;
  t = t < 0 ? 0 : (t > 1 ? 1 : t);
  return std::hypot(px - (ax + t * dx), py - (ay + t * dy));
}

/// Diagonal of the bounding box of x, y pairs.
inline double bbox_diagonal(const std::vector<double> &xy) {
  double lo[2] = {HUGE_VAL, HUGE_VAL}, hi[2] = {-HUGE_VAL, -HUGE_VAL};
  for (std::size_t i = 0; i < xy.size(); ++i) {
    lo[i % 2] = std::fmin(lo[i % 2], xy[i]);
    hi[i % 2] = std::fmax(hi[i % 2], xy[i]);
  }
  return std::hypot(hi[0] - lo[0], hi[1] - lo[1]);
}

/// Runs a shell command, returning its exit status; stdout goes to `out_file`.
inline int run(const std::string &cmd, const std::string &out_file) {
  const std::string full = cmd + " > \"" + out_file + "\"";
  const int rc = std::system(full.c_str());
  if (rc == -1) return -1;
#ifdef WEXITSTATUS
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
#else
  return rc;
#endif
}

inline std::string slurp(const std::string &path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// The number after `"key":` in `json`, searching from the object `"object":{` when given.
/// serde_json prints shortest round-trip numbers, so strtod gives the exact double.
inline double json_number(const std::string &json, const std::string &key, const std::string &object = "") {
  std::size_t from = 0;
  if (!object.empty()) {
    from = json.find("\"" + object + "\":{");
    if (from == std::string::npos) throw std::runtime_error("no object " + object + " in " + json);
  }
  const std::string k = "\"" + key + "\":";
  const std::size_t at = json.find(k, from);
  if (at == std::string::npos) throw std::runtime_error("no key " + key + " in " + json);
  return std::strtod(json.c_str() + at + k.size(), nullptr);
}

/// The number after `"key":` in `json`, searching from the objects named in `path` in turn
/// (`{"output_by_kind", "triangles"}`: the triangles' object inside output_by_kind).
inline double json_number_in(const std::string &json, const std::vector<std::string> &path, const std::string &key) {
  std::size_t from = 0;
  for (const auto &object : path) {
    from = json.find("\"" + object + "\":{", from);
    if (from == std::string::npos) throw std::runtime_error("no object " + object + " in " + json);
  }
  const std::string k = "\"" + key + "\":";
  const std::size_t at = json.find(k, from);
  if (at == std::string::npos) throw std::runtime_error("no key " + key + " in " + json);
  return std::strtod(json.c_str() + at + k.size(), nullptr);
}

}  // namespace qt

#endif  // QUADOPT_TEST_SUPPORT_HPP
