#include "reference.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <thread>

#include "core/spectral/colorimetry.h"

namespace atmo::reference {

namespace {

using glm::dvec3;
using spectral::kPi;
using spectral::SpectralAtmosphere;

// splitmix64 (Steele, Lea & Flood 2014): tiny, seedable, statistically good enough here.
struct Rng {
  std::uint64_t state;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  // Open interval (0, 1): -log(1 - u) and 1/u stay finite.
  double uniform() { return (static_cast<double>(next() >> 11) + 0.5) * 0x1.0p-53; }
};

Rng make_rng(std::uint64_t seed, std::uint64_t stream) {
  Rng a{seed};
  Rng b{a.next() ^ (stream * 0xd1342543de82ef95ull)};
  b.next();
  return b;
}

double rayleigh_phase(double c) { return 3.0 / (16.0 * kPi) * (1.0 + c * c); }

double cornette_shanks_phase(double g, double c) {
  const double g2 = g * g;
  const double denom = 1.0 + g2 - 2.0 * g * c;
  return 3.0 / (8.0 * kPi) * (1.0 - g2) / (2.0 + g2) * (1.0 + c * c) / (denom * std::sqrt(denom));
}

double henyey_greenstein_pdf(double g, double c) {
  const double denom = 1.0 + g * g - 2.0 * g * c;
  return (1.0 - g * g) / (4.0 * kPi * denom * std::sqrt(denom));
}

// Orthonormal basis around a unit vector (Duff et al. 2017, JCGT 6(1)).
void basis(const dvec3& n, dvec3& t, dvec3& b) {
  const double s = std::copysign(1.0, n.z);
  const double a = -1.0 / (s + n.z);
  const double xy = n.x * n.y * a;
  t = dvec3(1.0 + s * n.x * n.x * a, s * xy, -s * n.x);
  b = dvec3(xy, s + n.y * n.y * a, -n.y);
}

// Direction about `axis` with cos(angle) drawn from Henyey-Greenstein(g).
dvec3 sample_henyey_greenstein(const dvec3& axis, double g, double u1, double u2) {
  double c = 1.0 - 2.0 * u1;
  if (g != 0.0) {
    const double s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u1);
    c = (1.0 + g * g - s * s) / (2.0 * g);
  }
  c = std::clamp(c, -1.0, 1.0);
  const double sn = std::sqrt(std::max(0.0, 1.0 - c * c));
  dvec3 t, b;
  basis(axis, t, b);
  const double phi = 2.0 * kPi * u2;
  return glm::normalize(t * (sn * std::cos(phi)) + b * (sn * std::sin(phi)) + axis * c);
}

// Cosine-weighted hemisphere around n.
dvec3 sample_cosine_direction(const dvec3& n, Rng& rng) {
  const double u1 = rng.uniform(), u2 = rng.uniform();
  const double r = std::sqrt(u1), phi = 2.0 * kPi * u2;
  dvec3 t, b;
  basis(n, t, b);
  return glm::normalize(t * (r * std::cos(phi)) + b * (r * std::sin(phi)) + n * std::sqrt(1.0 - u1));
}

bool sphere_hits(const dvec3& p, const dvec3& d, double radius, double* near, double* far) {
  const double b = glm::dot(p, d);
  const double c = glm::dot(p, p) - radius * radius;
  const double disc = b * b - c;
  if (disc < 0.0) return false;
  const double s = std::sqrt(disc);
  *near = -b - s;
  *far = -b + s;
  return true;
}

// One quadrature interval of a ray: the medium is taken as constant over it,
// with the densities at its midpoint (x: Rayleigh, y: aerosols, z: ozone).
struct Node {
  double t0;
  double dt;
  dvec3 rho;
};

class Integrator {
 public:
  Integrator(const SpectralAtmosphere& atm, const Settings& s, const dvec3& sun_dir)
      : atm_(atm), s_(s), sun_(glm::normalize(sun_dir)), n_(atm.size()) {
    if (atm.rayleigh_scattering.size() != n_ || atm.mie_scattering.size() != n_ ||
        atm.mie_extinction.size() != n_ || atm.ozone_absorption.size() != n_ || atm.solar_irradiance.size() != n_)
      throw std::invalid_argument("reference: SpectralAtmosphere vectors differ in length");
    for (size_t k = 0; k < n_; ++k) {
      rayleigh_sum_ += atm.rayleigh_scattering[k];
      mie_sum_ += atm.mie_scattering[k];
    }
    f_.resize(n_);
    pdf_.resize(n_);
    tmp_.resize(n_);
  }

