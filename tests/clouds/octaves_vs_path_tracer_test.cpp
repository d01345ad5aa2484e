// The real-time lighting approximation (cloud_march.glsl's twin: a few
// octaves of forward scattering, a diffusion term for the deep light, an
// ambient term split between sky and ground, shaders/clouds/cloud_functions.glsl)
// against the Monte Carlo path tracer (all orders, tools/cloud_reference) on
// the same clouds: mean relative luminance error over the cloud's pixels, its
// bias, and the errors of the light's and the ambient's parts, per view.
//
// The references are STORED (path_traced_references.inc, written by
// DISABLED_RegenerateReferences from the path tracer, ~1 h on 2 cores,
// bit-identical on rerun): 500 000 paths per pixel (300 000 for the decks) in
// two independent halves. Fewer will not do: with the droplets' diffraction
// peak (2738 /sr) and the Sun a delta light, the next-event estimate is
// heavy-tailed. On the blob's centre pixel a third of the mean comes from 1
// path in 10^4 and 7 % from 1 in 2.5x10^5, so an image of ~100 paths per pixel
// (this test's until now) is typically 20-40 % darker than the converged
// radiance, and a model tuned to it comes out too dark. The stored halves
// differ by 1-5 % per pixel (printed as "reference noise": the mean over the
// pixels of |a - b| / (a + b)); the decks' neighbouring pixels scatter more
// (up to ~10 %), so read their figures as +-3 points.
// StoredReferencesMatchThePathTracer keeps the references honest.
//
// Views. Development (the defaults in core/clouds/cloud_optics.cpp were
// fitted on all of them, DISABLED_FitDefaults): the 600 m blob (peak optical
// depth ~20) from four sides, procedural cumulus prototypes under four suns
// and eyes, a thin cumulus (optical depth <= 2), and a homogeneous deck of
// optical thickness 20 seen from below and from above. Held out (never
// fitted, compared once): two more cumulus prototypes, a procedural stratus
// tile with holes (tau <= 7) from below and a denser one (tau <= 18) from
// above, and a thin cumulus (tau <= 5) against the Sun. Measured (any build:
// the figures are deterministic): development mean 12.1 %, held-out mean
// 14.6 % (docs/CLOUDS.md has the table; the model before the diffusion term
// scored 57.5 % and 53.5 %). The 15 % target holds on average, not on every
// view: a side-lit wide cumulus (19.5-19.8 %) and the backlit thin cumulus
// (26.9 %) stay above it. The limits are the measured figures plus ~2 points
// per view: they catch a regression of the model.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "cloud_path_tracer.h"
#include "reference_clouds.h"
#include "core/clouds/cloud_lighting.h"
#include "core/clouds/cloud_optics.h"
#include "core/clouds/procedural_clouds.h"

