// atmo_fog_error_chart — the error of the fog glow's airlight table against the table's size and precision,
// for the plugin's stable form and for the paper's F-function form, and of OpenGL's exponential fog, on one
// fixed set of scenes, against the independent brute-force reference (tools/fog_reference).
// tools/fog_error_chart.py runs it and draws docs/images/fog_airlight_error.png with atmo-chart; the
// figures are discussed in docs/measurements/fog_airlight_error.md.
//
// Scenes: one omni light of unit intensity, extinction beta = 0.01 /m (the errors depend on T = beta D,
// gamma and D_vp / D only), albedo 1; T = beta D at 10 values log-spaced over [0.01, 20] x gamma at 21
// angles 0 .. 180 deg (0, 0.1, 0.5, 1, 2, 5, 10, 20, 30, 45, 60, 90, 120, 135, 150, 165, 170, 175, 178,
// 179.5, 180) x D_vp in {no surface, 2 D (behind the light), D / 2 (in front of it)}: 630 scenes. sin(gamma)
// is floored at min_sin = 5e-4 (what the plugin passes for 1080 rows at 60 deg), and the reference is taken
// at the floored angle (gamma = 0 is otherwise infinite).
//
// Error of a scene: |model / reference - 1|. Per configuration: median, 95th percentile (nearest rank),
// worst, and the worst per angle region (forward <= 30 deg, side 30-120, back > 120).
//
// Configurations, each at g = 0.85 (HG, the plugin's default fog) and g = 0 (isotropic, the paper's case):
//   stable  the plugin's code: host_sdk/include/atmo/atmo_fog_lights.glsl's atmo_fog_airlight through the
//           C++ twin (core/fog/fog_twin.h: float, GL_LINEAR-like fetch), table core/fog/fog_model.cpp's
//           build_airlight_table(size, g).
//   paper   Sun et al. 2005 eq. 11: La = beta e^{-T cos g} / (2 pi D sin g) [F(A1, v1) - F(A1, g/2)],
//           A1 = T sin g, v1 = pi/4 + atan2(D_vp - D cos g, D sin g) / 2 (pi/2 with no surface), in float,
//           with its own table of F(u, v) = int_0^v 4 pi p(2 xi) e^{-u tan xi} d xi (adaptive Simpson here;
//           for g = 0 the paper's F exactly, for g = 0.85 the phase folded in as in digest 001 App. D) on the
//           paper's axes: u in [0, 10], v in [0, pi/2], linear, both ends on texel centres, GL_LINEAR,
//           clamped (so u > 10 reads u = 10).
//   sizes 8, 16, 32, 64, 128, 256 (square tables); precision fp32 (GL_R32F) or fp16 (every texel rounded
//           through glm::packHalf1x16, as a GL_R16F upload stores it; filtering still in float).
// OpenGL exponential fog (GL_EXP, fog colour 0 at night):
//   airlight pixels (the 210 scenes without a surface): it has no glow, so it adds no airlight: 100 % error.
//   lit-surface pixels: the 420 scenes with a surface. A Lambertian surface of albedo 0.5 at the ray's end,
//           normal towards the light (or, where the eye would then see its back, the bisector of the
//           directions to the light and to the eye). Pixel radiance:
//             reference: e^{-beta D_vp} kd [cos_s e^{-beta D_sp} / D_sp^2 + S] + La_ref,
//                        S = fog_reference::surface_scattered_lambert (eq. 15 by quadrature)
//             OpenGL:    e^{-beta D_vp} kd cos_s / D_sp^2                (no fog on the light's path, no glow)
//             plugin:    e^{-beta D_vp} kd atmo_fog_surface_terms(...).x + atmo_fog_airlight(...)
//                        (surface table 32 x 32 as the plugin builds it, multiple scattering off, albedo 1;
//                        the airlight table at each size, fp32)
//
// Usage: atmo_fog_error_chart --csv OUT.csv [--surface-albedo 0.5]
#include <glm/glm.hpp>
#include <glm/gtc/packing.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "core/fog/fog_model.h"
#include "core/fog/fog_twin.h"
#include "fog_reference.h"

