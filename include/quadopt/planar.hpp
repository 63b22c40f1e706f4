// quadopt/planar.hpp: the plane of a 3D mesh and its 2D frame, for the OpenMesh and CGAL
// adapters. Whether a mesh is planar is the library's one rule, the command-line tool's and
// the C ABI's too, asked of the library (quadopt_is_planar()); the frame is computed here as
// the command-line tool computes it (src/io/planar.rs):
//
// - If one coordinate is the same at every vertex used by a face (the plane z = c, the usual
//   case, or x = c, y = c), the 2D coordinates are the other two, unchanged, and the constant
//   one is kept: nothing is rounded.
// - Otherwise the mesh is planar when its used vertices lie on their least-squares plane to
//   within rounding (1e-12 of their bounding-box diagonal, plus 16 machine epsilons of their
//   largest coordinate: see quadopt_is_planar()); the plane is fitted by least squares
//   (centroid and the covariance matrix's eigenvector of the smallest eigenvalue, by Jacobi
//   rotations) and the 2D coordinates are taken in an orthonormal frame of that plane. A moved
//   vertex is written back as its point of the plane; vertices that did not move keep their
//   coordinates bit for bit.
// - Any other mesh lies on a curved surface, however slightly (a sheet whose z wobbles by 1e-4
//   of its size; a tilted plane stored in floats or with 6 significant digits): NotPlanar (an
//   Error with status QUADOPT_STATUS_NOT_PLANAR) names the farthest vertex. The adapters'
//   optimize() catches it and optimizes the mesh on its surface in 3D instead: a surface is
//   never flattened.
//
// The fit works on coordinates scaled by a power of two (exact), so it behaves the same at any
// finite scale, and gives the command-line tool's frame bit for bit.
#ifndef QUADOPT_PLANAR_HPP
#define QUADOPT_PLANAR_HPP

#include "../quadopt.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

namespace quadopt {

/// Thrown by the mesh adapters' planar functions (to_arrays(), quality()) for a mesh that does
/// not lie in a plane (status QUADOPT_STATUS_NOT_PLANAR). Their optimize() takes such a mesh:
/// it optimizes it on its surface in 3D (quadopt::optimize_surface()).
class NotPlanar : public Error {
 public:
  /// Vertex `vertex` (the mesh library's index) is `distance` away from the best-fit plane,
  /// more than `tolerance`.
  NotPlanar(std::size_t vertex, double distance, double tolerance, const std::string &library)
      : Error(QUADOPT_STATUS_NOT_PLANAR, describe(vertex, distance, tolerance, library)),
        vertex_(vertex),
        distance_(distance),
        tolerance_(tolerance) {}
  /// The vertex farthest from the plane.
  std::size_t vertex() const noexcept { return vertex_; }
  /// Its distance from the best-fit plane.
  double distance() const noexcept { return distance_; }
  /// The largest distance accepted (QuadoptPlanarity::tolerance, see quadopt_is_planar()).
  double tolerance() const noexcept { return tolerance_; }

 private:
  static std::string describe(std::size_t vertex, double distance, double tolerance, const std::string &library) {
    std::ostringstream s;
    s.precision(3);
    s << "the mesh is not planar: " << library << " vertex " << vertex << " is " << std::scientific << distance
      << " away from the best-fit plane (tolerance " << tolerance
      << "); the planar optimizer takes planar meshes only (optimize() optimizes a curved mesh on its surface)";
    return s.str();
  }
  std::size_t vertex_;
  double distance_;
  double tolerance_;
};

namespace planar {

/// Largest allowed distance from the fitted plane relative to the bounding-box diagonal of the
/// used vertices (the library's PLANARITY_TOLERANCE): rounding only. The library decides
/// (quadopt_is_planar(), which adds 16 machine epsilons of the largest coordinate); this is
/// its first term, for reference.
constexpr double tolerance = 1e-12;

/// Relative margin within which the frame's discrete choices (the normal's sign, u's axis)
/// count components as equal (the command-line tool's FRAME_TIE).
constexpr double kFrameTie = 1e-9;

/// Whether two doubles have the same bits.
inline bool same_bits(double a, double b) noexcept { return std::memcmp(&a, &b, sizeof a) == 0; }

/// The plane of a mesh and its 2D frame.
class Frame {
 public:
  /// The plane z = 0 (2D coordinates x, y).
  Frame() = default;