namespace {

using namespace atmo::clouds;

// ---------------------------------------------------------------------------
// The clouds and the views (their stored references depend on every number
// here: change one and regenerate).

using reference::blob_cloud;  // reference_clouds.h

// Prototype `index` of a procedural cumulus layer (seed 7, 1000-1800 m,
// voxels <= 30 m), at the origin, with extinction `extinction_per_m`.
CloudVolume cumulus_prototype(int index, float extinction_per_m) {
  CloudLayerSpec s;
  s.type = CloudLayerType::Cumulus;
  s.coverage_oktas = 3;
  s.base_m = 1000;
  s.top_m = 1800;
  s.area_size_m = 10000;
  s.seed = 7;
  s.max_voxel_size_m = 30;
  CloudVolume c = generate_cloud_layer(s).field.prototypes.at(static_cast<size_t>(index));
  c.origin_enu_m = glm::dvec3(0.0, 0.0, 1000.0);
  c.optics.extinction_per_m = extinction_per_m;
  return c;
}

// A homogeneous deck: 40 x 40 columns of 40 m, 8 voxels thick (one empty voxel
// above and below), vertical optical depth `tau`.
CloudVolume deck(double tau) {
  CloudVolume c;
  c.name = "deck";
  c.voxel_size_m = 40.0f;
  c.density = DenseGrid(40, 40, 10);
  for (int z = 1; z < 9; ++z)
    for (int y = 0; y < 40; ++y)
      for (int x = 0; x < 40; ++x) c.density.at(x, y, z) = 1.0f;
  c.optics.extinction_per_m = static_cast<float>(tau / (8 * 40.0));
  c.origin_enu_m = glm::dvec3(0, 0, 1000);
  return c;
}

// Unit vector towards the Sun: elevation, and azimuth from north (y) towards east (x).
glm::dvec3 sun_at(double elevation_deg, double azimuth_deg) {
  const double e = glm::radians(elevation_deg), a = glm::radians(azimuth_deg);
  return glm::dvec3(std::cos(e) * std::sin(a), std::cos(e) * std::cos(a), std::sin(e));
}

struct View {
  const char* key;
  const char* name;
  std::function<CloudVolume()> cloud;
  glm::dvec3 sun;
  glm::dvec3 eye_offset;       // eye = the cloud's centre + this; the camera looks at the centre
  double fov_deg = 0.0;        // 0: 0.9 x the cloud's bounding sphere
  int res = 16;                // square image
  int spp = 500000;            // reference paths per pixel for the Sun (sky and ground: spp / 16), per half
  float max_transmittance = 0.5f;  // pixels compared: the cloud's body (the edges are noise-dominated)
};

// Prototype `index` of a procedural stratus deck (seed 3, 800-1100 m, 6 km
// area: 62 x 62 x 8 voxels of 50 m, with holes), extinction `extinction_per_m`.
CloudVolume stratus_tile(int index, float extinction_per_m) {
  CloudLayerSpec s;
  s.type = CloudLayerType::Stratus;
  s.coverage_oktas = 8;
  s.base_m = 800;
  s.top_m = 1100;
  s.area_size_m = 6000;
  s.seed = 3;
  CloudVolume c = generate_cloud_layer(s).field.prototypes.at(static_cast<size_t>(index));
  c.optics.extinction_per_m = extinction_per_m;
  return c;
}

// The development views: the defaults were fitted on all of them.
const std::vector<View>& development_views() {
  static const auto cu3 = [] { return cumulus_prototype(3, 0.06f); };
  static const std::vector<View> v = {
      {"blob_eyesun", "blob, Sun behind the eye, 45 deg up", blob_cloud, glm::normalize(glm::dvec3(0, -1, 1)),
       glm::dvec3(0, -2000, 0)},
      {"blob_side", "blob, Sun to the side, 30 deg up", blob_cloud, glm::normalize(glm::dvec3(1, 0, 0.58)),
       glm::dvec3(0, -2000, 0)},
      {"blob_behind", "blob, Sun behind it, 20 deg up", blob_cloud, glm::normalize(glm::dvec3(0, 1, 0.36)),
       glm::dvec3(0, -2000, 0)},
      {"blob_below", "blob from below, Sun overhead", blob_cloud, glm::dvec3(0, 0, 1), glm::dvec3(0, -300, -1500)},
      {"cu0_side", "cumulus #0, Sun to the side, 45 deg up", [] { return cumulus_prototype(0, 0.06f); },
       sun_at(45, 90), glm::dvec3(0, -2000, 300)},
      {"cu_front", "cumulus #3, Sun high behind the eye", cu3, sun_at(60, 200), glm::dvec3(300, -2200, 200)},
      {"cu_low_sun", "cumulus #3, Sun 8 deg up to the side", cu3, sun_at(8, 70), glm::dvec3(-400, -2200, -100)},
      {"cu_below", "cumulus #3 from below, Sun 40 deg up", cu3, sun_at(40, 30), glm::dvec3(200, -500, -1400)},
      {"thin_side", "thin cumulus (tau <= 2), Sun 35 deg up", [] { return cumulus_prototype(5, 0.006f); },
       sun_at(35, 100), glm::dvec3(0, -1800, 100), 0.0, 16, 500000, 0.9f},
      {"deck_below", "deck tau 20 from below, Sun 50 deg up", [] { return deck(20.0); }, sun_at(50, 120),
       glm::dvec3(0, -300, -900), 30.0, 10, 300000},
      {"deck_above", "deck tau 20 from above, Sun 25 deg up", [] { return deck(20.0); }, sun_at(25, 250),
       glm::dvec3(0, -500, 900), 30.0, 10, 300000},
  };
  return v;
}

// The held-out views: clouds, suns and eyes no fit and no choice of the model
// saw (defined and path-traced before the model was final, compared once).
const std::vector<View>& held_out_views() {
  static const std::vector<View> v = {
      {"f_cu7_side", "cumulus #7, Sun 30 deg up, side-lit", [] { return cumulus_prototype(7, 0.06f); },
       sun_at(30, 120), glm::dvec3(-500, -2300, 0)},
      {"f_cu9_below", "cumulus #9 from below, Sun 65 deg up", [] { return cumulus_prototype(9, 0.06f); },
       sun_at(65, 300), glm::dvec3(300, -400, -1300)},
      {"f_st_below", "stratus tile (tau <= 7, holes) from below", [] { return stratus_tile(0, 0.04f); },
       sun_at(40, 200), glm::dvec3(0, -300, -900), 30.0, 10, 300000},
      {"f_st_thick_above", "stratus tile x2.5 (tau <= 18) from above", [] { return stratus_tile(3, 0.1f); },
       sun_at(20, 80), glm::dvec3(200, -600, 900), 30.0, 10, 300000},
      {"f_thin_behind", "thin cumulus (tau <= 5), Sun 20 deg up behind it", [] { return cumulus_prototype(11, 0.012f); },
       sun_at(20, 0), glm::dvec3(0, -1800, 0), 0.0, 16, 500000, 0.9f},
  };
  return v;
}

constexpr double kSunLux = 1e5, kSkyCdm2 = 4000.0, kGroundCdm2 = 1500.0;

reference::PinholeCamera camera_for(const View& v, const CloudVolume& cloud) {
  reference::PinholeCamera cam;
  cam.position_enu_m = cloud.centre_enu_m() + v.eye_offset;
  cam.forward = -v.eye_offset;
  cam.up = glm::dvec3(0, 0, 1);
  if (std::abs(glm::normalize(cam.forward).z) > 0.99) cam.up = glm::dvec3(0, 1, 0);
  cam.vertical_fov_rad = v.fov_deg > 0.0 ? glm::radians(v.fov_deg)
                                         : 2.0 * std::atan(cloud.bounding_radius_m() / glm::length(cam.forward)) * 0.9;
  cam.width = cam.height = v.res;
  return cam;
}

// The path tracer's pixel-centre ray (cloud_path_tracer.h: no jitter).
glm::dvec3 pixel_ray(const reference::PinholeCamera& cam, int row, int col) {
  const glm::dvec3 fwd = glm::normalize(cam.forward);
  const glm::dvec3 right = glm::normalize(glm::cross(fwd, cam.up));
  const glm::dvec3 up = glm::cross(right, fwd);
  const double th = std::tan(0.5 * cam.vertical_fov_rad);
  const double y = (1.0 - 2.0 * (row + 0.5) / cam.height) * th;
  const double x = (2.0 * (col + 0.5) / cam.width - 1.0) * th;
  return glm::normalize(fwd + x * right + y * up);
}

// ---------------------------------------------------------------------------
// The stored references.

struct StoredReference {
  const char* key;
  int res;
  // Per pixel, row-major: Sun, sky, ground radiance (cd/m^2, green, for
  // kSunLux, kSkyCdm2, kGroundCdm2), transmittance, and |a - b| / (a + b) of
  // the two halves' totals.
  const float* data;
};

#include "path_traced_references.inc"

const StoredReference* stored(const char* key) {
  for (const StoredReference& r : kStoredReferences)
    if (std::string(r.key) == key) return &r;
  return nullptr;
}

// ---------------------------------------------------------------------------
// The comparison.

struct Errors {
  double mean = 0.0, bias = 0.0;          // of (model - truth) / truth over the pixels
  double sun = 0.0, ambient = 0.0;        // mean |model - truth| of each part / the pixel's truth
  double sun_ratio = 0.0, ambient_ratio = 0.0;  // summed model / summed truth, per part
  double noise = 0.0;                     // the reference's: mean |a - b| / (a + b)
  int pixels = 0;
};

Errors compare(const View& v, const twin::CloudOctaves& octaves) {
  const CloudVolume cloud = v.cloud();
  const reference::PinholeCamera cam = camera_for(v, cloud);
  const StoredReference* ref = stored(v.key);
  Errors e;
  if (!ref || ref->res != v.res) return e;
  const LightDepths depths = compute_light_depths(cloud, v.sun);
  const twin::CloudPhase phase = phase_for_droplet(cloud.optics.droplet_diameter_um);
  CloudLight sun, amb;
  sun.direction_enu = amb.direction_enu = v.sun;
  sun.illuminance_lux = glm::dvec3(kSunLux);
  amb.sky_radiance = glm::dvec3(kSkyCdm2);
  amb.ground_radiance = glm::dvec3(kGroundCdm2);
  const twin::CloudMarch m_sun = make_cloud_march(cloud, sun, 0.5f, 2048);
  const twin::CloudMarch m_amb = make_cloud_march(cloud, amb, 0.5f, 2048);
  double sun_model = 0.0, sun_truth = 0.0, amb_model = 0.0, amb_truth = 0.0;
  for (int row = 0; row < v.res; ++row)
    for (int col = 0; col < v.res; ++col) {
      const float* px = ref->data + 5 * (static_cast<size_t>(row) * v.res + col);
      if (px[3] > v.max_transmittance) continue;
      const double truth_sun = px[0], truth_amb = px[1] + px[2], truth = truth_sun + truth_amb;
      const glm::dvec3 d = pixel_ray(cam, row, col);
      const double ms = march_cloud_ray(cloud, depths, m_sun, phase, octaves, cam.position_enu_m, d, 1e9).radiance.g;
      const double ma = march_cloud_ray(cloud, depths, m_amb, phase, octaves, cam.position_enu_m, d, 1e9).radiance.g;
      e.mean += std::abs(ms + ma - truth) / truth;
      e.bias += (ms + ma) / truth - 1.0;
      e.sun += std::abs(ms - truth_sun) / truth;
      e.ambient += std::abs(ma - truth_amb) / truth;
      e.noise += px[4];
      sun_model += ms, sun_truth += truth_sun, amb_model += ma, amb_truth += truth_amb;
      ++e.pixels;
    }
  if (e.pixels) {
    for (double* x : {&e.mean, &e.bias, &e.sun, &e.ambient, &e.noise}) *x /= e.pixels;
    e.sun_ratio = sun_model / sun_truth;
    e.ambient_ratio = amb_model / amb_truth;
  }
  return e;
}

void print(const View& v, const Errors& e, const char* label = "") {
  std::printf("%-42s %3d px: %s%5.1f %% (bias %+5.1f %%; Sun part %4.1f %%, ambient part %4.1f %%; "
              "model/truth Sun %.2f ambient %.2f; reference noise %.1f %%)\n",
              v.name, e.pixels, label, 100.0 * e.mean, 100.0 * e.bias, 100.0 * e.sun, 100.0 * e.ambient,
              e.sun_ratio, e.ambient_ratio, 100.0 * e.noise);
}

// Runs every view, prints it, and checks it against `limits` (same order); returns the mean.
double check_views(const std::vector<View>& views, const std::vector<double>& limits, const char* what) {
  double mean = 0.0;
  for (size_t i = 0; i < views.size(); ++i) {
    const Errors e = compare(views[i], default_octaves());
    print(views[i], e);
    EXPECT_GT(e.pixels, 20) << views[i].key << ": no stored reference, or too few cloud pixels";
    EXPECT_LE(e.mean, limits[i]) << views[i].name;
    mean += e.mean / views.size();
  }
  std::printf("%s: mean %.1f %% (target <= 15 %%)\n", what, 100.0 * mean);
  return mean;
}

TEST(CloudOctaves, MultipleScatteringApproximationAgainstPathTracer) {
  // The development views (fitted on). Measured: see docs/CLOUDS.md; each
  // limit ~2 points above its view's figure.
  const double mean = check_views(development_views(),
                                  {0.14, 0.17, 0.16, 0.18, 0.12, 0.11, 0.22, 0.15, 0.12, 0.13, 0.10}, "development views");
  EXPECT_LE(mean, 0.13);
  // Single scattering (plus the ambient) misses most of the light.
  for (const View& v : development_views()) {
    if (v.max_transmittance > 0.5f) continue;  // the thin cumulus: single scattering is most of it
    EXPECT_GT(compare(v, single_scattering_octaves()).mean, 0.3) << v.name;
  }
}

TEST(CloudOctaves, HeldOutCloudsAgainstPathTracer) {
  // Clouds, suns and eyes no fit saw. Measured: see docs/CLOUDS.md; each
  // limit ~2 points above its view's figure.
  const double mean = check_views(held_out_views(), {0.22, 0.17, 0.08, 0.09, 0.29}, "held-out views");
  EXPECT_LE(mean, 0.16);
}

// The stored references against the path tracer as it is now, cheaply: the
// transmittance (exact, no noise) to the bit, so the clouds and cameras are
// the ones stored; the sky's and ground's parts (light-tailed) at 128 paths
// per pixel within 6 % over each view's cloud pixels; the Sun's part at 1024
// paths per pixel, whose heavy tail scatters one view's mean by ~15 % (0.69 to
// 1.32 measured), so only the mean over the views of live / stored, within
// 15 % (measured 1.00).
TEST(CloudOctaves, StoredReferencesMatchThePathTracer) {
  std::vector<View> views = development_views();
  for (const View& v : held_out_views()) views.push_back(v);
  double sun_ratio = 0.0;
  for (const View& v : views) {
    const StoredReference* ref = stored(v.key);
    ASSERT_NE(ref, nullptr) << v.key;
    ASSERT_EQ(ref->res, v.res) << v.key;
    const CloudVolume cloud = v.cloud();
    const reference::PinholeCamera cam = camera_for(v, cloud);
    reference::CloudEnvironment env[3];
    for (auto& e : env) e.light_direction = v.sun;
    env[0].light_illuminance_lux = glm::dvec3(kSunLux);
    env[1].sky_radiance = glm::dvec3(kSkyCdm2);
    env[2].ground_radiance = glm::dvec3(kGroundCdm2);
    const int spp[3] = {1024, 128, 128};
    double live[3] = {0, 0, 0}, kept[3] = {0, 0, 0};
    int mismatched_t = 0;
    for (int k = 0; k < 3; ++k) {
      reference::PathTraceSettings s;
      s.samples_per_pixel = spp[k];
      s.seed = 77 + k;
      const reference::CloudImage img = reference::path_trace(cloud, env[k], cam, s);
      for (size_t i = 0; i < img.radiance.size(); ++i) {
        const float* px = ref->data + 5 * i;
        if (k == 0 && std::abs(img.transmittance[i] - px[3]) > 1e-6f) ++mismatched_t;
        if (px[3] > v.max_transmittance) continue;
        live[k] += img.radiance[i].g;
        kept[k] += px[k];
      }
    }
    std::printf("%-16s live / stored: Sun %.3f, sky %.3f, ground %.3f\n", v.key, live[0] / kept[0],
                live[1] / kept[1], live[2] / kept[2]);
    EXPECT_EQ(mismatched_t, 0) << v.key << ": the cloud or the camera differs from the stored reference's";
    EXPECT_NEAR(live[1] / kept[1], 1.0, 0.06) << v.key;
    EXPECT_NEAR(live[2] / kept[2], 1.0, 0.06) << v.key;
    sun_ratio += live[0] / kept[0] / views.size();
  }
  std::printf("Sun: mean live / stored %.3f\n", sun_ratio);
  EXPECT_NEAR(sun_ratio, 1.0, 0.15);
}

// ---------------------------------------------------------------------------
// Not part of the suite.

// Writes path_traced_references.inc (to $ATMO_REFERENCE_OUT, else the working
// directory) from the path tracer: each view's Sun, sky and ground images in
// two independent halves (seeds 1000 h + part), averaged. ~1 h on 2 cores;
// $ATMO_REFERENCE_VIEWS (keys separated by commas) limits it to some views.
// Run with --gtest_also_run_disabled_tests --gtest_filter='*RegenerateReferences'.
TEST(CloudOctaves, DISABLED_RegenerateReferences) {
  const char* out_path = std::getenv("ATMO_REFERENCE_OUT");
  const char* only = std::getenv("ATMO_REFERENCE_VIEWS");
  std::ofstream out(out_path ? out_path : "path_traced_references.inc");
  ASSERT_TRUE(out.good());
  out << "// Generated by octaves_vs_path_tracer_test.cpp, DISABLED_RegenerateReferences: do not edit.\n"
         "// Per pixel: Sun, sky, ground (cd/m^2), transmittance, |a - b| / (a + b) of the two halves.\n";
  std::vector<View> all = development_views(), views;
  for (const View& v : held_out_views()) all.push_back(v);
  for (const View& v : all)
    if (!only || ("," + std::string(only) + ",").find("," + std::string(v.key) + ",") != std::string::npos)
      views.push_back(v);
  for (const View& v : views) {
    const CloudVolume cloud = v.cloud();
    const reference::PinholeCamera cam = camera_for(v, cloud);
    const size_t n = static_cast<size_t>(v.res) * v.res;
    std::vector<double> part[2][3];
    std::vector<float> transmittance;
    for (int h = 0; h < 2; ++h)
      for (int k = 0; k < 3; ++k) {
        reference::CloudEnvironment env;
        env.light_direction = v.sun;
        if (k == 0) env.light_illuminance_lux = glm::dvec3(kSunLux);
        if (k == 1) env.sky_radiance = glm::dvec3(kSkyCdm2);
        if (k == 2) env.ground_radiance = glm::dvec3(kGroundCdm2);
        reference::PathTraceSettings s;
        s.samples_per_pixel = k == 0 ? v.spp : v.spp / 16;
        s.seed = 1000 * static_cast<uint64_t>(h + 1) + k;
        const reference::CloudImage img = reference::path_trace(cloud, env, cam, s);
        for (size_t i = 0; i < n; ++i) part[h][k].push_back(img.radiance[i].g);
        transmittance = img.transmittance;
      }
    out << "const float kRef_" << v.key << "[] = {\n";
    char buf[160];
    for (size_t i = 0; i < n; ++i) {
      const double a = part[0][0][i] + part[0][1][i] + part[0][2][i];
      const double b = part[1][0][i] + part[1][1][i] + part[1][2][i];
      std::snprintf(buf, sizeof buf, "%.6g, %.6g, %.6g, %.6g, %.4g,\n", 0.5 * (part[0][0][i] + part[1][0][i]),
                    0.5 * (part[0][1][i] + part[1][1][i]), 0.5 * (part[0][2][i] + part[1][2][i]),
                    double(transmittance[i]), a + b > 0.0 ? std::abs(a - b) / (a + b) : 0.0);
      out << buf;
    }
    out << "};\n";
    std::printf("%s done\n", v.key);
    std::fflush(stdout);
  }
  out << "const StoredReference kStoredReferences[] = {\n";
  for (const View& v : views) out << "    {\"" << v.key << "\", " << v.res << ", kRef_" << v.key << "},\n";
  out << "};\n";
}

// The fit that chose default_octaves() (docs/CLOUDS.md): Nelder-Mead on the
// tuning views, the ambient's two parameters on the ambient's error first,
// then the octaves' and the diffusion's on the Sun's. Prints the parameters.
std::vector<double> nelder_mead(const std::function<double(const std::vector<double>&)>& f, std::vector<double> x0,
                                int iterations) {
  const size_t n = x0.size();
  std::vector<std::vector<double>> s(n + 1, x0);
  std::vector<double> fv(n + 1);
  for (size_t i = 0; i < n; ++i) s[i + 1][i] += 0.2 * std::abs(x0[i]) + 0.02;
  for (size_t i = 0; i <= n; ++i) fv[i] = f(s[i]);
  for (int it = 0; it < iterations; ++it) {
    std::vector<size_t> o(n + 1);
    for (size_t i = 0; i <= n; ++i) o[i] = i;
    std::sort(o.begin(), o.end(), [&](size_t a, size_t b) { return fv[a] < fv[b]; });
    const auto S = s;
    const auto F = fv;
    for (size_t i = 0; i <= n; ++i) s[i] = S[o[i]], fv[i] = F[o[i]];
    std::vector<double> c(n, 0.0);
    for (size_t i = 0; i < n; ++i)
      for (size_t j = 0; j < n; ++j) c[j] += s[i][j] / n;
    auto along = [&](double t) {
      std::vector<double> r(n);
      for (size_t j = 0; j < n; ++j) r[j] = c[j] + t * (s[n][j] - c[j]);
      return r;
    };
    const auto xr = along(-1.0);
    const double fr = f(xr);
    if (fr < fv[0]) {
      const auto xe = along(-2.0);
      const double fe = f(xe);
      s[n] = fe < fr ? xe : xr, fv[n] = std::min(fe, fr);
    } else if (fr < fv[n - 1]) {
      s[n] = xr, fv[n] = fr;
    } else {
      const auto xc = along(fr < fv[n] ? -0.5 : 0.5);
      const double fc = f(xc);
      if (fc < std::min(fr, fv[n])) {
        s[n] = xc, fv[n] = fc;
      } else {
        for (size_t i = 1; i <= n; ++i) {
          for (size_t j = 0; j < n; ++j) s[i][j] = s[0][j] + 0.5 * (s[i][j] - s[0][j]);
          fv[i] = f(s[i]);
        }
      }
    }
  }
  return s[std::min_element(fv.begin(), fv.end()) - fv.begin()];
}

TEST(CloudOctaves, DISABLED_FitDefaults) {
  const std::vector<View>& views = development_views();
  twin::CloudOctaves o = default_octaves();
  auto set = [&](const std::vector<double>& p, bool ambient) {
    if (ambient) {
      o.ambient_loss = static_cast<float>(p[0]), o.ambient_extinction = static_cast<float>(p[1]);
      o.ambient_view_extinction = static_cast<float>(p[2]);
    } else {
      o.extinction_scale = static_cast<float>(p[0]), o.scattering_scale = static_cast<float>(p[1]);
      o.eccentricity_scale = static_cast<float>(p[2]), o.diffusion_strength = static_cast<float>(p[3]);
      o.diffusion_extinction = static_cast<float>(p[4]), o.diffusion_side_escape = static_cast<float>(p[5]);
      o.diffusion_anisotropy = static_cast<float>(p[6]), o.diffusion_buildup_extinction = static_cast<float>(p[7]);
    }
  };
  auto objective = [&](const std::vector<double>& p, bool ambient) {
    for (double x : p)
      if (x < 0.0) return 1e9;
    set(p, ambient);
    double f = 0.0;
    for (const View& v : views) {
      const Errors e = compare(v, o);
      f += (ambient ? e.ambient : e.sun) / views.size();
    }
    return f;
  };
  std::vector<double> amb = {o.ambient_loss + 0.01, o.ambient_extinction, o.ambient_view_extinction};
  amb = nelder_mead([&](const std::vector<double>& p) { return objective(p, true); }, amb, 150);
  set(amb, true);
  std::vector<double> sun = {o.extinction_scale,   o.scattering_scale,      o.eccentricity_scale,
                             o.diffusion_strength, o.diffusion_extinction,  o.diffusion_side_escape,
                             o.diffusion_anisotropy, o.diffusion_buildup_extinction};
  for (int round = 0; round < 2; ++round)
    sun = nelder_mead([&](const std::vector<double>& p) { return objective(p, false); }, sun, 300);
  set(sun, false);
  std::printf("ambient_loss %.3f ambient_extinction %.3f ambient_view_extinction %.3f | a %.3f b %.3f c %.3f | diffusion K %.3f k %.3f side %.3f "
              "anisotropy %.3f buildup %.3f\n",
              o.ambient_loss, o.ambient_extinction, o.ambient_view_extinction, o.extinction_scale, o.scattering_scale, o.eccentricity_scale,
              o.diffusion_strength, o.diffusion_extinction, o.diffusion_side_escape, o.diffusion_anisotropy,
              o.diffusion_buildup_extinction);
  double mean = 0.0;
  for (const View& v : views) {
    const Errors e = compare(v, o);
    print(v, e);
    mean += e.mean / views.size();
  }
  std::printf("fitted: mean %.1f %%\n", 100.0 * mean);
}

}  // namespace
