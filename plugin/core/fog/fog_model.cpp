#include "core/fog/fog_model.h"

#include "core/fog/fog_twin.h"

#include <algorithm>
#include <functional>
#include <map>
#include <mutex>
#include <thread>

#include "core/clouds/parallel_bands.h"

namespace atmo::fog {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Adaptive Simpson on [a, b] to absolute tolerance `tol` (templated: the integrands are inlined).
template <typename F>
double simpson_step(const F& f, double a, double b, double fa, double fm, double fb, double whole, double tol,
                    int depth) {
  const double m = 0.5 * (a + b), lm = 0.5 * (a + m), rm = 0.5 * (m + b);
  const double flm = f(lm), frm = f(rm);
  const double left = (m - a) / 6.0 * (fa + 4.0 * flm + fm);
  const double right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
  const double delta = left + right - whole;
  if (depth <= 0 || std::abs(delta) <= 15.0 * tol) return left + right + delta / 15.0;
  return simpson_step(f, a, m, fa, flm, fm, left, 0.5 * tol, depth - 1) +
         simpson_step(f, m, b, fm, frm, fb, right, 0.5 * tol, depth - 1);
}

// Adaptive Simpson started on `pieces` equal parts (so a narrow feature is not missed).
template <typename F>
double integrate(const F& f, double a, double b, double abs_tol, int pieces = 8) {
  double sum = 0.0;
  const double h = (b - a) / pieces;
  for (int i = 0; i < pieces; ++i) {
    const double x0 = a + i * h, x1 = x0 + h, xm = 0.5 * (x0 + x1);
    const double f0 = f(x0), fm = f(xm), f1 = f(x1);
    sum += simpson_step(f, x0, x1, f0, fm, f1, h / 6.0 * (f0 + 4.0 * fm + f1), abs_tol / pieces, 40);
  }
  return sum;
}

// 4 pi p(alpha) for the scattering angle alpha = 2 xi; from t = tan xi: cos 2 xi = (1 - t^2) / (1 + t^2).
double phase_weight(double xi, double g) { return 4.0 * kPi * henyey_greenstein(std::cos(2.0 * xi), g); }
double phase_weight_of_tan(double t, double g) {
  return 4.0 * kPi * henyey_greenstein((1.0 - t * t) / (1.0 + t * t), g);
}

// x^n, by squaring when n is a power of two (the surface table's exponents).
double lobe_power(double x, double n) {
  int k = 0;
  const double m = std::frexp(n, &k);  // n = m 2^k, m in [0.5, 1)
  if (m != 0.5 || k < 1 || k > 12) return std::pow(x, n);
  for (int i = 1; i < k; ++i) x *= x;
  return x;
}

// Up to 4 threads share a table's rows or columns (each texel written by one: the table does not depend on
// the count).
int table_threads() { return static_cast<int>(std::clamp(std::thread::hardware_concurrency(), 1u, 4u)); }

double thickness_from_coordinate(double x) {
  // x = sqrt(u / (1 + u))  =>  u = x^2 / (1 - x^2)
  const double x2 = x * x;
  return x2 >= 1.0 ? INFINITY : x2 / (1.0 - x2);
}

// C_n(gamma, theta) = integral_0^{2 pi} max(0, cos gamma cos theta + sin gamma sin theta cos phi)^n d phi.
double lobe_azimuth_integral(double gamma, double theta, double n) {
  const double a = std::cos(gamma) * std::cos(theta), b = std::sin(gamma) * std::sin(theta);
  if (a + b <= 0.0) return 0.0;
  const double phi0 = (a - b >= 0.0 || b <= 0.0) ? kPi : std::acos(std::clamp(-a / b, -1.0, 1.0));
  if (n == 1.0) return 2.0 * (a * phi0 + b * std::sin(phi0));
  // 24-point Gauss-Legendre on [0, phi0]: the integrand is smooth there.
  static const double x[12] = {0.0640568928626056, 0.1911188674736163, 0.3150426796961634, 0.4337935076260451,
                               0.5454214713888396, 0.6480936519369755, 0.7401241915785544, 0.8200019859739029,
                               0.8864155270044011, 0.9382745520027328, 0.9747285559713095, 0.9951872199970213};
  static const double w[12] = {0.1279381953467522, 0.1258374563468283, 0.1216704729278034, 0.1155056680537256,
                               0.1074442701159656, 0.0976186521041139, 0.0861901615319533, 0.0733464814110803,
                               0.0592985849154368, 0.0442774388174198, 0.0285313886289337, 0.0123412297999872};
  double sum = 0.0;
  for (int i = 0; i < 12; ++i) {
    for (double s : {-1.0, 1.0}) {
      const double phi = 0.5 * phi0 * (1.0 + s * x[i]);
      sum += w[i] * lobe_power(std::max(a + b * std::cos(phi), 0.0), n);
    }
  }
  return 2.0 * 0.5 * phi0 * sum;
}

}  // namespace