  /// Fits the plane of the points `xyz` (3 doubles per vertex) whose `used` flag is nonzero
  /// (all when `used` is empty). Throws NotPlanar naming the farthest vertex (its index in
  /// `names` when given, else in `xyz`) when they are not planar by the library's rule
  /// (quadopt_is_planar()), and Error with status QUADOPT_STATUS_NON_FINITE_COORDINATE for a
  /// NaN or infinite coordinate.
  static Frame fit(const std::vector<double> &xyz, const std::vector<std::uint8_t> &used, const std::string &library,
                   const std::vector<std::size_t> *names = nullptr) {
    const std::size_t n = xyz.size() / 3;
    auto name = [&](std::size_t i) { return names ? (*names)[i] : i; };
    for (std::size_t i = 0; i < 3 * n; ++i) {
      if (!std::isfinite(xyz[i])) {
        throw Error(QUADOPT_STATUS_NON_FINITE_COORDINATE,
                    library + " vertex " + std::to_string(name(i / 3)) + " has a non-finite coordinate");
      }
    }
    std::vector<std::size_t> idx;
    for (std::size_t i = 0; i < n; ++i) {
      if (used.empty() || (i < used.size() && used[i])) idx.push_back(i);
    }
    Frame f;
    if (idx.empty()) return f;
    for (int axis : {2, 0, 1}) {
      const double value = xyz[3 * idx[0] + axis];
      bool constant = true;
      for (std::size_t i : idx) constant = constant && xyz[3 * i + axis] == value;
      if (constant) {
        f.axis_ = axis;
        f.value_ = value;
        return f;
      }
    }
    // Not in a plane x, y or z = const: the library decides whether it is planar, on the used
    // points alone (the same sums, in the same order, as on the whole mesh).
    {
      std::vector<double> points;
      points.reserve(3 * idx.size());
      for (std::size_t i : idx) points.insert(points.end(), &xyz[3 * i], &xyz[3 * i] + 3);
      QuadoptPlanarity p{};
      check(quadopt_is_planar(points.data(), idx.size(), nullptr, 0, &p));
      if (!p.planar) throw NotPlanar(name(idx[p.vertex]), p.distance, p.tolerance, library);
    }
    double lo[3], hi[3];
    for (int c = 0; c < 3; ++c) lo[c] = hi[c] = xyz[3 * idx[0] + c];
    for (std::size_t i : idx) {
      for (int c = 0; c < 3; ++c) {
        lo[c] = std::fmin(lo[c], xyz[3 * i + c]);
        hi[c] = std::fmax(hi[c], xyz[3 * i + c]);
      }
    }
    // Sums and products on coordinates scaled by 2^-e (exact), so that nothing overflows or
    // underflows at any scale; every comparison is between quantities scaled alike. (No axis
    // is constant here, so the extent is positive.)
    double half = 0;
    for (int c = 0; c < 3; ++c) half = std::fmax(half, hi[c] * 0.5 - lo[c] * 0.5);
    int e = 0;
    std::frexp(half, &e);  // half = m 2^e, m in [0.5, 1): the CLI's binary exponent + 1
    auto scaled = [e](double x) { return std::ldexp(x, -e); };
    double sum[3] = {0, 0, 0};
    for (std::size_t i : idx) {
      for (int c = 0; c < 3; ++c) sum[c] += scaled(xyz[3 * i + c]);
    }
    double origin[3];
    for (int c = 0; c < 3; ++c) origin[c] = std::ldexp(sum[c] / static_cast<double>(idx.size()), e);
    double cov[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    for (std::size_t i : idx) {
      double d[3];
      for (int c = 0; c < 3; ++c) d[c] = scaled(xyz[3 * i + c] - origin[c]);
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) cov[r][c] += d[r] * d[c];
      }
    }
    double normal[3];
    smallest_eigenvector(cov, normal);
    // The normal's sign and u's axis are discrete choices: taken with a relative margin
    // (kFrameTie) so that a rescaled copy of the mesh, whose fitted normal differs in its
    // last bits, gets the same frame; the same rule as quadopt's own (src/io/planar.rs).
    const double a[3] = {std::fabs(normal[0]), std::fabs(normal[1]), std::fabs(normal[2])};
    const auto near = [](double c, double m) { return c <= m * (1.0 + kFrameTie); };
    const double big = std::max(std::max(a[0], a[1]), a[2]);
    const double first_big = near(big, a[0]) ? normal[0] : (near(big, a[1]) ? normal[1] : normal[2]);
    if (first_big < 0) {
      for (double& c : normal) c = -c;
    }
    // u: the coordinate axis most parallel to the plane (the first within the margin of the
    // smallest component), projected into it.
    const double small = std::min(std::min(a[0], a[1]), a[2]);
    double axis[3] = {0, 0, 0};
    axis[near(a[0], small) ? 0 : (near(a[1], small) ? 1 : 2)] = 1;
    const double along = dot(axis, normal);
    double u[3];
    for (int c = 0; c < 3; ++c) u[c] = axis[c] - along * normal[c];
    const double inv = 1.0 / std::sqrt(dot(u, u));
    for (int c = 0; c < 3; ++c) u[c] *= inv;
    f.axis_ = -1;
    for (int c = 0; c < 3; ++c) {
      f.origin_[c] = origin[c];
      f.u_[c] = u[c];
      f.normal_[c] = normal[c];
    }
    // v = normal x u
    f.v_[0] = normal[1] * u[2] - u[1] * normal[2];
    f.v_[1] = normal[2] * u[0] - u[2] * normal[0];
    f.v_[2] = normal[0] * u[1] - u[0] * normal[1];
    return f;
  }