  void radiance(const dvec3& eye, const dvec3& dir, Rng& rng, Radiance* out);

 private:
  double sigma_t(size_t k, const dvec3& rho) const {
    return atm_.rayleigh_scattering[k] * rho.x + atm_.mie_extinction[k] * rho.y + atm_.ozone_absorption[k] * rho.z;
  }
  double tau(size_t k, const dvec3& column) const { return sigma_t(k, column); }  // same linear form
  // Scattering coefficient times phase function, 1/(m sr).
  double scatter(size_t k, const dvec3& rho, double phase_r, double phase_m) const {
    return atm_.rayleigh_scattering[k] * rho.x * phase_r + atm_.mie_scattering[k] * rho.y * phase_m;
  }

  dvec3 density(const dvec3& p) const {
    const double h = glm::length(p) - atm_.bottom_radius_m;
    return dvec3(atm_.rayleigh_density(h), atm_.mie_density(h), atm_.ozone_density(h));
  }

  // Nodes over [t0, t1] of the ray o + t d (o from the planet's centre).
  // Altitude along a line is monotone on each side of the point closest to
  // the centre, so the ray is split there and each piece gets quadratic
  // spacing that is finest at its low-altitude end, where the air is densest.
  void march(const dvec3& o, const dvec3& d, double t0, double t1, int n, std::vector<Node>& out) const {
    out.clear();
    if (!(t1 > t0) || n < 1) return;
    auto piece = [&](double a, double b, int m, bool fine_at_start) {
      for (int i = 0; i < m; ++i) {
        const double u0 = double(i) / m, u1 = double(i + 1) / m;
        const double s0 = fine_at_start ? u0 * u0 : 1.0 - (1.0 - u0) * (1.0 - u0);
        const double s1 = fine_at_start ? u1 * u1 : 1.0 - (1.0 - u1) * (1.0 - u1);
        const double ta = a + (b - a) * s0, tb = a + (b - a) * s1;
        out.push_back({ta, tb - ta, density(o + d * (0.5 * (ta + tb)))});
      }
    };
    const double t_low = -glm::dot(o, d);
    if (t_low > t0 && t_low < t1 && n >= 2) {
      const int n1 = std::clamp(static_cast<int>(std::lround(n * (t_low - t0) / (t1 - t0))), 1, n - 1);
      piece(t0, t_low, n1, false);
      piece(t_low, t1, n - n1, true);
    } else {
      piece(t0, t1, n, t_low <= t0);
    }
  }

  // Column densities (m) from x to the top towards the sun; false in the Earth's shadow.
  bool sun_column(const dvec3& x, dvec3* column) {
    double near, far;
    if (sphere_hits(x, sun_, atm_.bottom_radius_m, &near, &far) && far > 0.0) return false;
    *column = dvec3(0.0);
    if (!sphere_hits(x, sun_, atm_.top_radius_m, &near, &far) || far <= 0.0) return true;
    march(x, sun_, 0.0, far, s_.transmittance_steps, sun_nodes_);
    for (const Node& nd : sun_nodes_) *column += nd.rho * nd.dt;
    return true;
  }