double extinction_from_visibility(double mor_m) { return std::log(20.0) / mor_m; }

double henyey_greenstein(double cos_angle, double g) {
  const double d = 1.0 + g * g - 2.0 * g * cos_angle;
  return (1.0 - g * g) / (4.0 * kPi * d * std::sqrt(d));
}

double FogOptics::transport_per_m() const { return extinction_per_m * (1.0 - albedo * phase_g); }

double FogOptics::diffusion_decay_per_m(double depth_m) const {
  const double tr = transport_per_m();
  const double absorption = extinction_per_m * (1.0 - albedo);
  double mu2 = 3.0 * tr * absorption;
  if (std::isfinite(depth_m) && tr > 0.0) {
    const double h_eff = std::max(depth_m, 0.0) + 2.0 * 2.0 / (3.0 * tr);
    mu2 += (kPi / h_eff) * (kPi / h_eff);
  }
  return std::sqrt(mu2);
}

double ghat(double u, double v, double g, double rel_tol) {
  v = std::clamp(v, 0.0, 0.5 * kPi);
  if (v >= 0.5 * kPi || std::isinf(u)) return 0.0;
  if (u < 1.0) {
    const double tv = std::tan(v);
    auto f = [&](double xi) {
      if (xi >= 0.5 * kPi) return u > 0.0 ? 0.0 : phase_weight(xi, g);
      const double t = std::tan(xi);
      return phase_weight_of_tan(t, g) * (u > 0.0 ? std::exp(-u * (t - tv)) : 1.0);
    };
    // The integral's size, for the tolerance only: an 8-point midpoint sum of the phase part.
    double scale = 0.0;
    for (int k = 0; k < 8; ++k) scale += phase_weight(v + (k + 0.5) / 8.0 * (0.5 * kPi - v), g);
    scale *= (0.5 * kPi - v) / 8.0;
    return integrate(f, v, 0.5 * kPi, rel_tol * std::max(scale, 1e-30), 16);
  }
  // u >= 1: s = tan xi - tan v = y / u, y = -ln(1 - w): Ghat = (1/u) int_0^1 q(xi) / (1 + (tan v + s)^2) dw.
  const double tv = std::tan(v);
  auto f = [&](double w) {
    if (w >= 1.0) return 0.0;
    const double s = -std::log1p(-w) / u;
    const double t = tv + s;
    return phase_weight_of_tan(t, g) / (1.0 + t * t);
  };
  const double estimate = f(0.0);
  return integrate(f, 0.0, 1.0, rel_tol * std::max(estimate, 1e-30), 16) / u;
}

double ghat_u_limit(double v, double g) {
  const double c = std::cos(v);
  return phase_weight(v, g) * c * c;
}

FogTable build_airlight_table(int size, double g) {
  FogTable t;
  t.width = t.height = size;
  t.texels.resize(static_cast<size_t>(size) * size);
  clouds::for_bands(size, table_threads(), [&](int begin, int end) {
    for (int j = begin; j < end; ++j) {
      // The v = pi/2 row holds the limit y -> 0, taken at a y far below any texel.
      const double y = std::max(0.5 * kPi * (1.0 - static_cast<double>(j) / (size - 1)), 1e-7);
      const double v = 0.5 * kPi - y;
      for (int i = 0; i < size; ++i) {
        // The u = inf column holds the limit, taken at a u far above any texel's.
        const double u = std::min(thickness_from_coordinate(static_cast<double>(i) / (size - 1)), 1e8);
        const double scale = twin::atmo_fog_ghat_scale(static_cast<float>(u), static_cast<float>(y));
        t.texels[static_cast<size_t>(j) * size + i] = static_cast<float>(ghat(u, v, g, 1e-7) / scale);  // float texels
      }
    }
  });
  return t;
}