namespace {

namespace fr = atmo::fog_reference;
namespace fog = atmo::fog;
namespace tw = atmo::fog::twin;
using glm::dvec3;
using glm::vec2;
using glm::vec3;

constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kBeta = 0.01;
constexpr float kMinSin = 5.0e-4f;
constexpr double kPaperUMax = 10.0;
const int kSizes[] = {8, 16, 32, 64, 128, 256};
const double kGammasDeg[] = {0,  0.1, 0.5, 1,   2,   5,   10,  20,  30,  45,   60,
                             90, 120, 135, 150, 165, 170, 175, 178, 179.5, 180};
const double kDvpFactors[] = {kInf, 2.0, 0.5};

double deg(double d) { return d * kPi / 180.0; }

struct Scene {
  double t, gamma_deg, dvp_factor;
  double gamma;      // the floored angle, radians (the reference's and the models' angle)
  double reference;  // reference airlight
  // Lit-surface pixel (finite D_vp only).
  bool surface = false;
  double d_sp = 0, cos_s = 0;
  double surface_scattered = 0;  // reference S (per unit kd)
};

fr::Medium medium(double g) {
  fr::Medium m;
  m.extinction_per_m = kBeta;
  m.albedo = 1.0;
  m.hg_g = g;
  return m;
}

// Light at d (cos gamma, sin gamma, 0), eye at 0, ray along +x.
std::vector<Scene> make_scenes(double g) {
  std::vector<Scene> scenes;
  for (int i = 0; i < 10; ++i) {
    const double t = 0.01 * std::pow(2000.0, i / 9.0);
    for (double gd : kGammasDeg)
      for (double f : kDvpFactors) {
        Scene s;
        s.t = t;
        s.gamma_deg = gd;
        s.dvp_factor = f;
        const double gamma = deg(gd);
        s.gamma = std::atan2(std::max(std::sin(gamma), static_cast<double>(kMinSin)), std::cos(gamma));
        const double d = t / kBeta, d_vp = d * f;
        fr::Light light;
        light.position_m = d * dvec3(std::cos(s.gamma), std::sin(s.gamma), 0.0);
        s.reference = fr::single_scattering_radiance(medium(g), light, dvec3(0.0), dvec3(1, 0, 0), d_vp, 1e-8);
        if (std::isfinite(d_vp)) {
          s.surface = true;
          const dvec3 p(d_vp, 0.0, 0.0);
          const dvec3 to_light = light.position_m - p;
          s.d_sp = glm::length(to_light);
          const dvec3 l = to_light / s.d_sp, e(-1.0, 0.0, 0.0);
          // Facing the light, unless the eye would see its back: then half-way between light and eye.
          const dvec3 n = glm::dot(l, e) > 0.0 ? l : glm::normalize(l + e);
          s.cos_s = glm::dot(n, l);
          s.surface_scattered = fr::surface_scattered_lambert(medium(g), light, p, n, 1e-6);
        }
        scenes.push_back(s);
      }
  }
  return scenes;
}

// ---------------------------------------------------------------------------------------------------------
// The paper's F table, built here (not from the plugin's Ghat).

double adaptive_simpson(const std::function<double(double)>& f, double a, double b, double fa, double fm, double fb,
                        double whole, double tol, int depth) {
  const double m = 0.5 * (a + b), lm = 0.5 * (a + m), rm = 0.5 * (m + b);
  const double flm = f(lm), frm = f(rm);
  const double left = (m - a) / 6.0 * (fa + 4.0 * flm + fm), right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
  const double delta = left + right - whole;
  if (depth <= 0 || std::abs(delta) <= 15.0 * tol) return left + right + delta / 15.0;
  return adaptive_simpson(f, a, m, fa, flm, fm, left, 0.5 * tol, depth - 1) +
         adaptive_simpson(f, m, b, fm, frm, fb, right, 0.5 * tol, depth - 1);
}

double integrate(const std::function<double(double)>& f, double a, double b, double tol) {
  const double m = 0.5 * (a + b), fa = f(a), fm = f(m), fb = f(b);
  return adaptive_simpson(f, a, b, fa, fm, fb, (b - a) / 6.0 * (fa + 4.0 * fm + fb), tol, 50);
}

// F(u, v) = int_0^v 4 pi p(2 xi) exp(-u tan xi) d xi with the reference's HG phase.
double paper_f(double u, double v, double g, int pieces = 64) {
  auto integrand = [&](double xi) {
    const double e = xi >= 0.5 * kPi ? (u > 0.0 ? 0.0 : 1.0) : std::exp(-u * std::tan(xi));
    return 4.0 * kPi * fr::henyey_greenstein(std::cos(2.0 * xi), g) * e;
  };
  double sum = 0.0;
  for (int k = 0; k < pieces; ++k) sum += integrate(integrand, v * k / pieces, v * (k + 1) / pieces, 1e-13);
  return sum;
}

// Texel (i, j) holds F(u_i, v_j), u_i = 10 i / (n - 1), v_j = (pi/2) j / (n - 1): the twin's fetch and
// atmo_fog_grid then do GL_LINEAR on exactly those sample positions.
fog::FogTable build_paper_table(int n, double g) {
  fog::FogTable t;
  t.width = t.height = n;
  t.texels.resize(static_cast<size_t>(n) * n);
  for (int i = 0; i < n; ++i) {
    const double u = kPaperUMax * i / (n - 1);
    double acc = 0.0;
    t.texels[static_cast<size_t>(i)] = 0.0f;
    for (int j = 1; j < n; ++j) {
      const double v0 = 0.5 * kPi * (j - 1) / (n - 1), v1 = 0.5 * kPi * j / (n - 1);
      auto integrand = [&](double xi) {
        const double e = xi >= 0.5 * kPi ? (u > 0.0 ? 0.0 : 1.0) : std::exp(-u * std::tan(xi));
        return 4.0 * kPi * fr::henyey_greenstein(std::cos(2.0 * xi), g) * e;
      };
      const int pieces = std::max(1, 256 / n);
      for (int k = 0; k < pieces; ++k)
        acc += integrate(integrand, v0 + (v1 - v0) * k / pieces, v0 + (v1 - v0) * (k + 1) / pieces, 1e-14);
      t.texels[static_cast<size_t>(j) * n + i] = static_cast<float>(acc);
    }
  }
  return t;
}

void to_half(fog::FogTable& t) {
  for (float& x : t.texels) x = glm::unpackHalf1x16(glm::packHalf1x16(x));
}

float paper_airlight(const fog::FogTable& t, double d_d, double gamma, double d_vp_d) {
  const float beta = static_cast<float>(kBeta), d = static_cast<float>(d_d), n = static_cast<float>(t.width);
  const float pi = static_cast<float>(kPi);
  const float cg = static_cast<float>(std::cos(gamma));
  const float sg = std::max(std::sqrt(std::max(1.0f - cg * cg, 0.0f)), kMinSin);
  const float gam = std::atan2(sg, cg);
  const float tsv = beta * d;
  const float a0 = beta * std::exp(-tsv * cg) / (2.0f * pi * d * sg);
  const float a1 = tsv * sg;
  const float v1 = std::isfinite(d_vp_d) ? 0.25f * pi + 0.5f * std::atan2(static_cast<float>(d_vp_d) - d * cg, d * sg)
                                         : 0.5f * pi;
  const float x = a1 / static_cast<float>(kPaperUMax);
  auto f = [&](float v) {
    return tw::atmo_fog_table_fetch(t, vec2(tw::atmo_fog_grid(x, n), tw::atmo_fog_grid(v / (0.5f * pi), n)));
  };
  return a0 * std::max(f(v1) - f(0.5f * gam), 0.0f);
}

float stable_airlight(const fog::FogTable& t, double d, double gamma, double d_vp) {
  return tw::atmo_fog_airlight(t, static_cast<float>(t.width), static_cast<float>(kBeta), static_cast<float>(d),
                               static_cast<float>(std::cos(gamma)),
                               std::isfinite(d_vp) ? static_cast<float>(d_vp) : tw::ATMO_FOG_FAR, kMinSin);
}

// ---------------------------------------------------------------------------------------------------------
// Statistics and output.

struct Row {
  std::string form, precision;
  double g;
  int size;
  int scenes;
  double median, p95, worst, worst_fwd, worst_side, worst_back;
  std::string worst_at;
};

Row stats(const std::string& form, const std::string& precision, double g, int size, const std::vector<Scene>& scenes,
          const std::vector<double>& errors) {
  Row r{form, precision, g, size, static_cast<int>(errors.size()), 0, 0, 0, 0, 0, 0, ""};
  std::vector<double> sorted = errors;
  std::sort(sorted.begin(), sorted.end());
  const size_t n = sorted.size();
  r.median = n % 2 ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
  r.p95 = sorted[static_cast<size_t>(std::ceil(0.95 * n)) - 1];
  r.worst = sorted.back();
  for (size_t i = 0; i < n; ++i) {
    const Scene& s = scenes[i];
    const double e = errors[i];
    double& region = s.gamma_deg <= 30 ? r.worst_fwd : (s.gamma_deg <= 120 ? r.worst_side : r.worst_back);
    region = std::max(region, e);
    if (e == r.worst && r.worst_at.empty()) {
      char buf[80];
      std::snprintf(buf, sizeof buf, "T %.3g gamma %g Dvp/D %g", s.t, s.gamma_deg, s.dvp_factor);
      r.worst_at = buf;
    }
  }
  return r;
}

double rel(double model, double reference) {
  const double e = std::abs(model / reference - 1.0);
  return std::isfinite(e) ? e : 1e30;  // a NaN or inf model value: "off every scale"
}

}  // namespace

