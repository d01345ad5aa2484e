#include "core/shadows/sh.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace atmo::shadows {

namespace {

double factorial_ratio(int l, int m) {  // (l - m)! / (l + m)!
  double r = 1.0;
  for (int k = l - m + 1; k <= l + m; ++k) r /= k;
  return r;
}

// Legendre P_l(x) for l = 0..n-1.
std::vector<double> legendre(int n, double x) {
  std::vector<double> p(std::max(n, 2));
  p[0] = 1.0;
  p[1] = x;
  for (int l = 2; l < n; ++l) p[l] = ((2 * l - 1) * x * p[l - 1] - (l - 1) * p[l - 2]) / l;
  p.resize(n);
  return p;
}

// Gauss-Legendre nodes and weights on [-1, 1] (Newton on P_n).
void gauss_legendre(int n, std::vector<double>& x, std::vector<double>& w) {
  x.assign(n, 0.0);
  w.assign(n, 0.0);
  for (int i = 0; i < n; ++i) {
    double z = std::cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 1.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = z;
      for (int l = 2; l <= n; ++l) {
        const double p2 = ((2 * l - 1) * z * p1 - (l - 1) * p0) / l;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (z * p1 - p0) / (z * z - 1.0);
      const double dz = p1 / dp;
      z -= dz;
      if (std::abs(dz) < 1e-16) break;
    }
    x[i] = z;
    w[i] = 2.0 / ((1.0 - z * z) * dp * dp);
  }
}

}  // namespace

ShVector sh_basis(int order, const glm::dvec3& direction) {
  const double len = glm::length(direction);
  const glm::dvec3 d = len > 0.0 ? direction / len : glm::dvec3(0.0, 0.0, 1.0);
  ShVector y(coefficients(order), 0.0);
  // (x + iy)^m = sin^m(theta) e^{i m phi}; P_l^m(z) = (1 - z^2)^{m/2} Q_l^m(z).
  double re = 1.0, im = 0.0;
  for (int m = 0; m < order; ++m) {
    // Q_m^m = (2m - 1)!!, Q_{m+1}^m = z (2m + 1) Q_m^m, (l - m) Q_l^m = z (2l - 1) Q_{l-1}^m - (l + m - 1) Q_{l-2}^m.
    double q_prev = 0.0, q = 1.0;
    for (int k = 1; k <= m; ++k) q *= 2 * k - 1;
    for (int l = m; l < order; ++l) {
      if (l == m + 1) {
        q_prev = q;
        q = d.z * (2 * m + 1) * q;
      } else if (l > m + 1) {
        const double next = (d.z * (2 * l - 1) * q - (l + m - 1) * q_prev) / (l - m);
        q_prev = q;
        q = next;
      }
      const double n = std::sqrt((2 * l + 1) / (4.0 * M_PI) * factorial_ratio(l, m));
      if (m == 0) {
        y[l * (l + 1)] = n * q;
      } else {
        y[l * (l + 1) + m] = M_SQRT2 * n * q * re;
        y[l * (l + 1) - m] = M_SQRT2 * n * q * im;
      }
    }
    const double r2 = re * d.x - im * d.y, i2 = re * d.y + im * d.x;
    re = r2;
    im = i2;
  }
  return y;
}

std::vector<double> cap_zh(int order, double theta_rad) {
  const double c = std::cos(std::clamp(theta_rad, 0.0, M_PI));
  const std::vector<double> p = legendre(order + 1, c);
  std::vector<double> zh(order);
  zh[0] = std::sqrt(M_PI) * (1.0 - c);
  for (int l = 1; l < order; ++l) zh[l] = std::sqrt(M_PI / (2 * l + 1)) * (p[l - 1] - p[l + 1]);
  return zh;
}

