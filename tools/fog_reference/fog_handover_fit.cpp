// fog_handover_fit — measures the plugin's multiple-scattering model of fog lit by a point light against
// the all-orders Monte Carlo reference (tools/fog_reference), and fits the handover of the diffusion term
// (atmo_fog_diffusion_light, host_sdk/include/atmo/atmo_fog_lights.glsl; kHandoverRate in
// plugin/core/fog/fog_model.h). docs/measurements/fog_multiple_scattering.md has the results.
//
// Scene: an omnidirectional light of 1 cd, the eye at distance D from it, an unbounded homogeneous fog of
// extinction beta (HG g = 0.85 by default), no surface on the view ray (d_vp = inf). For each optical
// thickness T = beta D and view angle gamma (between the view direction and the direction to the light):
//   mc     the Monte Carlo radiance with all orders (monte_carlo_radiance), with its standard error;
//   ss     the exact single scattering (single_scattering_radiance, adaptive quadrature);
//   model  what the plugin draws: the glow pass's airlight (the twin's atmo_fog_airlight on the plugin's
//          64^2 table, times albedo) + the fog pass's diffusion radiance: the diffusion field at the EYE
//          (the twin's atmo_fog_diffusion_light, as make_fog_frame sums it) seen through the whole
//          visible depth, (1 - e^{-beta L}) max((fluence + 3 flux . dir) / 4 pi, 0), L = inf here.
// The fit: the handover rate (the diffusion vector's z) that minimises the RMS of ln(model / mc) over the grid
// (optionally only T >= --fit-min-t), the model evaluated through the twin whatever the GLSL's handover form.
//
// Usage: fog_handover_fit [--albedo A] [--g G] [--target-rel R] [--max-seconds S] [--threads N]
//                         [--thickness 0.25,0.5,...] [--angles 2,10,...] [--csv out.csv] [--raw in.csv]
//                         [--fit-min-t T] [--seed S]
//   --raw reads a CSV this program wrote (the MC columns) instead of running the Monte Carlo again.
//   --surface: instead, the irradiance on a small surface facing the light at distance D (the kd part of
//   atmo_fog_surface_terms, cos_s = 1) against direct + exact single scattering (surface_scattered_lambert)
//   + the Monte Carlo's multiple part integrated over the hemisphere, 2 pi int L_mult cos sin d theta
//   (8-point Gauss-Legendre in theta; the radiance is symmetric about the light direction).
// The runs behind docs/measurements/fog_multiple_scattering.*: --albedo 0.99 --max-seconds 25 --target-rel 0.04;
// --albedo 0.999 --thickness 0.5,1,2,4,8 --max-seconds 15 --target-rel 0.05; each with --csv, then --raw on
// those files (the model recomputed); --surface --thickness 1,2,4,8 --max-seconds 8 --target-rel 0.05. The
// Monte Carlo stops on time as well as on precision, so a rerun draws other batches.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "atmo_support/cli.h"
#include "core/fog/fog_model.h"
#include "core/fog/fog_twin.h"
#include "fog_reference.h"

namespace fr = atmo::fog_reference;
namespace fog = atmo::fog;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kBeta = 0.01;  // 1/m

struct Point {
  double thickness = 0, gamma_deg = 0, albedo = 0;
  double mc = 0, mc_se = 0, mc_single = 0, mc_multiple = 0, mc_multiple_se = 0;
  uint64_t paths = 0;
  double seconds = 0, truncated = 0, vertices = 0;
  double ss = 0;         // exact single scattering (quadrature)
  double ss_model = 0;   // the glow pass's airlight (table), times albedo
  double diffusion_full = 0;  // the fog pass's diffusion radiance with the handover = 1 (rate = inf)
};

// The fog pass's diffusion radiance at the eye for a view at gamma to the light, with the handover rate
// `rate` (the diffusion vector's z), from the twin (the GLSL text fog_medium.frag runs).
double diffusion_radiance(const fog::FogOptics& o, double distance, double gamma, float rate) {
  const glm::vec4 diffusion(static_cast<float>(o.transport_per_m()), static_cast<float>(o.diffusion_decay_per_m(INFINITY)),
                            rate, 1.0e30f);
  return fog::twin::atmo_fog_pass_one_light(diffusion, static_cast<float>(o.extinction_per_m),
                                            static_cast<float>(distance), static_cast<float>(std::cos(gamma)));
}