  /// Whether the plane is x, y or z = const (2D coordinates are two of the 3D ones, exactly).
  bool axis_aligned() const noexcept { return axis_ >= 0; }
  /// For an axis-aligned plane: the constant coordinate (0 = x, 1 = y, 2 = z).
  int axis() const noexcept { return axis_; }
  /// The unit normal (of a tilted plane; the constant axis of an axis-aligned one).
  void normal(double out[3]) const noexcept {
    for (int c = 0; c < 3; ++c) out[c] = axis_ >= 0 ? (c == axis_ ? 1.0 : 0.0) : normal_[c];
  }
  /// The two 3D coordinates that are the 2D ones of an axis-aligned plane, right-handed
  /// (yz, zx or xy).
  void in_plane_axes(int &i, int &j) const noexcept {
    i = axis_ == 0 ? 1 : (axis_ == 1 ? 2 : 0);
    j = axis_ == 0 ? 2 : (axis_ == 1 ? 0 : 1);
  }

  /// The in-plane coordinates of `p` (its projection onto the plane).
  void to_2d(const double p[3], double q[2]) const noexcept {
    if (axis_ >= 0) {
      int i, j;
      in_plane_axes(i, j);
      q[0] = p[i];
      q[1] = p[j];
      return;
    }
    const double d[3] = {p[0] - origin_[0], p[1] - origin_[1], p[2] - origin_[2]};
    q[0] = dot(d, u_);
    q[1] = dot(d, v_);
  }

  /// The point of the plane with in-plane coordinates `q`.
  void to_3d(const double q[2], double p[3]) const noexcept {
    if (axis_ >= 0) {
      int i, j;
      in_plane_axes(i, j);
      p[axis_] = value_;
      p[i] = q[0];
      p[j] = q[1];
      return;
    }
    for (int c = 0; c < 3; ++c) p[c] = (origin_[c] + q[0] * u_[c]) + q[1] * v_[c];
  }

  /// The 2D coordinates (2 per vertex) of points `xyz` (3 per vertex).
  std::vector<double> to_2d(const std::vector<double> &xyz) const {
    std::vector<double> xy(2 * (xyz.size() / 3));
    for (std::size_t i = 0; i < xyz.size() / 3; ++i) to_2d(&xyz[3 * i], &xy[2 * i]);
    return xy;
  }

 private:
  static double dot(const double a[3], const double b[3]) noexcept { return (a[0] * b[0] + a[1] * b[1]) + a[2] * b[2]; }

  /// The unit eigenvector of the smallest eigenvalue of a symmetric 3x3 matrix (cyclic
  /// Jacobi), exactly as the command-line tool computes it.
  static void smallest_eigenvector(double a[3][3], double out[3]) {
    double v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const int pairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
    for (int sweep = 0; sweep < 64; ++sweep) {
      const double off = (a[0][1] * a[0][1] + a[0][2] * a[0][2]) + a[1][2] * a[1][2];
      const double diag = (a[0][0] * a[0][0] + a[1][1] * a[1][1]) + a[2][2] * a[2][2];
      if (off <= 1e-32 * diag || off == 0.0) break;
      for (const auto &pq : pairs) {
        const int p = pq[0], q = pq[1];
        if (a[p][q] == 0.0) continue;
        const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
        const double sign = std::signbit(theta) ? -1.0 : 1.0;
        const double t = sign / (std::fabs(theta) + std::sqrt(theta * theta + 1.0));
        const double c = 1.0 / std::sqrt(t * t + 1.0);
        const double s = t * c;
        for (int r = 0; r < 3; ++r) {
          const double kp = a[r][p], kq = a[r][q];
          a[r][p] = c * kp - s * kq;
          a[r][q] = s * kp + c * kq;
        }
        for (int k = 0; k < 3; ++k) {
          const double pk = a[p][k], qk = a[q][k];
          a[p][k] = c * pk - s * qk;
          a[q][k] = s * pk + c * qk;
        }
        for (auto &row : v) {
          const double kp = row[p], kq = row[q];
          row[p] = c * kp - s * kq;
          row[q] = s * kp + c * kq;
        }
      }
    }
    int k = 0;
    for (int i = 1; i < 3; ++i) {
      if (a[i][i] < a[k][k]) k = i;
    }
    double n[3] = {v[0][k], v[1][k], v[2][k]};
    const double inv = 1.0 / std::sqrt(dot(n, n));
    if (std::isfinite(inv) && inv > 0) {
      for (int c = 0; c < 3; ++c) out[c] = n[c] * inv;
    } else {
      out[0] = 0;
      out[1] = 0;
      out[2] = 1;
    }
  }

  int axis_ = 2;  // -1: tilted
  double value_ = 0;
  double origin_[3] = {0, 0, 0};
  double u_[3] = {1, 0, 0};
  double v_[3] = {0, 1, 0};
  double normal_[3] = {0, 0, 1};
};

}  // namespace planar
}  // namespace quadopt

#endif  // QUADOPT_PLANAR_HPP
