// fog_reference.cpp — deterministic parts of the fog reference: phase, cone profile, slab optical
// thickness, the single-scattering integral along a ray and the surface integrals (eq. 15).
#include "fog_reference.h"

#include <algorithm>
#include <cmath>
#include <queue>
#include <vector>

namespace atmo::fog_reference {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();

// ---------------------------------------------------------------------------------------------
// Global adaptive Gauss-Kronrod G7/K15 (QUADPACK qk15 nodes and weights).
const double kXgk[8] = {0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
                        0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
                        0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
                        0.207784955007898467600689403773245, 0.0};
const double kWgk[8] = {0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
                        0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
                        0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
                        0.204432940075298892414161999234649, 0.209482141084727828012999174891714};
const double kWg[4] = {0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
                       0.381830050505118944950369775488975, 0.417959183673469387755102040816327};

struct Piece {
  double a, b, value, error;
  bool operator<(const Piece& o) const { return error < o.error; }  // max-heap on error
};

template <class F>
Piece gauss_kronrod(F& f, double a, double b) {
  const double c = 0.5 * (a + b), h = 0.5 * (b - a);
  const double fc = f(c);
  double k = fc * kWgk[7], g = fc * kWg[3];
  for (int j = 0; j < 7; ++j) {
    const double dx = h * kXgk[j];
    const double s = f(c - dx) + f(c + dx);
    k += kWgk[j] * s;
    if (j % 2 == 1) g += kWg[j / 2] * s;
  }
  return {a, b, k * h, std::abs((k - g) * h)};
}

// Integral of f over [points.front(), points.back()], with the (sorted) points as break points.
// Stops when the summed error estimate is <= max(abs_tol, rel_tol * |integral|).
template <class F>
double integrate(F&& f, std::vector<double> points, double rel_tol, double abs_tol = 0.0,
                 int max_pieces = 20000) {
  std::sort(points.begin(), points.end());
  points.erase(std::unique(points.begin(), points.end()), points.end());
  std::priority_queue<Piece> heap;
  double frozen_value = 0, frozen_error = 0;  // pieces too narrow to split further
  for (size_t i = 0; i + 1 < points.size(); ++i) heap.push(gauss_kronrod(f, points[i], points[i + 1]));
  auto totals = [&](double& value, double& error) {
    value = frozen_value;
    error = frozen_error;
    std::priority_queue<Piece> copy = heap;
    while (!copy.empty()) {
      value += copy.top().value;
      error += copy.top().error;
      copy.pop();
    }
  };
  double value = 0, error = 0;
  totals(value, error);
  int iterations = 0;
  while (!heap.empty() && error > std::max(abs_tol, rel_tol * std::abs(value)) &&
         static_cast<int>(heap.size()) < max_pieces) {
    const Piece worst = heap.top();
    heap.pop();
    const double mid = 0.5 * (worst.a + worst.b);
    if (!(mid > worst.a && mid < worst.b)) {  // at the resolution of double: keep as it is
      frozen_value += worst.value;
      frozen_error += worst.error;
      continue;
    }
    const Piece left = gauss_kronrod(f, worst.a, mid), right = gauss_kronrod(f, mid, worst.b);
    value += left.value + right.value - worst.value;
    error += left.error + right.error - worst.error;
    heap.push(left);
    heap.push(right);
    if (++iterations % 64 == 0) totals(value, error);  // no drift from the running sums
  }
  totals(value, error);
  return value;
}

double clamp_g(double g) { return std::clamp(g, -0.999999, 0.999999); }

bool is_omni(const Light& light) { return !(light.cos_outer > -1.0); }

bool is_unbounded(const Medium& m) { return m.bottom_m == -kInf && m.top_m == kInf; }

// Fraction of the segment za -> zb (z coordinates only) inside [bottom, top].
double slab_fraction(double za, double zb, double bottom, double top) {
  if (za == zb) return (za >= bottom && za <= top) ? 1.0 : 0.0;
  double t0 = (bottom - za) / (zb - za), t1 = (top - za) / (zb - za);
  if (t0 > t1) std::swap(t0, t1);
  const double lo = std::max(t0, 0.0), hi = std::min(t1, 1.0);
  return hi > lo ? hi - lo : 0.0;
}

glm::dvec3 any_perpendicular(const glm::dvec3& v) {
  const glm::dvec3 t = std::abs(v.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  return glm::normalize(t - glm::dot(t, v) * v);
}

// Real roots of A x^2 + B x + C = 0 appended to out (only those in (lo, hi)).
void add_quadratic_roots(double A, double B, double C, double lo, double hi, std::vector<double>& out) {
  auto add = [&](double x) {
    if (std::isfinite(x) && x > lo && x < hi) out.push_back(x);
  };
  const double scale = std::max({std::abs(A), std::abs(B), std::abs(C)});
  if (!(scale > 0)) return;
  if (std::abs(A) <= 1e-14 * scale) {
    if (B != 0) add(-C / B);
    return;
  }
  const double disc = B * B - 4 * A * C;
  if (disc < 0) return;
  const double q = -0.5 * (B + std::copysign(std::sqrt(disc), B));
  if (q != 0) {
    add(q / A);
    add(C / q);
  } else {
    add(0.0);
  }
}

}  // namespace

// -------------------------------------------------------------------------------------------------
double henyey_greenstein(double cos_scattering_angle, double g) {
  constexpr double inv4pi = 1.0 / (4.0 * kPi);
  if (g == 0) return inv4pi;
  g = clamp_g(g);
  const double mu = std::clamp(cos_scattering_angle, -1.0, 1.0);
  const double denom = 1.0 + g * g - 2.0 * g * mu;  // >= (1-|g|)^2 > 0
  return inv4pi * (1.0 - g * g) / (denom * std::sqrt(denom));
}

double light_profile(const Light& light, const glm::dvec3& direction_from_light) {
  if (is_omni(light)) return 1.0;
  const double len = glm::length(direction_from_light), axis_len = glm::length(light.axis);
  if (!(len > 0) || !(axis_len > 0)) return 1.0;
  const double c = glm::dot(direction_from_light, light.axis) / (len * axis_len);
  if (!(light.cos_inner > light.cos_outer)) return c >= light.cos_outer ? 1.0 : 0.0;
  const double t = std::clamp((c - light.cos_outer) / (light.cos_inner - light.cos_outer), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

double optical_thickness(const Medium& medium, const glm::dvec3& a, const glm::dvec3& b) {
  const double beta = medium.extinction_per_m;
  if (!(beta > 0)) return 0.0;
  const double len = glm::length(b - a);
  if (!(len > 0)) return 0.0;
  if (is_unbounded(medium)) return beta * len;
  return beta * len * slab_fraction(a.z, b.z, medium.bottom_m, medium.top_m);
}

// -------------------------------------------------------------------------------------------------
double single_scattering_radiance(const Medium& medium, const Light& light, const glm::dvec3& eye,
                                  const glm::dvec3& view_dir, double d_vp, double rel_tol) {
  const double beta = medium.extinction_per_m;
  const double sigma_s = beta * medium.albedo;
  if (!(beta > 0) || !(sigma_s > 0) || !(d_vp > 0) || light.intensity == 0) return 0.0;
  if (!std::isfinite(beta) || !std::isfinite(sigma_s)) return 0.0;
  const double view_len = glm::length(view_dir);
  if (!(view_len > 0) || !std::isfinite(view_len)) return 0.0;
  const glm::dvec3 v = view_dir / view_len;
  const glm::dvec3 w = light.position_m - eye;
  const double D = glm::length(w);
  if (!(D > 0) || !std::isfinite(D)) return 0.0;

  // Light = eye + x_c v + b n, with n unit and perpendicular to v.
  const double x_c = glm::dot(w, v);
  double b = glm::length(glm::cross(w, v));
  glm::dvec3 n = w - x_c * v;
  n -= glm::dot(n, v) * v;  // re-orthogonalise: the subtraction above cancels when gamma ~ 0 or pi
  const double n_len = glm::length(n);
  n = n_len > 0 ? n / n_len : any_perpendicular(v);  // on the line: any perpendicular displacement
  const double b_min = 1e-9 * D;
  if (!(b >= b_min)) b = b_min;  // light on the view line: see the header
  const glm::dvec3 light_pos = eye + x_c * v + b * n;  // equals light.position_m unless displaced

  // Closest point of the segment to the light, x*, and its distance c (> 0).
  const double x_star = std::clamp(x_c, 0.0, d_vp);
  const double z_star = x_star - x_c;  // z = x - x_c
  const double c = std::sqrt(z_star * z_star + b * b);

  const bool slab = !is_unbounded(medium);
  const bool omni = is_omni(light);
  const double g = clamp_g(medium.hg_g);
  const double I0 = light.intensity;

  // Break points in x.
  std::vector<double> xs = {0.0, d_vp};
  if (x_c > 0 && x_c < d_vp) xs.push_back(x_c);
  if (slab && v.z != 0) {
    for (double plane : {medium.bottom_m, medium.top_m}) {
      const double x = (plane - eye.z) / v.z;
      if (std::isfinite(x) && x > 0 && x < d_vp) xs.push_back(x);
    }
  }
  if (!omni) {
    const double axis_len = glm::length(light.axis);
    if (axis_len > 0) {
      const glm::dvec3 a = light.axis / axis_len;
      const glm::dvec3 w0 = eye - light_pos;
      for (double cc : {light.cos_inner, light.cos_outer}) {
        if (!(cc > -1 && cc < 1)) continue;
        const double va = glm::dot(v, a), wa = glm::dot(w0, a);
        add_quadratic_roots(va * va - cc * cc, 2 * (wa * va - cc * cc * glm::dot(w0, v)),
                            wa * wa - cc * cc * glm::dot(w0, w0), 0.0, d_vp, xs);
      }
    }
  }
  std::vector<double> etas;
  etas.reserve(xs.size());
  for (double x : xs) etas.push_back(std::isinf(x) ? 0.5 * kPi : std::atan((x - x_star) / c));
  // The eye end: exactly atan(-x*/c); the far end of an infinite ray: pi/2.

  auto integrand = [&](double eta) -> double {
    const double t = std::tan(eta);
    const double z = z_star + c * t;         // x - x_c, computed without cancellation near the peak
    const double x = std::max(x_c + z, 0.0);  // distance from the eye
    const double d2 = z * z + b * b;
    const double d = std::sqrt(d2);
    const double jacobian_over_d2 = c * (1.0 + t * t) / d2;  // (dx/deta) / d^2
    double tau;
    if (slab) {
      const double pz = eye.z + x * v.z;
      if (pz < medium.bottom_m || pz > medium.top_m) return 0.0;  // vacuum: no scattering
      tau = beta * (x * slab_fraction(eye.z, pz, medium.bottom_m, medium.top_m) +
                    d * slab_fraction(light_pos.z, pz, medium.bottom_m, medium.top_m));
    } else {
      tau = beta * (x + d);
    }
    const double cos_scattering = -z / d;  // light travels light->point, then point->eye (-v)
    const double profile = omni ? 1.0 : light_profile(light, (z * v - b * n) / d);
    if (profile == 0.0) return 0.0;
    const double value = sigma_s * henyey_greenstein(cos_scattering, g) * I0 * profile * std::exp(-tau) *
                         jacobian_over_d2;
    return std::isfinite(value) ? value : 0.0;
  };
  const double result = integrate(integrand, etas, std::max(rel_tol, 1e-14), 1e-300);
  return std::isfinite(result) ? result : 0.0;
}

// -------------------------------------------------------------------------------------------------
namespace {

// Integral over the hemisphere about `axis` of L_a(direction, D_vp = inf) * max(0, cos)^exponent.
double surface_integral(const Medium& medium, const Light& light, const glm::dvec3& point,
                        const glm::dvec3& axis_in, double exponent, double rel_tol) {
  const double beta = medium.extinction_per_m;
  if (!(beta > 0) || !(beta * medium.albedo > 0) || light.intensity == 0) return 0.0;
  if (!(exponent >= 0)) return 0.0;
  const glm::dvec3 to_light = light.position_m - point;
  const double D = glm::length(to_light);
  const double axis_len = glm::length(axis_in);
  if (!(D > 0) || !std::isfinite(D) || !(axis_len > 0)) return 0.0;
  rel_tol = std::max(rel_tol, 1e-12);
  const glm::dvec3 l = to_light / D, axis = axis_in / axis_len;
  // Frame about the light direction: e1 towards the axis.
  const double cos_th = std::clamp(glm::dot(axis, l), -1.0, 1.0);
  const double sin_th = glm::length(glm::cross(axis, l));
  glm::dvec3 e1 = axis - cos_th * l;
  e1 -= glm::dot(e1, l) * l;  // re-orthogonalise: the subtraction above cancels when sin_th is small
  const double e1_len = glm::length(e1);
  e1 = (sin_th > 1e-12 && e1_len > 0) ? e1 / e1_len : any_perpendicular(l);
  const glm::dvec3 e2 = glm::cross(l, e1);
  const double theta = std::atan2(sin_th, cos_th);

  auto weight = [exponent](double cosine) -> double {
    if (!(cosine > 0)) return 0.0;
    return exponent == 0 ? 1.0 : std::pow(std::min(cosine, 1.0), exponent);
  };
  const double tol_la = rel_tol * 1e-2, tol_inner = rel_tol * 1e-1;
  const bool symmetric = is_omni(light) && is_unbounded(medium);

  auto outer = [&](double gp) -> double {  // gp: polar angle about the light direction
    const double cg = std::cos(gp), sg = std::sin(gp);
    const double a = cg * cos_th, bb = sg * sin_th;  // cos to the axis = a + bb cos(phi)
    if (a + bb <= 0) return 0.0;                     // the whole circle is below the horizon
    const double phi_max = (a - bb >= 0) ? kPi : std::acos(std::clamp(-a / bb, -1.0, 1.0));
    if (symmetric) {
      const glm::dvec3 dir = cg * l + sg * e1;
      const double la = single_scattering_radiance(medium, light, point, dir, kInf, tol_la);
      if (la == 0.0) return 0.0;
      auto w_phi = [&](double phi) { return weight(a + bb * std::cos(phi)); };
      const double ring = 2.0 * integrate(w_phi, {0.0, phi_max}, tol_inner, 1e-300);
      return sg * la * ring;
    }
    auto f_phi = [&](double phi) {
      const double wgt = weight(a + bb * std::cos(phi));
      if (wgt == 0.0) return 0.0;
      const glm::dvec3 dir = cg * l + sg * (std::cos(phi) * e1 + std::sin(phi) * e2);
      return wgt * single_scattering_radiance(medium, light, point, dir, kInf, tol_la);
    };
    return sg * integrate(f_phi, {-phi_max, 0.0, phi_max}, tol_inner, 1e-300);
  };
  // Break points where the ring first touches / leaves the horizon: cos(gp + theta) = 0 or cos(gp - theta) = 0.
  std::vector<double> pts = {0.0, kPi};
  for (double p : {0.5 * kPi - theta, 1.5 * kPi - theta, theta + 0.5 * kPi, theta - 0.5 * kPi})
    if (p > 0 && p < kPi) pts.push_back(p);
  const double result = integrate(outer, pts, rel_tol, 1e-300);
  return std::isfinite(result) ? result : 0.0;
}

}  // namespace

double surface_scattered_lambert(const Medium& medium, const Light& light, const glm::dvec3& point,
                                 const glm::dvec3& normal, double rel_tol) {
  return surface_integral(medium, light, point, normal, 1.0, rel_tol);
}

double surface_scattered_phong(const Medium& medium, const Light& light, const glm::dvec3& point,
                               const glm::dvec3& reflected, double exponent, double rel_tol) {
  return surface_integral(medium, light, point, reflected, exponent, rel_tol);
}

}  // namespace atmo::fog_reference