// The plugin's model at handover rate `rate`: the airlight + the diffusion radiance, both from the twin.
double model_at(const fog::FogOptics& o, const Point& p, double rate) {
  return p.ss_model + diffusion_radiance(o, p.thickness / kBeta, p.gamma_deg * kPi / 180.0, static_cast<float>(rate));
}

struct FitStats {
  double rms_log = 0;
  double worst_abs_log = 0;
};

FitStats fit_stats(const fog::FogOptics& o, const std::vector<Point>& pts, double rate, double min_t) {
  FitStats s;
  int n = 0;
  for (const Point& p : pts) {
    if (p.thickness < min_t || !(p.mc > 0)) continue;
    const double e = std::log(model_at(o, p, rate) / p.mc);
    s.rms_log += e * e;
    s.worst_abs_log = std::max(s.worst_abs_log, std::abs(e));
    ++n;
  }
  s.rms_log = n ? std::sqrt(s.rms_log / n) : 0;
  return s;
}

// Minimum of f on [a, b]: a scan of 250 steps (f need not be unimodal: the clamp of the P1 radiance at 0
// makes kinks), then golden section around the best step.
template <class F>
double minimise(F&& f, double a, double b) {
  const int steps = 250;
  int best = 0;
  double fbest = f(a);
  for (int i = 1; i <= steps; ++i) {
    const double v = f(a + (b - a) * i / steps);
    if (v < fbest) { fbest = v; best = i; }
  }
  const double h = (b - a) / steps;
  double lo = std::max(a, a + h * (best - 1)), hi = std::min(b, a + h * (best + 1));
  const double r = 0.5 * (std::sqrt(5.0) - 1.0);
  double c = hi - r * (hi - lo), d = lo + r * (hi - lo);
  double fc = f(c), fd = f(d);
  for (int i = 0; i < 60; ++i) {
    if (fc < fd) {
      hi = d; d = c; fd = fc; c = hi - r * (hi - lo); fc = f(c);
    } else {
      lo = c; c = d; fc = fd; d = lo + r * (hi - lo); fd = f(d);
    }
  }
  const double x = 0.5 * (lo + hi);
  return f(x) <= fbest ? x : a + h * best;
}

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

void band_table(const fog::FogOptics& o, const std::vector<Point>& pts, double rate) {
  struct Band { const char* name; double lo, hi; };
  const Band bands[] = {{"thin   T<=1  ", 0, 1}, {"medium 1<T<=4", 1, 4}, {"thick  T>4   ", 4, 1e9}};
  std::printf("\nrelative error vs MC total (model: handover rate %.4f)\n", rate);
  std::printf("band           n  | SS alone: median   worst  | SS+diffusion: median   worst | MC se: median  worst\n");
  for (const Band& b : bands) {
    std::vector<double> ess, em, ese;
    double wss = 0, wm = 0;
    for (const Point& p : pts) {
      if (!(p.thickness > b.lo && p.thickness <= b.hi)) continue;
      const double es = p.ss / p.mc - 1.0, e2 = model_at(o, p, rate) / p.mc - 1.0;
      ess.push_back(es);
      em.push_back(e2);
      ese.push_back(p.mc_se / p.mc);
      if (std::abs(es) > std::abs(wss)) wss = es;
      if (std::abs(e2) > std::abs(wm)) wm = e2;
    }
    if (ess.empty()) continue;
    std::printf("%s %3zu  |        %+7.3f  %+7.3f  |            %+7.3f  %+7.3f |     %6.3f  %6.3f\n", b.name, ess.size(),
                median(ess), wss, median(em), wm, median(ese), *std::max_element(ese.begin(), ese.end()));
  }
}