namespace {

// e^T G_n(T, theta) = integral_0^pi Ghat(T sin gamma, gamma / 2) C_n(gamma, theta) d gamma,
// by composite Simpson on `ghat_row` (Ghat at gamma_j = pi j / (m - 1), m odd) against the lobe's
// azimuth integrals C_n(gamma_j, theta), which do not depend on T (or on the phase): `lobe_row`.
double surface_integral(const std::vector<double>& ghat_row, const double* lobe_row) {
  const int m = static_cast<int>(ghat_row.size());
  const double h = kPi / (m - 1);
  double sum = 0.0;
  for (int j = 0; j < m; ++j) {
    const double wj = (j == 0 || j == m - 1) ? 1.0 : (j % 2 ? 4.0 : 2.0);
    sum += wj * ghat_row[j] * lobe_row[j];
  }
  return sum * h / 3.0;
}

std::vector<double> lobe_row(double theta, double n, int m) {
  std::vector<double> row(m);
  for (int j = 0; j < m; ++j) row[j] = lobe_azimuth_integral(kPi * j / (m - 1), theta, n);
  return row;
}

// The surface table's Ghat to this relative tolerance: its texels are floats, interpolated, and the surface
// integral averages over gamma.
constexpr double kSurfaceTolerance = 1e-6;

std::vector<double> surface_ghat_row(double thickness, double g, int m) {
  std::vector<double> row(m);
  for (int j = 0; j < m; ++j) {
    const double gamma = kPi * j / (m - 1);
    row[j] = ghat(thickness * std::sin(gamma), 0.5 * gamma, g, kSurfaceTolerance);
  }
  return row;
}

// 257 samples of gamma: the Lambertian surface term's worst error to T 14 is that of 513 (1.204 against 1.203 %,
// FogSurfaceTerm), in half the time.
constexpr int kSurfaceGammaSamples = 257;

// The lobes' azimuth integrals for every row of a surface table of theta_size angles (layer k, angle j):
// they depend on neither the thickness nor the phase, so a process makes them once per table height.
const std::vector<double>& surface_lobes(int theta_size) {
  static std::mutex mutex;
  static std::map<int, std::vector<double>> made;
  const std::lock_guard<std::mutex> lock(mutex);
  std::vector<double>& lobes = made[theta_size];
  if (lobes.empty()) {
    const int m = kSurfaceGammaSamples, rows = theta_size * kSurfaceLayers;
    lobes.resize(static_cast<size_t>(rows) * m);
    clouds::for_bands(rows, table_threads(), [&](int begin, int end) {
      for (int r = begin; r < end; ++r) {
        const double n = std::ldexp(1.0, r / theta_size), theta = kPi * (r % theta_size) / (theta_size - 1);
        const std::vector<double> row = lobe_row(theta, n, m);
        std::copy(row.begin(), row.end(), lobes.begin() + static_cast<std::ptrdiff_t>(r) * m);
      }
    });
  }
  return lobes;
}

}  // namespace

std::shared_ptr<const FogTables> fog_tables(double g, int airlight_size, int surface_size) {
  struct Made {
    double g;
    int airlight_size, surface_size;
    std::shared_ptr<const FogTables> tables;
  };
  constexpr size_t kKept = 4;
  static std::mutex mutex;
  static std::vector<Made> made;  // the most recently used last
  const std::lock_guard<std::mutex> lock(mutex);
  for (size_t k = 0; k < made.size(); ++k)
    if (made[k].g == g && made[k].airlight_size == airlight_size && made[k].surface_size == surface_size) {
      std::rotate(made.begin() + static_cast<std::ptrdiff_t>(k), made.begin() + static_cast<std::ptrdiff_t>(k) + 1,
                  made.end());
      return made.back().tables;
    }
  auto tables = std::make_shared<FogTables>();
  tables->airlight = build_airlight_table(airlight_size, g);
  tables->surface = build_surface_table(surface_size, surface_size, g);
  if (made.size() == kKept) made.erase(made.begin());
  made.push_back({g, airlight_size, surface_size, tables});
  return tables;
}

