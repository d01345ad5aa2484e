// The real-time lighting approximation (cloud_march.glsl's twin: a few
// octaves of forward scattering, a diffusion term for the deep light, an
// ambient term split between sky and ground, shaders/clouds/cloud_functions.glsl)
// against the Monte Carlo path tracer (all orders, tools/cloud_reference) on
// the same clouds: mean relative luminance error over the cloud's pixels, its
// bias, and the errors of the light's and the ambient's parts, per view.
//
// The references are STORED (tools/cloud_reference/path_traced_references.inc,
// with the views in lighting_views.cpp; written by
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
#include "lighting_views.h"
#include "core/clouds/cloud_lighting.h"
#include "core/clouds/cloud_optics.h"

namespace {

using namespace atmo::clouds;
using reference::LightingErrors;
using View = reference::LightingView;
using reference::development_views;
using reference::held_out_views;

constexpr double kSunLux = reference::kViewSunLux, kSkyCdm2 = reference::kViewSkyCdm2,
                 kGroundCdm2 = reference::kViewGroundCdm2;

LightingErrors compare(const View& v, const twin::CloudOctaves& octaves) {
  return reference::compare_with_reference(v, octaves);
}

void print(const View& v, const LightingErrors& e, const char* label = "") {
  std::printf("%-42s %3d px: %s%5.1f %% (bias %+5.1f %%; Sun part %4.1f %%, ambient part %4.1f %%; "
              "model/truth Sun %.2f ambient %.2f; reference noise %.1f %%)\n",
              v.name, e.pixels, label, 100.0 * e.mean, 100.0 * e.bias, 100.0 * e.sun, 100.0 * e.ambient,
              e.sun_ratio, e.ambient_ratio, 100.0 * e.noise);
}

// Runs every view, prints it, and checks it against `limits` (same order); returns the mean.
double check_views(const std::vector<View>& views, const std::vector<double>& limits, const char* what) {
  double mean = 0.0;
  for (size_t i = 0; i < views.size(); ++i) {
    const LightingErrors e = compare(views[i], default_octaves());
    print(views[i], e);
    EXPECT_GT(e.pixels, 20) << views[i].key << ": no stored reference, or too few cloud pixels";
    EXPECT_LE(e.mean, limits[i]) << views[i].name;
    mean += e.mean / views.size();
  }
  std::printf("%s: mean %.1f %% (target <= 15 %%)\n", what, 100.0 * mean);
  return mean;
}

// Each view's limit, ~2 points above its figure (measured: see docs/CLOUDS.md):
// the development views (fitted on), then the held-out ones (clouds, suns and
// eyes no fit saw).
const std::vector<double> kDevelopmentLimits = {0.14, 0.17, 0.16, 0.18, 0.12, 0.11, 0.22, 0.15, 0.12, 0.13, 0.10};
const std::vector<double> kHeldOutLimits = {0.22, 0.17, 0.08, 0.09, 0.29};

TEST(CloudOctaves, MultipleScatteringApproximationAgainstPathTracer) {
  const double mean = check_views(development_views(), kDevelopmentLimits, "development views");
  EXPECT_LE(mean, 0.13);
  // Single scattering (plus the ambient) misses most of the light.
  for (const View& v : development_views()) {
    if (v.max_transmittance > 0.5f) continue;  // the thin cumulus: single scattering is most of it
    EXPECT_GT(compare(v, single_scattering_octaves()).mean, 0.3) << v.name;
  }
}

TEST(CloudOctaves, HeldOutCloudsAgainstPathTracer) {
  const double mean = check_views(held_out_views(), kHeldOutLimits, "held-out views");
  EXPECT_LE(mean, 0.16);
}

// The layer march (ATMO_CLOUD_DRAW_LAYER: the same lighting through a clipmap
// of the cloud, resampled around the eye) against the same references, every
// view: no worse than the per-cloud march, give or take half a point (the two
// marches sample the ray apart; each reference's own noise is 2-4 %; measured:
// see docs/CLOUDS.md), so within the same limits, and both means within the
// 15 % target.
TEST(CloudOctaves, LayerMarchAgainstPathTracer) {
  const std::vector<double>* limits[2] = {&kDevelopmentLimits, &kHeldOutLimits};
  const std::vector<View>* groups[2] = {&development_views(), &held_out_views()};
  double mean[2] = {0.0, 0.0}, worst_gap = -1.0;
  for (int g = 0; g < 2; ++g) {
    const std::vector<View>& views = *groups[g];
    ASSERT_EQ(views.size(), limits[g]->size());
    for (size_t i = 0; i < views.size(); ++i) {
      const View& v = views[i];
      const LightingErrors per_cloud = compare(v, default_octaves());
      const LightingErrors layer =
          reference::compare_with_reference(v, default_octaves(), reference::LightingMarch::Layer);
      print(v, layer, "layer ");
      EXPECT_EQ(layer.pixels, per_cloud.pixels) << v.key;
      EXPECT_LE(layer.mean, (*limits[g])[i]) << v.name << " (per-cloud march " << per_cloud.mean << ")";
      EXPECT_LE(layer.mean, per_cloud.mean + 0.005) << v.name << " (per-cloud march " << per_cloud.mean << ")";
      worst_gap = std::max(worst_gap, layer.mean - per_cloud.mean);
      mean[g] += layer.mean / static_cast<double>(views.size());
    }
  }
  std::printf("layer march: development views %.1f %%, held-out views %.1f %% (target <= 15 %%); worst view against "
              "the per-cloud march %+.1f points\n",
              100.0 * mean[0], 100.0 * mean[1], 100.0 * worst_gap);
  EXPECT_LE(mean[0], 0.15);
  EXPECT_LE(mean[1], 0.15);
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
    const reference::StoredReference* ref = reference::stored_reference(v.key);
    ASSERT_NE(ref, nullptr) << v.key;
    ASSERT_EQ(ref->res, v.res) << v.key;
    const CloudVolume cloud = v.cloud();
    const reference::PinholeCamera cam = reference::camera_for(v, cloud);
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
// Not part of the suite: compiled only into cloud_generators
// (tests/clouds/CMakeLists.txt; built, never registered with CTest), so the
// suite has no disabled test.
#ifdef ATMO_CLOUD_GENERATORS

// Writes path_traced_references.inc (for tools/cloud_reference/; to
// $ATMO_REFERENCE_OUT, else the working
// directory) from the path tracer: each view's Sun, sky and ground images in
// two independent halves (seeds 1000 h + part), averaged. ~1 h on 2 cores;
// $ATMO_REFERENCE_VIEWS (keys separated by commas) limits it to some views.
// Run: build/tests/clouds/cloud_generators --gtest_also_run_disabled_tests --gtest_filter='*RegenerateReferences'.
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
    const reference::PinholeCamera cam = reference::camera_for(v, cloud);
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
// tuning views, the ambient's parameters on the ambient's error first, then
// the octaves' and the diffusion's on the Sun's. Prints the parameters.
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
      const LightingErrors e = compare(v, o);
      f += (ambient ? e.ambient : e.sun) / views.size();
    }
    return f;
  };
  std::vector<double> amb = {o.ambient_loss + 0.01, o.ambient_extinction, o.ambient_view_extinction};
  amb = reference::nelder_mead([&](const std::vector<double>& p) { return objective(p, true); }, amb, 150);
  set(amb, true);
  std::vector<double> sun = {o.extinction_scale,   o.scattering_scale,      o.eccentricity_scale,
                             o.diffusion_strength, o.diffusion_extinction,  o.diffusion_side_escape,
                             o.diffusion_anisotropy, o.diffusion_buildup_extinction};
  for (int round = 0; round < 2; ++round)
    sun = reference::nelder_mead([&](const std::vector<double>& p) { return objective(p, false); }, sun, 300);
  set(sun, false);
  std::printf("ambient_loss %.3f ambient_extinction %.3f ambient_view_extinction %.3f | a %.3f b %.3f c %.3f | diffusion K %.3f k %.3f side %.3f "
              "anisotropy %.3f buildup %.3f\n",
              o.ambient_loss, o.ambient_extinction, o.ambient_view_extinction, o.extinction_scale, o.scattering_scale, o.eccentricity_scale,
              o.diffusion_strength, o.diffusion_extinction, o.diffusion_side_escape, o.diffusion_anisotropy,
              o.diffusion_buildup_extinction);
  double mean = 0.0;
  for (const View& v : views) {
    const LightingErrors e = compare(v, o);
    print(v, e);
    mean += e.mean / views.size();
  }
  std::printf("fitted: mean %.1f %%\n", 100.0 * mean);
}

#endif  // ATMO_CLOUD_GENERATORS

}  // namespace