std::vector<double> clamped_cosine_zh(int order) {
  // c_l = 2 pi N_l integral_0^1 (t / pi) P_l(t) dt, by Gauss-Legendre on [0, 1] (exact: a polynomial).
  std::vector<double> x, w;
  gauss_legendre(order + 2, x, w);
  std::vector<double> zh(order, 0.0);
  for (size_t q = 0; q < x.size(); ++q) {
    const double t = 0.5 * (x[q] + 1.0), wt = 0.5 * w[q];
    const std::vector<double> p = legendre(order, t);
    for (int l = 0; l < order; ++l) zh[l] += 2.0 * M_PI * std::sqrt((2 * l + 1) / (4.0 * M_PI)) * wt * t / M_PI * p[l];
  }
  return zh;
}

ShVector rotate_zh(const std::vector<double>& zh, const glm::dvec3& axis) {
  const int order = static_cast<int>(zh.size());
  ShVector c = sh_basis(order, axis);
  for (int i = 0; i < coefficients(order); ++i) {
    const int l = band_of(i);
    c[i] *= std::sqrt(4.0 * M_PI / (2 * l + 1)) * zh[l];
  }
  return c;
}

TripleProduct::TripleProduct(int order) : order_(order) {
  if (order < 1 || order > 10) throw std::invalid_argument("TripleProduct: order must be in [1, 10]");
  const int n = coefficients(order);
  std::vector<double> zs, ws;
  gauss_legendre(2 * order + 2, zs, ws);
  const int azimuths = 3 * order + 3;
  dense_.assign(static_cast<size_t>(n) * n * n, 0.0);
  for (size_t a = 0; a < zs.size(); ++a) {
    const double s = std::sqrt(std::max(0.0, 1.0 - zs[a] * zs[a]));
    for (int b = 0; b < azimuths; ++b) {
      const double phi = 2.0 * M_PI * (b + 0.5) / azimuths;
      const ShVector y = sh_basis(order, {s * std::cos(phi), s * std::sin(phi), zs[a]});
      const double w = ws[a] * 2.0 * M_PI / azimuths;
      for (int i = 0; i < n; ++i)
        for (int j = i; j < n; ++j)
          for (int k = j; k < n; ++k) dense_[(static_cast<size_t>(i) * n + j) * n + k] += w * y[i] * y[j] * y[k];
    }
  }
  // Symmetric: fill every permutation from i <= j <= k, and zero the quadrature's round-off.
  for (int i = 0; i < n; ++i)
    for (int j = i; j < n; ++j)
      for (int k = j; k < n; ++k) {
        double v = dense_[(static_cast<size_t>(i) * n + j) * n + k];
        if (std::abs(v) < 1e-12) v = 0.0;
        const int p[6][3] = {{i, j, k}, {i, k, j}, {j, i, k}, {j, k, i}, {k, i, j}, {k, j, i}};
        for (const auto& q : p) dense_[(static_cast<size_t>(q[0]) * n + q[1]) * n + q[2]] = v;
      }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const double v = dense_[(static_cast<size_t>(i) * n + j) * n + k];
        if (v != 0.0)
          entries_.push_back({static_cast<uint16_t>(i), static_cast<uint16_t>(j), static_cast<uint16_t>(k), v});
      }
}

double TripleProduct::gamma(int i, int j, int k) const {
  const int n = coefficients(order_);
  return dense_[(static_cast<size_t>(i) * n + j) * n + k];
}

ShVector TripleProduct::product(const ShVector& f, const ShVector& g) const {
  ShVector r(coefficients(order_), 0.0);
  for (const Entry& e : entries_) r[e.i] += e.value * f[e.j] * g[e.k];
  return r;
}

std::vector<double> TripleProduct::product_matrix(const ShVector& f) const {
  const int n = coefficients(order_);
  std::vector<double> m(static_cast<size_t>(n) * n, 0.0);
  for (const Entry& e : entries_) m[static_cast<size_t>(e.i) * n + e.j] += e.value * f[e.k];
  return m;
}

ShVector sh_one(int order) {
  ShVector one(coefficients(order), 0.0);
  one[0] = std::sqrt(4.0 * M_PI);
  return one;
}