  // Distance from x along d to the ground (*ground = true) or out of the atmosphere.
  double segment_end(const dvec3& x, const dvec3& d, bool* ground) const {
    double near, far;
    *ground = false;
    if (sphere_hits(x, d, atm_.bottom_radius_m, &near, &far) && near > 0.0) {
      *ground = true;
      return near;
    }
    if (!sphere_hits(x, d, atm_.top_radius_m, &near, &far)) return 0.0;
    return std::max(far, 0.0);
  }

  void add_sun_scatter(const dvec3& x, const dvec3& d, const dvec3& rho, const double* weight, double scale,
                       double* accum) {
    dvec3 column;
    if (!sun_column(x, &column)) return;
    const double c = glm::dot(d, sun_);
    const double pr = rayleigh_phase(c), pm = cornette_shanks_phase(atm_.mie_g, c);
    for (size_t k = 0; k < n_; ++k)
      accum[k] += weight[k] * scale * scatter(k, rho, pr, pm) * std::exp(-tau(k, column)) * atm_.solar_irradiance[k];
  }

  void add_sun_ground(const dvec3& x, const double* weight, double scale, double* accum) {
    const double mu_s = glm::dot(glm::normalize(x), sun_);
    if (mu_s <= 0.0) return;
    dvec3 column;
    if (!sun_column(x, &column)) return;
    for (size_t k = 0; k < n_; ++k)
      accum[k] += weight[k] * scale * atm_.ground_albedo / kPi * mu_s * std::exp(-tau(k, column)) *
                  atm_.solar_irradiance[k];
  }

  // Next direction after a scattering at a point reached along d (densities
  // rho): with probability 0.8 the medium's own phase function, Rayleigh or
  // aerosol in proportion to their scattering summed over all wavelengths (so
  // the pdf is the same for every hero wavelength), the aerosol lobe drawn
  // from Henyey-Greenstein (Cornette-Shanks / HG <= 1.14); with probability
  // 0.2 Henyey-Greenstein about the sun, for the bright aureole that the next
  // vertex sees through its forward peak. phase/pdf then stays below ~1.5,
  // so path weights do not grow with the order. Returns the pdf.
  dvec3 sample_scatter_direction(const dvec3& d, const dvec3& rho, Rng& rng, double* pdf) const {
    const double g = atm_.mie_g;
    const double rayleigh = rayleigh_sum_ * rho.x, mie = mie_sum_ * rho.y;
    const double a_r = rayleigh + mie > 0.0 ? rayleigh / (rayleigh + mie) : 1.0;
    const double u0 = rng.uniform();
    dvec3 d2;
    if (u0 < 0.8 * a_r) {
      double c;
      do c = 1.0 - 2.0 * rng.uniform();  // rejection: (1 + c^2) / 2 under the uniform density
      while (rng.uniform() * 2.0 > 1.0 + c * c);
      d2 = sample_henyey_greenstein(d, 0.0, 0.5 * (1.0 - c), rng.uniform());
    } else if (u0 < 0.8) {
      d2 = sample_henyey_greenstein(d, g, rng.uniform(), rng.uniform());
    } else {
      d2 = sample_henyey_greenstein(sun_, g, rng.uniform(), rng.uniform());
    }
    const double c = glm::dot(d, d2);
    *pdf = 0.8 * (a_r * rayleigh_phase(c) + (1.0 - a_r) * henyey_greenstein_pdf(g, c)) +
           0.2 * henyey_greenstein_pdf(g, glm::dot(sun_, d2));
    return d2;
  }
  // Next direction off the Lambertian ground: half cosine-weighted, half
  // towards the sun's aureole. Returns albedo/pi * cos / pdf (0 below the horizon).
  dvec3 sample_ground_direction(const dvec3& n, Rng& rng, double* weight) const {
    const double u0 = rng.uniform();
    const dvec3 d2 = u0 < 0.5 ? sample_cosine_direction(n, rng)
                              : sample_henyey_greenstein(sun_, atm_.mie_g, rng.uniform(), rng.uniform());
    const double c = glm::dot(n, d2);
    const double pdf = 0.5 * std::max(c, 0.0) / kPi + 0.5 * henyey_greenstein_pdf(atm_.mie_g, glm::dot(sun_, d2));
    *weight = c > 0.0 ? atm_.ground_albedo / kPi * c / pdf : 0.0;
    return d2;
  }