double surface_g(double thickness, double theta, double exponent, double g) {
  const int m = 4097;
  return std::exp(-thickness) * surface_integral(surface_ghat_row(thickness, g, m), lobe_row(theta, exponent, m).data());
}

FogTable build_surface_table(int thickness_size, int theta_size, double g) {
  FogTable t;
  t.width = thickness_size;
  t.height = theta_size * kSurfaceLayers;
  t.texels.assign(static_cast<size_t>(t.width) * t.height, 0.0f);
  const int m = kSurfaceGammaSamples;
  const std::vector<double>& lobes = surface_lobes(theta_size);
  clouds::for_bands(thickness_size, table_threads(), [&](int begin, int end) {
    for (int i = begin; i < end; ++i) {
      const double x = static_cast<double>(i) / (thickness_size - 1);
      // The last column is T = inf: e^T G falls slowly there (5.0 at T = 15, 4.5 at 30, 3.4 at 100 for n = 1,
      // theta = 0, g = 0.85), so it holds T = 100; the term it scales carries e^-T, below 1e-6 of the direct
      // light beyond T = 15. ((1 + T) e^T G, the earlier texel, grows like T: 4.7x too high at T = 17.)
      const double thickness = std::min(thickness_from_coordinate(x), 100.0);
      const std::vector<double> row = surface_ghat_row(thickness, g, m);
      for (int r = 0; r < t.height; ++r)
        t.texels[static_cast<size_t>(r) * t.width + i] =
            static_cast<float>(surface_integral(row, lobes.data() + static_cast<size_t>(r) * m));
    }
  });
  return t;
}

GlowBound::GlowBound(double g) : ghat0_(257), shape_max_(257, 0.0) {
  const int n = static_cast<int>(ghat0_.size());
  for (int i = 0; i < n; ++i) ghat0_[i] = ghat(0.0, 0.5 * kPi * i / (n - 1), g, 1e-7);
  for (int i = n - 2; i >= 1; --i)
    shape_max_[i] = std::max(std::max(ghat0_[i], ghat0_[i - 1]) / std::sin(kPi * i / (n - 1)), shape_max_[i + 1]);
}

double GlowBound::radius_rad(double beta, double albedo, double distance_m, double intensity_cd,
                             double threshold_cd_m2) const {
  if (!(beta > 0.0) || !(intensity_cd > 0.0) || !(distance_m > 0.0)) return 0.0;
  const double scale = albedo * intensity_cd * std::exp(-beta * distance_m) * beta / (2.0 * kPi * distance_m);
  const int n = static_cast<int>(ghat0_.size());
  // Ghat(0, .) falls with the angle, so no sample off the core can beat the first one's bound: a dim or far
  // light (most of a city's) is settled here.
  if (scale * ghat0_[0] / std::sin(kPi / (n - 1)) < threshold_cd_m2)
    return std::min(scale * ghat0_[0] / threshold_cd_m2, kPi / (n - 1));
  // From the back (pi) towards the light: the first sample above the threshold (with its neighbour's Ghat,
  // as the bound must hold between samples): the largest i whose suffix maximum reaches it, by bisection.
  const double want = threshold_cd_m2 / scale;
  if (shape_max_[1] >= want) {
    int lo = 1, hi = n - 2;  // shape_max_[lo] >= want; find the largest such
    while (lo < hi) {
      const int mid = (lo + hi + 1) / 2;
      if (shape_max_[mid] >= want)
        lo = mid;
      else
        hi = mid - 1;
    }
    return std::min(kPi * (lo + 1) / (n - 1), kPi);
  }
  // Only the core, where sin(gamma) ~ gamma and Ghat ~ Ghat(0, 0).
  return std::min(scale * ghat0_[0] / threshold_cd_m2, kPi / (n - 1));
}

}  // namespace atmo::fog