int main(int argc, char** argv) {
  std::string csv_path;
  double surface_albedo = 0.5;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--csv") && i + 1 < argc) {
      csv_path = argv[++i];
    } else if (!std::strcmp(argv[i], "--surface-albedo") && i + 1 < argc) {
      surface_albedo = std::atof(argv[++i]);
    } else {
      std::fprintf(stderr, "usage: %s --csv OUT.csv [--surface-albedo 0.5]\n", argv[0]);
      return 2;
    }
  }
  if (csv_path.empty()) {
    std::fprintf(stderr, "usage: %s --csv OUT.csv [--surface-albedo 0.5]\n", argv[0]);
    return 2;
  }
  const auto start = std::chrono::steady_clock::now();
  // Self-check of the paper's F against the digest's golden values (isotropic).
  {
    const double golden[][3] = {{0.1, kPi / 2, 1.2910047283}, {1, kPi / 2, 0.6214496242}, {10, kPi / 2, 0.0981910350},
                                {1, 1.2, 0.6150868050},       {3, 1.2, 0.2919415871},     {0.5, 0.3, 0.2782776998},
                                {5, 0.8, 0.1876710613}};
    double worst = 0;
    for (const auto& c : golden) worst = std::max(worst, std::abs(paper_f(c[0], c[1], 0.0) / c[2] - 1.0));
    std::printf("paper F vs digest 001 golden values: worst relative error %.1e\n", worst);
    if (worst > 1e-8) return 1;
  }
  const float kd = static_cast<float>(surface_albedo / kPi);
  std::vector<Row> rows;
  for (double g : {0.85, 0.0}) {
    const std::vector<Scene> scenes = make_scenes(g);
    std::printf("g = %.2f: %zu scenes, reference done at %.1f s\n", g, scenes.size(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    std::vector<fog::FogTable> stable_fp32;
    std::vector<Row> fp32_rows, fp16_rows;
    for (int size : kSizes) {
      const auto t0 = std::chrono::steady_clock::now();
      stable_fp32.push_back(fog::build_airlight_table(size, g));
      const fog::FogTable paper_fp32 = build_paper_table(size, g);
      for (const std::string precision : {"fp32", "fp16"}) {
        fog::FogTable stable = stable_fp32.back(), paper = paper_fp32;
        if (precision == "fp16") {
          to_half(stable);
          to_half(paper);
        }
        std::vector<double> e_stable, e_paper;
        for (const Scene& s : scenes) {
          const double d = s.t / kBeta, d_vp = d * s.dvp_factor;
          e_stable.push_back(rel(stable_airlight(stable, d, deg(s.gamma_deg), d_vp), s.reference));
          e_paper.push_back(rel(paper_airlight(paper, d, deg(s.gamma_deg), d_vp), s.reference));
        }
        std::vector<Row>& dst = precision == "fp32" ? fp32_rows : fp16_rows;
        dst.push_back(stats("stable form (plugin)", precision, g, size, scenes, e_stable));
        dst.push_back(stats("paper F form", precision, g, size, scenes, e_paper));
      }
      std::printf("  size %d: tables and errors in %.1f s\n", size,
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    rows.insert(rows.end(), fp32_rows.begin(), fp32_rows.end());
    rows.insert(rows.end(), fp16_rows.begin(), fp16_rows.end());
    // OpenGL exponential fog and the whole lit-surface pixel.
    std::vector<Scene> lit;
    for (const Scene& s : scenes)
      if (s.surface) lit.push_back(s);
    std::vector<Scene> sky;  // no surface on the ray: pure airlight pixels
    for (const Scene& s : scenes)
      if (!s.surface) sky.push_back(s);
    std::vector<double> e_gl_air(sky.size(), 1.0), e_gl_lit;  // OpenGL fog adds no airlight: 100 %
    std::vector<double> ref_pixel;
    for (const Scene& s : lit) {
      const double d = s.t / kBeta, d_vp = d * s.dvp_factor;
      const double att = std::exp(-kBeta * d_vp);
      const double surface = kd * (s.cos_s * std::exp(-kBeta * s.d_sp) / (s.d_sp * s.d_sp) + s.surface_scattered);
      ref_pixel.push_back(att * surface + s.reference);
      const double gl = att * kd * s.cos_s / (s.d_sp * s.d_sp);
      e_gl_lit.push_back(rel(gl, ref_pixel.back()));
    }
    rows.push_back(stats("OpenGL exp fog: airlight pixels", "-", g, 0, sky, e_gl_air));
    rows.push_back(stats("OpenGL exp fog: lit-surface pixels", "-", g, 0, lit, e_gl_lit));
    const fog::FogTable surface_table = fog::build_surface_table(32, 32, g);
    for (size_t k = 0; k < stable_fp32.size(); ++k) {
      const fog::FogTable& stable = stable_fp32[k];
      const int size = kSizes[k];
      std::vector<double> e_plugin;
      for (size_t i = 0; i < lit.size(); ++i) {
        const Scene& s = lit[i];
        const double d = s.t / kBeta, d_vp = d * s.dvp_factor;
        const glm::vec2 terms = tw::atmo_fog_surface_terms(
            surface_table, vec2(32.0f, 32.0f), static_cast<float>(kBeta), 1.0f, glm::vec4(0.0f),
            static_cast<float>(s.d_sp), static_cast<float>(kBeta * s.d_sp), static_cast<float>(s.cos_s),
            static_cast<float>(s.cos_s), 1.0f);
        const float pixel = std::exp(-static_cast<float>(kBeta * d_vp)) * kd * terms.x +
                            stable_airlight(stable, d, deg(s.gamma_deg), d_vp);
        e_plugin.push_back(rel(pixel, ref_pixel[i]));
      }
      rows.push_back(stats("plugin: lit-surface pixels", "fp32", g, size, lit, e_plugin));
    }
  }

  std::ofstream out(csv_path);
  if (!out) {
    std::fprintf(stderr, "cannot write %s\n", csv_path.c_str());
    return 2;
  }
  out << "# atmo_fog_error_chart (bench/fog_error_chart.cpp): relative error |model / reference - 1| (percent) "
         "against tools/fog_reference's quadrature on 630 scenes (T = beta D 0.01..20 log x 21 angles 0..180 deg x "
         "D_vp none / 2 D / D/2; min_sin 5e-4); lit-surface pixels: the 420 scenes with a surface, Lambertian, "
         "albedo " << surface_albedo << "; size 0: does not depend on a table\n";
  out << "form,precision,g,size,scenes,median_pct,p95_pct,worst_pct,worst_forward_pct,worst_side_pct,worst_back_pct,"
         "worst_at\n";
  std::printf("%-36s %-5s %-5s %5s %11s %11s %11s %11s %11s %11s  %s\n", "form", "prec", "g", "size", "median %",
              "p95 %", "worst %", "fwd<=30 %", "side %", "back>120 %", "worst at");
  for (const Row& r : rows) {
    char line[512];
    std::snprintf(line, sizeof line, "%s,%s,%.2f,%d,%d,%.4g,%.4g,%.4g,%.4g,%.4g,%.4g,%s\n", r.form.c_str(),
                  r.precision.c_str(), r.g, r.size, r.scenes, 100 * r.median, 100 * r.p95, 100 * r.worst,
                  100 * r.worst_fwd, 100 * r.worst_side, 100 * r.worst_back, r.worst_at.c_str());
    out << line;
    std::printf("%-36s %-5s %-5.2f %5d %11.4g %11.4g %11.4g %11.4g %11.4g %11.4g  %s\n", r.form.c_str(),
                r.precision.c_str(), r.g, r.size, 100 * r.median, 100 * r.p95, 100 * r.worst, 100 * r.worst_fwd,
                100 * r.worst_side, 100 * r.worst_back, r.worst_at.c_str());
  }
  std::printf("done in %.1f s; wrote %s\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), csv_path.c_str());
  return 0;
}