  void trace(dvec3 x, dvec3 d, int order, Rng& rng, double* accum);

  const SpectralAtmosphere& atm_;
  const Settings& s_;
  dvec3 sun_;
  size_t n_;
  double rayleigh_sum_ = 0.0, mie_sum_ = 0.0;
  std::vector<Node> view_nodes_, path_nodes_, sun_nodes_;
  std::vector<double> f_, pdf_, tmp_;
};

// Radiance arriving at x from direction d (light travelling along -d) that
// has interacted at least once more, weighted by f_ on entry. Free paths are
// sampled at a hero wavelength and every wavelength is weighted by the
// balance heuristic over all wavelengths (one-sample spectral MIS, Wilkie et
// al. 2014): w_k = f_k / mean_j pdf_j, bounded by N · albedo. f_ and pdf_ are
// both divided by the hero's pdf after each event so they stay O(1).
void Integrator::trace(dvec3 x, dvec3 d, int order, Rng& rng, double* accum) {
  const size_t hero = std::min(static_cast<size_t>(rng.uniform() * n_), n_ - 1);
  std::fill(pdf_.begin(), pdf_.end(), 1.0);
  // Russian roulette compares the weight with the path's starting weight (which
  // carries the view ray's dt and transmittance), not with 1.
  double start_weight = 0.0;
  for (size_t k = 0; k < n_; ++k) start_weight = std::max(start_weight, f_[k]);
  if (!(start_weight > 0.0)) return;
  for (;;) {
    bool ground;
    const double t_end = segment_end(x, d, &ground);
    march(x, d, 0.0, t_end, s_.transmittance_steps, path_nodes_);
    const double target = -std::log(rng.uniform());
    dvec3 column(0.0), rho_hit(0.0);
    double tau_hero = 0.0, t_hit = 0.0;
    bool collided = false;
    for (const Node& nd : path_nodes_) {
      const double sig = sigma_t(hero, nd.rho);
      if (tau_hero + sig * nd.dt >= target && sig > 0.0) {
        const double s = (target - tau_hero) / sig;
        column += nd.rho * s;
        t_hit = nd.t0 + s;
        rho_hit = nd.rho;
        collided = true;
        break;
      }
      tau_hero += sig * nd.dt;
      column += nd.rho * nd.dt;
    }
    for (size_t k = 0; k < n_; ++k) {
      const double tr = std::exp(-tau(k, column));
      f_[k] *= tr;
      pdf_[k] *= collided ? sigma_t(k, rho_hit) * tr : tr;
    }
    const double norm = pdf_[hero];
    if (!(norm > 0.0)) return;
    double mean_pdf = 0.0;
    for (size_t k = 0; k < n_; ++k) {
      f_[k] /= norm;
      pdf_[k] /= norm;
      mean_pdf += pdf_[k];
    }
    const double mis = static_cast<double>(n_) / mean_pdf;

    if (!collided && !ground) return;  // escaped to space
    ++order;
    if (collided) {
      x += d * t_hit;
      if (order <= s_.max_scattering_order) add_sun_scatter(x, d, rho_hit, f_.data(), mis, accum);
    } else {
      const dvec3 n = glm::normalize(x + d * t_end);
      x = n * (atm_.bottom_radius_m + 1e-3);  // just above the ground, so the next ray leaves it
      if (order <= s_.max_scattering_order) add_sun_ground(x, f_.data(), mis, accum);
    }
    if (order + 1 > s_.max_scattering_order) return;

    // Russian roulette on the largest weight, after a few orders.
    if (order >= 4) {
      double wmax = 0.0;
      for (size_t k = 0; k < n_; ++k) wmax = std::max(wmax, f_[k] * mis);
      const double q = std::min(1.0, wmax / start_weight);
      if (!(rng.uniform() < q)) return;
      for (size_t k = 0; k < n_; ++k) f_[k] /= q;
    }

    if (collided) {
      double pdf_dir;
      const dvec3 d2 = sample_scatter_direction(d, rho_hit, rng, &pdf_dir);
      const double c = glm::dot(d, d2);
      const double pr = rayleigh_phase(c), pm = cornette_shanks_phase(atm_.mie_g, c);
      for (size_t k = 0; k < n_; ++k) f_[k] *= scatter(k, rho_hit, pr, pm) / pdf_dir;
      d = d2;
    } else {
      double w;
      d = sample_ground_direction(glm::normalize(x), rng, &w);
      if (w == 0.0) return;
      for (size_t k = 0; k < n_; ++k) f_[k] *= w;
    }
  }
}

void Integrator::radiance(const dvec3& eye, const dvec3& dir, Rng& rng, Radiance* out) {
  out->spectral.assign(n_, 0.0);
  out->transmittance.assign(n_, 1.0);
  out->hits_ground = false;
  double* L = out->spectral.data();
  double near, far;
  double t0 = 0.0;
  if (glm::length(eye) > atm_.top_radius_m) {
    if (!sphere_hits(eye, dir, atm_.top_radius_m, &near, &far) || far <= 0.0) return;  // misses the atmosphere
    t0 = std::max(near, 0.0);
  }
  bool ground;
  const double t_end = segment_end(eye + dir * t0, dir, &ground) + t0;
  march(eye, dir, t0, t_end, s_.view_steps, view_nodes_);

  const int max_order = s_.max_scattering_order;
  const double c_sun = glm::dot(dir, sun_);
  const double pr_sun = rayleigh_phase(c_sun), pm_sun = cornette_shanks_phase(atm_.mie_g, c_sun);
  std::vector<double> t_view(n_);
  dvec3 column(0.0);
  for (const Node& nd : view_nodes_) {
    // Midpoint rule: transmittance from the eye to the node's centre.
    const dvec3 mid_column = column + nd.rho * (0.5 * nd.dt);
    for (size_t k = 0; k < n_; ++k) t_view[k] = std::exp(-tau(k, mid_column));
    const dvec3 x = eye + dir * (nd.t0 + 0.5 * nd.dt);
    if (max_order >= 1) {
      dvec3 sun_col;
      if (sun_column(x, &sun_col))
        for (size_t k = 0; k < n_; ++k)
          L[k] += t_view[k] * scatter(k, nd.rho, pr_sun, pm_sun) * std::exp(-tau(k, sun_col)) *
                  atm_.solar_irradiance[k] * nd.dt;
    }
    if (max_order >= 2) {
      for (int j = 0; j < s_.paths_per_step; ++j) {
        double pdf_dir;
        const dvec3 d2 = sample_scatter_direction(dir, nd.rho, rng, &pdf_dir);
        const double c = glm::dot(dir, d2);
        const double pr = rayleigh_phase(c), pm = cornette_shanks_phase(atm_.mie_g, c);
        for (size_t k = 0; k < n_; ++k)
          f_[k] = t_view[k] * nd.dt * scatter(k, nd.rho, pr, pm) / (pdf_dir * s_.paths_per_step);
        trace(x, d2, 1, rng, L);
      }
    }
    column += nd.rho * nd.dt;
  }
  for (size_t k = 0; k < n_; ++k) out->transmittance[k] = std::exp(-tau(k, column));

  if (ground) {
    out->hits_ground = true;
    const dvec3 n = glm::normalize(eye + dir * t_end);
    const dvec3 xg = n * (atm_.bottom_radius_m + 1e-3);
    if (max_order >= 1) add_sun_ground(xg, out->transmittance.data(), 1.0, L);
    if (max_order >= 2) {
      for (int j = 0; j < s_.ground_paths; ++j) {
        double w;
        const dvec3 d2 = sample_ground_direction(n, rng, &w);
        if (w == 0.0) continue;
        for (size_t k = 0; k < n_; ++k) f_[k] = out->transmittance[k] * w / s_.ground_paths;
        trace(xg, d2, 1, rng, L);
      }
    }
  }
}

Radiance radiance_impl(const SpectralAtmosphere& atm, double eye_altitude_m, const dvec3& view_dir, const dvec3& sun_dir,
                       const Settings& settings, std::uint64_t stream, const spectral::SpectrumToColor& color) {
  Radiance r;
  Integrator integrator(atm, settings, sun_dir);
  Rng rng = make_rng(settings.seed, stream);
  const dvec3 eye(0.0, 0.0, atm.bottom_radius_m + std::max(eye_altitude_m, 0.0));
  integrator.radiance(eye, glm::normalize(view_dir), rng, &r);
  r.linear_srgb = color.linear_srgb(r.spectral);
  r.luminance_cd_m2 = color.luminance(r.spectral);
  return r;
}

}  // namespace

