// sh.h — real spherical harmonics for sky occlusion by spheres (Ren et al.
// 2006, Guerrero's thesis: ../shared/docs/digest-002): the basis at any order,
// a cap's zonal harmonics in closed form, zonal rotation, the triple product,
// and the SH exponential and logarithm (exact, "optimal linear" and hybrid).
//
// Convention: order n holds bands l < n, n^2 coefficients, flat index
// i = l (l + 1) + m. No Condon-Shortley phase (Sloan's convention, the one
// AtmoLighting's SH9 uses): y_1^{-1} = +0.488603 y, y_1^1 = +0.488603 x. The
// tables, the rotation and the triple product all use it. Double precision:
// the GLSL include (atmo_sky_occlusion.glsl) is the float, order-4 runtime.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace atmo::shadows {

using ShVector = std::vector<double>;  // order^2 coefficients

constexpr int coefficients(int order) { return order * order; }
constexpr int band_of(int index) {
  int l = 0;
  while ((l + 1) * (l + 1) <= index) ++l;
  return l;
}

// y_i(direction) for i < order^2; direction need not be unit (it is normalised). Recurrences on the
// associated Legendre polynomials (Press et al.), the azimuth from (x + iy)^m.
ShVector sh_basis(int order, const glm::dvec3& direction);

// The zonal harmonics (m = 0 coefficients, one per band) of the indicator of a cap of half-angle
// theta (radians, [0, pi]) about +z: c_0 = sqrt(pi) (1 - cos theta), c_l = sqrt(pi / (2l + 1))
// (P_{l-1}(cos theta) - P_{l+1}(cos theta)).
std::vector<double> cap_zh(int order, double theta_rad);
// The ZH of max(0, cos)/pi about +z (a white Lambertian receiver's weight; its DC is 1/sqrt(4 pi)
// times 1, so rho . V is the cosine-weighted visible fraction).
std::vector<double> clamped_cosine_zh(int order);
// Rotates zonal harmonics from +z to the axis: c_lm = sqrt(4 pi / (2l + 1)) zh_l y_lm(axis) (Sloan 2005).
ShVector rotate_zh(const std::vector<double>& zh, const glm::dvec3& axis);

// Gamma_ijk = integral of y_i y_j y_k over the sphere, for one order, by quadrature that is exact for
// the polynomials (Gauss-Legendre in z, uniform in azimuth). Sparse: the non-zero (i, j, k) triples.
class TripleProduct {
 public:
  explicit TripleProduct(int order);
  int order() const { return order_; }
  struct Entry {
    uint16_t i, j, k;
    double value;
  };
  const std::vector<Entry>& entries() const { return entries_; }
  double gamma(int i, int j, int k) const;  // dense lookup (slow; for tests)
  // (f * g)_i = sum_jk Gamma_ijk f_j g_k: the projection of the product of the two truncated functions.
  ShVector product(const ShVector& f, const ShVector& g) const;
  // M_f with (M_f)_ij = sum_k f_k Gamma_ijk, row-major n^2 x n^2 (f * g = M_f g).
  std::vector<double> product_matrix(const ShVector& f) const;

 private:
  int order_;
  std::vector<Entry> entries_;
  std::vector<double> dense_;
};

// The constant 1 in SH: (sqrt(4 pi), 0, ...).
ShVector sh_one(int order);
double sh_dot(const ShVector& a, const ShVector& b);

// Symmetric eigen-decomposition (cyclic Jacobi): a = V diag(values) V^T, V's columns the vectors
// (row-major n x n in and out).
void symmetric_eigen(std::vector<double> a, int n, std::vector<double>& values, std::vector<double>& vectors);

// exp*(f) = 1 + f + f*f/2 + ... = expm(M_f) 1, exactly for the truncated products (eigen-decomposition).
ShVector sh_exp_exact(const TripleProduct& gamma, const ShVector& f);
// log*(g) = logm(M_g) 1 with M_g's eigenvalues clipped below at epsilon (Ren et al.; the thesis's
// (3.34)). A blocker's log depends on epsilon only beyond an angular radius of about 50 degrees.
constexpr double kLogEpsilon = 0.02;
ShVector sh_log_exact(const TripleProduct& gamma, const ShVector& g, double epsilon = kLogEpsilon);

// The "optimal linear" exponential (Ren et al.'s (a, b) by the magnitude of f's non-DC part):
// exp*(f) ~ exp(f_0 / sqrt(4 pi)) (a(|f^|) 1 + b(|f^|) f^), (a, b) fitted on single-sphere logs.
class OptimalLinearTable {
 public:
  // Built from the logs of single spheres of angular radius up to 90 degrees at this order.
  OptimalLinearTable(const TripleProduct& gamma, int samples = 256);
  double max_magnitude() const { return max_magnitude_; }
  // (a, b) at magnitude m (linear between samples; clamped beyond the largest single sphere's).
  glm::dvec2 at(double magnitude) const;
  int samples() const { return static_cast<int>(ab_.size()); }
  const std::vector<glm::dvec2>& table() const { return ab_; }  // at magnitude k * max / (samples - 1)

 private:
  double max_magnitude_ = 0.0;
  std::vector<glm::dvec2> ab_;
};

ShVector sh_exp_optimal_linear(const OptimalLinearTable& table, const ShVector& f);
// Hybrid: the optimal-linear exponential of f^ / 2^p with |f^| / 2^p <= hybrid_magnitude, then p SH
// squarings (exp x = (exp(x / 2^p))^(2^p)); p <= kHybridMaxSquarings.
constexpr double kHybridMagnitude = 1.0;
constexpr int kHybridMaxSquarings = 3;
ShVector sh_exp_hybrid(const TripleProduct& gamma, const OptimalLinearTable& table, const ShVector& f);

// A blocker: 1 - cap (0 where a sphere of angular radius theta hides the sky, 1 elsewhere), as ZH.
std::vector<double> blocker_zh(int order, double theta_rad);
// The log of a blocker, as ZH (exact log with the clipped eigenvalues).
std::vector<double> log_blocker_zh(const TripleProduct& gamma, double theta_rad, double epsilon = kLogEpsilon);

}  // namespace atmo::shadows