// Irradiance on a small surface facing the light (see the usage notes): prints model vs reference per T.
int surface_check(const fog::FogOptics& optics, const fr::Medium& medium, const std::vector<double>& thicknesses,
                  double max_seconds, double target_rel, int threads, uint64_t seed) {
  static const double x[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267, 0.9602898564975363};
  static const double w[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};
  const fog::FogTable table = fog::build_surface_table(32, 32, optics.phase_g);  // as make_fog_context
  const glm::vec2 size(32.0f, 32.0f);
  const fr::Light light;
  const double beta = optics.extinction_per_m;
  std::printf("T      E_direct    E_ss_ref    E_ss_model  E_mult_mc (se)          E_diff_model  "
              "total_ref   total_model  model/ref  (model-direct)/(ref-direct)\n");
  for (double T : thicknesses) {
    const double D = T / beta;
    const glm::dvec3 point(D, 0, 0), normal(-1, 0, 0);
    const double direct = std::exp(-T) / (D * D);
    const double ss_ref = fr::surface_scattered_lambert(medium, light, point, normal, 1e-5);
    double mult = 0, var = 0;
    for (int k = 0; k < 8; ++k) {
      const double xi = k < 4 ? -x[3 - k] : x[k - 4], wi = k < 4 ? w[3 - k] : w[k - 4];
      const double theta = 0.25 * kPi * (1.0 + xi), weight = 0.25 * kPi * wi * 2.0 * kPi * std::cos(theta) * std::sin(theta);
      const glm::dvec3 dir(-std::cos(theta), std::sin(theta), 0);
      double sum = 0, v = 0;
      uint64_t n = 0, batch = 0;
      const auto t0 = std::chrono::steady_clock::now();
      for (;;) {
        const uint64_t paths = 8192;
        const fr::MonteCarloResult r = fr::monte_carlo_radiance(medium, light, point, dir, INFINITY, paths,
                                                                seed + 31337ull * k + 104729ull * batch++ +
                                                                    1000003ull * static_cast<uint64_t>(T * 1000),
                                                                2000, threads);
        sum += paths * r.multiple;
        v += static_cast<double>(paths) * paths * r.multiple_std_error * r.multiple_std_error;
        n += paths;
        const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if ((n >= 16384 && std::sqrt(v) / n <= target_rel * sum / n) || sec > max_seconds) break;
      }
      mult += weight * sum / n;
      var += weight * weight * v / (static_cast<double>(n) * n);
    }
    const glm::vec4 diffusion(static_cast<float>(optics.transport_per_m()),
                              static_cast<float>(optics.diffusion_decay_per_m(INFINITY)),
                              static_cast<float>(fog::kHandoverRate), 1.0e30f);
    const glm::vec4 no_diffusion(diffusion.x, diffusion.y, diffusion.z, 0.0f);
    const float fb = static_cast<float>(beta), fd = static_cast<float>(D), ft = static_cast<float>(T);
    const float albedo = static_cast<float>(optics.albedo);
    const double model = fog::twin::atmo_fog_surface_terms(table, size, fb, albedo, diffusion, fd, ft, 1.0f, 1.0f, 1.0f).x;
    const double model_no = fog::twin::atmo_fog_surface_terms(table, size, fb, albedo, no_diffusion, fd, ft, 1.0f, 1.0f, 1.0f).x;
    const double ref = direct + ss_ref + mult;
    std::printf("%-6g %.4e  %.4e  %.4e  %.4e (%.3f)  %.4e    %.4e  %.4e  %7.3f    %7.3f\n", T, direct, ss_ref,
                model_no - direct, mult, std::sqrt(var) / mult, model - model_no, ref, model, model / ref,
                (model - direct) / (ref - direct));
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  double albedo = 0.99, g = 0.85, target_rel = 0.04, max_seconds = 60, fit_min_t = 0;
  int threads = 2;
  uint64_t seed = 20240601;
  std::vector<double> thicknesses = {0.25, 0.5, 1, 2, 4, 8, 16};
  std::vector<double> angles = {2, 10, 30, 60, 90, 150};
  std::string csv_path, raw_path;
  bool surface = false;
  CLI::App app{"fog_handover_fit: the plugin's fog multiple scattering against the Monte Carlo, and the fit of "
               "its handover (docs/measurements/fog_multiple_scattering.md)"};
  app.add_option("--albedo", albedo, "Single-scattering albedo")->check(CLI::Range(0.0, 1.0));
  app.add_option("--g", g, "Henyey-Greenstein asymmetry")->check(CLI::Range(-0.99, 0.99));
  app.add_option("--target-rel", target_rel, "Monte Carlo: stop at this relative standard error")
      ->check(CLI::Range(1.0e-4, 1.0));
  app.add_option("--max-seconds", max_seconds, "Monte Carlo: time per case, s")->check(CLI::Range(0.1, 86400.0));
  app.add_option("--threads", threads, "Monte Carlo threads")->check(CLI::Range(1, 256));
  app.add_option("--thickness", thicknesses, "Optical thicknesses T = beta D, comma-separated")
      ->delimiter(',')
      ->check(CLI::Range(1.0e-3, 100.0));
  app.add_option("--angles", angles, "View angles to the light, degrees, comma-separated")
      ->delimiter(',')
      ->check(CLI::Range(0.0, 180.0));
  app.add_option("--csv", csv_path, "Write the points as CSV");
  app.add_option("--raw", raw_path, "Read the Monte Carlo columns from a CSV this program wrote")
      ->check(CLI::ExistingFile);
  app.add_option("--fit-min-t", fit_min_t, "Fit only T >= this")->check(CLI::Range(0.0, 100.0));
  app.add_option("--seed", seed, "Monte Carlo seed");
  app.add_flag("--surface", surface, "The surface irradiance check instead");
  if (const auto exit_code = atmo::support::parse_command_line(app, argc, argv)) return *exit_code;

  fog::FogOptics optics;
  optics.extinction_per_m = kBeta;
  optics.albedo = albedo;
  optics.phase_g = g;
  const fog::FogTable table = fog::build_airlight_table(64, g);  // the plugin's default size
  fr::Medium medium;
  medium.extinction_per_m = kBeta;
  medium.albedo = albedo;
  medium.hg_g = g;
  fr::Light light;  // at the origin, 1 cd, omnidirectional

  if (surface) return surface_check(optics, medium, thicknesses, max_seconds, target_rel, threads, seed);

  std::vector<Point> pts;
  if (!raw_path.empty()) {
    std::ifstream in(raw_path);
    std::string line;
    std::getline(in, line);  // header
    while (std::getline(in, line)) {
      Point p;
      unsigned long long paths = 0;
      if (std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%llu", &p.thickness, &p.gamma_deg, &p.albedo, &p.mc,
                      &p.mc_se, &p.mc_single, &p.mc_multiple, &p.mc_multiple_se, &paths) < 9)
        continue;
      p.paths = paths;
      if (std::abs(p.albedo - albedo) > 1e-9) continue;
      pts.push_back(p);
    }
  } else {
    for (double T : thicknesses)
      for (double a : angles) pts.push_back(Point{T, a, albedo});
  }

  // Exact SS and the model's parts (recomputed for raw input too: they are cheap).
  for (Point& p : pts) {
    const double D = p.thickness / kBeta, gamma = p.gamma_deg * kPi / 180.0;
    const glm::dvec3 eye(D, 0, 0), dir(-std::cos(gamma), std::sin(gamma), 0);  // the light at the origin
    p.ss = fr::single_scattering_radiance(medium, light, eye, dir, INFINITY, 1e-8);
    p.ss_model = albedo * fog::twin::atmo_fog_airlight(table, 64.0f, static_cast<float>(kBeta), static_cast<float>(D),
                                                       static_cast<float>(std::cos(gamma)), fog::kNoTop, 0.0f);
    p.diffusion_full = diffusion_radiance(optics, D, gamma, 1.0e30f);
  }

  if (raw_path.empty()) {
    std::printf("T      gamma   paths     sec   mc_total    se/mc  mc_single/ss  mult/ss  ss/mc  model/mc  needed_x  vertices truncated\n");
    for (Point& p : pts) {
      const double D = p.thickness / kBeta, gamma = p.gamma_deg * kPi / 180.0;
      const glm::dvec3 eye(D, 0, 0), dir(-std::cos(gamma), std::sin(gamma), 0);
      // Batches of 8192 paths (each its own seed) until the target standard error or the time budget.
      const auto t0 = std::chrono::steady_clock::now();
      double sum_t = 0, var_t = 0, sum_s = 0, sum_m = 0, var_m = 0;
      uint64_t n = 0, batch = 0;
      for (;;) {
        const uint64_t paths = 8192;
        const uint64_t s = seed + 1000003ull * static_cast<uint64_t>(p.thickness * 1000) +
                           7919ull * static_cast<uint64_t>(p.gamma_deg * 10) + 104729ull * batch++;
        const fr::MonteCarloResult r = fr::monte_carlo_radiance(medium, light, eye, dir, INFINITY, paths, s, 2000, threads);
        const double w = static_cast<double>(paths);
        sum_t += w * r.total;
        var_t += w * w * r.total_std_error * r.total_std_error;
        sum_s += w * r.single;
        sum_m += w * r.multiple;
        var_m += w * w * r.multiple_std_error * r.multiple_std_error;
        n += paths;
        p.truncated += w * r.truncated_weight;
        p.vertices += w * r.mean_vertices;
        const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const double mean = sum_t / n, se = std::sqrt(var_t) / n;
        if ((n >= 16384 && se <= target_rel * mean) || sec > max_seconds) break;
      }
      p.paths = n;
      p.truncated /= n;
      p.vertices /= n;
      p.mc = sum_t / n;
      p.mc_se = std::sqrt(var_t) / n;
      p.mc_single = sum_s / n;
      p.mc_multiple = sum_m / n;
      p.mc_multiple_se = std::sqrt(var_m) / n;
      p.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const double current = model_at(optics, p, fog::kHandoverRate);
      std::printf("%-6g %5g %8llu %7.1f  %.4e  %6.3f  %8.3f  %8.3f  %6.3f  %7.3f  %7.3f  %7.1f  %.2e\n", p.thickness,
                  p.gamma_deg, static_cast<unsigned long long>(p.paths), p.seconds, p.mc, p.mc_se / p.mc,
                  p.mc_single / p.ss, p.mc_multiple / p.ss, p.ss / p.mc, current / p.mc,
                  (p.mc - p.ss_model) / p.diffusion_full, p.vertices, p.truncated);
      std::fflush(stdout);
    }
  } else {
    std::printf("T      gamma   mc_total    se/mc  ss/mc  ss_model/ss  needed_x (mc - ss_model) / diffusion at handover 1\n");
    for (const Point& p : pts)
      std::printf("%-6g %5g  %.4e  %6.3f  %6.3f  %8.4f  %7.3f\n", p.thickness, p.gamma_deg, p.mc, p.mc_se / p.mc,
                  p.ss / p.mc, p.ss_model / p.ss, (p.mc - p.ss_model) / p.diffusion_full);
  }

  // The fit: the rate (the diffusion vector's z) by golden section on the RMS of ln(model / mc), the model
  // evaluated by the twin (whatever the GLSL's handover form is).
  const double rate = minimise([&](double r) { return fit_stats(optics, pts, r, fit_min_t).rms_log; }, 0.0, 5.0);
  std::printf("\nper-thickness best rate (RMS ln(model/mc) over the angles) vs the fitted and the current rate:\n");
  std::vector<double> ts;
  for (const Point& p : pts)
    if (std::find(ts.begin(), ts.end(), p.thickness) == ts.end()) ts.push_back(p.thickness);
  for (double T : ts) {
    std::vector<Point> sub;
    for (const Point& p : pts)
      if (p.thickness == T) sub.push_back(p);
    auto f = [&](double r) { return fit_stats(optics, sub, r, 0).rms_log; };
    const double best = minimise(f, 0.0, 5.0);
    std::printf("  T %-5g best rate %.3f (rms %.3f); fitted %.3f: rms %.3f; current %.3f: rms %.3f; none: rms %.3f\n", T,
                best, f(best), rate, f(rate), fog::kHandoverRate, f(fog::kHandoverRate), f(0.0));
  }
  const FitStats fitted = fit_stats(optics, pts, rate, fit_min_t);
  const FitStats now = fit_stats(optics, pts, fog::kHandoverRate, fit_min_t);
  const FitStats none = fit_stats(optics, pts, 0.0, fit_min_t);
  std::printf("\nfitted rate %.4f: RMS ln(model/mc) %.4f, worst |ln| %.4f (fit over T >= %g)\n", rate, fitted.rms_log,
              fitted.worst_abs_log, fit_min_t);
  std::printf("current kHandoverRate %.4f: RMS %.4f, worst %.4f;  no diffusion: RMS %.4f, worst %.4f\n",
              fog::kHandoverRate, now.rms_log, now.worst_abs_log, none.rms_log, none.worst_abs_log);
  band_table(optics, pts, fog::kHandoverRate);
  band_table(optics, pts, rate);

  if (!csv_path.empty()) {
    std::ofstream out(csv_path);
    out << "T,gamma_deg,albedo,mc_total,mc_std_error,mc_single,mc_multiple,mc_multiple_std_error,paths,ss,ss_model,"
           "diffusion_unscaled,model,ss_rel_error,model_rel_error\n";
    char buf[512];
    for (const Point& p : pts) {
      const double model = model_at(optics, p, fog::kHandoverRate);
      std::snprintf(buf, sizeof buf, "%g,%g,%g,%.6e,%.3e,%.6e,%.6e,%.3e,%llu,%.6e,%.6e,%.6e,%.6e,%.4f,%.4f\n",
                    p.thickness, p.gamma_deg, p.albedo, p.mc, p.mc_se, p.mc_single, p.mc_multiple, p.mc_multiple_se,
                    static_cast<unsigned long long>(p.paths), p.ss, p.ss_model, p.diffusion_full, model,
                    p.ss / p.mc - 1.0, model / p.mc - 1.0);
      out << buf;
    }
  }
  return 0;
}