Radiance sky_radiance(const SpectralAtmosphere& atm, double eye_altitude_m, const dvec3& view_dir_enu,
                      const dvec3& sun_dir_enu, const Settings& settings, std::uint64_t stream) {
  const spectral::SpectrumToColor color(atm.wavelengths_nm);
  return radiance_impl(atm, eye_altitude_m, view_dir_enu, sun_dir_enu, settings, stream, color);
}

dvec3 enu_direction(double heading_deg, double elevation_deg) {
  const double h = heading_deg * kPi / 180.0, e = elevation_deg * kPi / 180.0;
  return dvec3(std::sin(h) * std::cos(e), std::cos(h) * std::cos(e), std::sin(e));
}

glm::dmat3 enu_from_view(double heading_deg, double pitch_deg) {
  const double h = heading_deg * kPi / 180.0;
  const dvec3 forward = enu_direction(heading_deg, pitch_deg);
  const dvec3 right(std::cos(h), -std::sin(h), 0.0);  // also defined looking straight up or down
  const dvec3 up = glm::cross(right, forward);
  return glm::dmat3(right, up, -forward);
}

Image render_image(const SpectralAtmosphere& atm, double eye_altitude_m, const Camera& camera, const dvec3& sun_dir_enu,
                   const Settings& settings, int threads) {
  Image image;
  image.width = camera.width;
  image.height = camera.height;
  const size_t count = static_cast<size_t>(camera.width) * camera.height;
  image.linear_srgb.assign(count, dvec3(0.0));
  image.luminance_cd_m2.assign(count, 0.0);
  const spectral::SpectrumToColor color(atm.wavelengths_nm);
  const double tan_half = std::tan(0.5 * camera.vertical_fov_rad);
  const double aspect = double(camera.width) / camera.height;
  threads = std::max(1, threads);
  auto work = [&](int first_row) {
    for (int y = first_row; y < camera.height; y += threads) {
      for (int x = 0; x < camera.width; ++x) {
        const double ndc_x = (x + 0.5) / camera.width * 2.0 - 1.0;
        const double ndc_y = 1.0 - (y + 0.5) / camera.height * 2.0;  // row 0 at the top
        const dvec3 view(ndc_x * tan_half * aspect, ndc_y * tan_half, -1.0);
        const dvec3 dir = glm::normalize(camera.enu_from_view * view);
        const size_t i = static_cast<size_t>(y) * camera.width + x;
        Radiance r = radiance_impl(atm, eye_altitude_m, dir, sun_dir_enu, settings, i, color);
        image.linear_srgb[i] = r.linear_srgb;
        image.luminance_cd_m2[i] = r.luminance_cd_m2;
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(work, t);
  work(0);
  for (std::thread& t : pool) t.join();
  return image;
}

}  // namespace atmo::reference