double sh_dot(const ShVector& a, const ShVector& b) {
  double s = 0.0;
  for (size_t i = 0; i < std::min(a.size(), b.size()); ++i) s += a[i] * b[i];
  return s;
}

void symmetric_eigen(std::vector<double> a, int n, std::vector<double>& values, std::vector<double>& vectors) {
  vectors.assign(static_cast<size_t>(n) * n, 0.0);
  for (int i = 0; i < n; ++i) vectors[static_cast<size_t>(i) * n + i] = 1.0;
  auto at = [&](std::vector<double>& m, int r, int c) -> double& { return m[static_cast<size_t>(r) * n + c]; };
  for (int sweep = 0; sweep < 100; ++sweep) {
    double off = 0.0, diag = 0.0;
    for (int p = 0; p < n; ++p) {
      diag += at(a, p, p) * at(a, p, p);
      for (int q = p + 1; q < n; ++q) off += at(a, p, q) * at(a, p, q);
    }
    if (off <= 1e-30 * std::max(diag, 1e-300)) break;
    for (int p = 0; p < n; ++p)
      for (int q = p + 1; q < n; ++q) {
        const double apq = at(a, p, q);
        if (std::abs(apq) < 1e-300) continue;
        const double theta = (at(a, q, q) - at(a, p, p)) / (2.0 * apq);
        const double t = (theta >= 0.0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
        const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
        for (int k = 0; k < n; ++k) {  // columns p, q of A
          const double akp = at(a, k, p), akq = at(a, k, q);
          at(a, k, p) = c * akp - s * akq;
          at(a, k, q) = s * akp + c * akq;
        }
        for (int k = 0; k < n; ++k) {  // rows p, q
          const double apk = at(a, p, k), aqk = at(a, q, k);
          at(a, p, k) = c * apk - s * aqk;
          at(a, q, k) = s * apk + c * aqk;
        }
        for (int k = 0; k < n; ++k) {
          const double vkp = at(vectors, k, p), vkq = at(vectors, k, q);
          at(vectors, k, p) = c * vkp - s * vkq;
          at(vectors, k, q) = s * vkp + c * vkq;
        }
      }
  }
  values.resize(n);
  for (int i = 0; i < n; ++i) values[i] = at(a, i, i);
}

namespace {
// F(M_f) 1 for a symmetric M_f and a scalar function F of its eigenvalues.
template <typename F>
ShVector matrix_function_times_one(const TripleProduct& gamma, const ShVector& f, F fn) {
  const int n = coefficients(gamma.order());
  std::vector<double> values, vectors;
  symmetric_eigen(gamma.product_matrix(f), n, values, vectors);
  // (V F(D) V^T)(sqrt(4 pi) e_0) = sqrt(4 pi) sum_k V_ik F(d_k) V_0k
  ShVector r(n, 0.0);
  const double one = std::sqrt(4.0 * M_PI);
  for (int k = 0; k < n; ++k) {
    const double w = one * fn(values[k]) * vectors[static_cast<size_t>(0) * n + k];
    for (int i = 0; i < n; ++i) r[i] += vectors[static_cast<size_t>(i) * n + k] * w;
  }
  return r;
}
}  // namespace

ShVector sh_exp_exact(const TripleProduct& gamma, const ShVector& f) {
  return matrix_function_times_one(gamma, f, [](double x) { return std::exp(x); });
}

ShVector sh_log_exact(const TripleProduct& gamma, const ShVector& g, double epsilon) {
  return matrix_function_times_one(gamma, g, [epsilon](double x) { return std::log(std::max(x, epsilon)); });
}

std::vector<double> blocker_zh(int order, double theta_rad) {
  std::vector<double> b = cap_zh(order, theta_rad);
  for (double& c : b) c = -c;
  b[0] += std::sqrt(4.0 * M_PI);
  return b;
}

std::vector<double> log_blocker_zh(const TripleProduct& gamma, double theta_rad, double epsilon) {
  const int order = gamma.order();
  const ShVector g = rotate_zh(blocker_zh(order, theta_rad), {0.0, 0.0, 1.0});
  const ShVector log_g = sh_log_exact(gamma, g, epsilon);
  // Back to ZH: on +z only m = 0 survives, c_l0 = sqrt(4 pi / (2l + 1)) zh_l y_l0(+z) = zh_l.
  std::vector<double> zh(order);
  for (int l = 0; l < order; ++l) zh[l] = log_g[l * (l + 1)];
  return zh;
}

OptimalLinearTable::OptimalLinearTable(const TripleProduct& gamma, int samples) {
  const int order = gamma.order();
  const int n = coefficients(order);
  // The single-sphere family, theta over (0, 90] degrees: |f^| grows monotonically with theta.
  const int sweep = 4 * samples;
  std::vector<double> mags{0.0};
  std::vector<glm::dvec2> abs{{1.0, 1.0}};
  for (int s = 1; s <= sweep; ++s) {
    const double theta = 0.5 * M_PI * s / sweep;
    ShVector f = rotate_zh(log_blocker_zh(gamma, theta), {0.0, 0.0, 1.0});
    f[0] = 0.0;
    const double m2 = sh_dot(f, f);
    if (m2 <= 1e-24) continue;
    const ShVector e = sh_exp_exact(gamma, f);
    const double a = e[0] / std::sqrt(4.0 * M_PI);  // e . 1 / (1 . 1)
    const double b = sh_dot(e, f) / m2;
    const double m = std::sqrt(m2);
    if (m <= mags.back()) continue;  // keep it monotone
    mags.push_back(m);
    abs.push_back({a, b});
  }
  (void)n;
  max_magnitude_ = mags.back();
  ab_.resize(samples);
  size_t k = 0;
  for (int s = 0; s < samples; ++s) {
    const double m = max_magnitude_ * s / (samples - 1);
    while (k + 2 < mags.size() && mags[k + 1] < m) ++k;
    const double t = std::clamp((m - mags[k]) / (mags[k + 1] - mags[k]), 0.0, 1.0);
    ab_[s] = abs[k] * (1.0 - t) + abs[k + 1] * t;
  }
}

glm::dvec2 OptimalLinearTable::at(double magnitude) const {
  const double x = std::clamp(magnitude / max_magnitude_, 0.0, 1.0) * (ab_.size() - 1);
  const size_t i = std::min(static_cast<size_t>(x), ab_.size() - 2);
  const double t = x - i;
  return ab_[i] * (1.0 - t) + ab_[i + 1] * t;
}

ShVector sh_exp_optimal_linear(const OptimalLinearTable& table, const ShVector& f) {
  ShVector hat = f;
  hat[0] = 0.0;
  const double m = std::sqrt(sh_dot(hat, hat));
  const glm::dvec2 ab = table.at(m);
  const double scale = std::exp(f[0] / std::sqrt(4.0 * M_PI));
  ShVector r(f.size());
  for (size_t i = 0; i < f.size(); ++i) r[i] = scale * ab.y * hat[i];
  r[0] = scale * ab.x * std::sqrt(4.0 * M_PI);
  return r;
}

ShVector sh_exp_hybrid(const TripleProduct& gamma, const OptimalLinearTable& table, const ShVector& f) {
  ShVector hat = f;
  hat[0] = 0.0;
  const double m = std::sqrt(sh_dot(hat, hat));
  int p = 0;
  while (p < kHybridMaxSquarings && m / std::ldexp(1.0, p) > kHybridMagnitude) ++p;
  for (double& c : hat) c = std::ldexp(c, -p);
  ShVector r = sh_exp_optimal_linear(table, hat);
  for (int k = 0; k < p; ++k) r = gamma.product(r, r);
  const double scale = std::exp(f[0] / std::sqrt(4.0 * M_PI));
  for (double& c : r) c *= scale;
  return r;
}

}  // namespace atmo::shadows
