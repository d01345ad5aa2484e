// atmo_clouds_error_cost — the clouds' error against cost (docs/CLOUDS.md
// "Error against cost"; tools/clouds_error_cost.py runs it and draws the
// charts with atmo-chart).
//
// A fixed cumulus scene drawn through the C ABI (the plugin linked
// statically, bench/cloud_scene.h): tests/plugin_gl/cloud_impostor_test.cpp's
// layer (4 oktas, base 1200 m, tops 2200 m, a 6 km square 3 to 9 km north,
// seed 11), the eye at 1700 m looking north 2 degrees up, 60 degrees vertical
// field of view, the Sun ~50 degrees up, output DISPLAY_SRGB (exposure 1e-4),
// 640x360 by default. Every frame draws the sky and the aerial perspective
// first (untimed) and then the clouds pass, timed: wall ms from a drained
// queue to glFinish (GL timer query alongside).
//
// Error of a frame: PSNR and RMSE of the whole displayed frame (sRGB, peak 1,
// as the impostor test) against the reference drawn at the same eye: the
// direct march (ATMO_CLOUD_DRAW_DIRECT) at full resolution (divisor 1) and
// step 0.5 voxels; psnr_cloud_db is the same over the pixels the reference's
// clouds change (more than 1/255 from the sky-only frame), where the error is.
//
// Sweeps (all other knobs at their defaults: impostors 128 texels, 0.5
// degrees, 8 updates a frame; march divisor 2, step 1 voxel; 6 octaves):
//   texels     impostor_texels 32, 64, 128, 256. Warm-up at the start eye
//              until nothing is rendered, then `--frames` frames moving 5 m
//              east each (re-renders within the budget happen): cost = the
//              median of those frames; error at the last one. Twice: with
//              the default texel rule (an impostor whose texel would cover
//              more than 1 pixel of the march's image is handed to the
//              direct march, so coarse tiles mean more marching), and with
//              it lifted (impostor_max_pixels_per_texel 8): the error of the
//              resolution alone.
//   threshold  impostor_angle_threshold_deg 0.15, 0.5, 1, 2, 4 on a path:
//              warm-up at the start, then `--path-frames` frames moving 30 m
//              east each, so impostors go stale; error = the mean over the
//              path of each frame against the direct march of that frame (mean
//              PSNR, mean RMSE, worst PSNR); cost = the MEAN ms a frame over
//              the path (re-renders, and a cut's burst, included).
//   direct     the direct march, march_resolution_divisor 1, 2, 4 x
//              march_step_voxels 0.5, 1, 2, at the texels sweep's last eye:
//              cost = the median of `--frames` frames; divisor 1 step 0.5 is
//              the reference itself (error 0; its cost is listed).
//   layer      the layer march (ATMO_CLOUD_DRAW_LAYER), divisor 1, 2, 4 x a
//              step budget of 48, 96, 192 (the default), 384 steps a pixel,
//              at the same eye and against the same reference as `direct`.
//   quality    the view's cost knob (AtmoViewState.cloud_quality: low,
//              medium, medium without temporal, high, full) of the layer
//              march on three views, each against its own direct-march
//              reference: this scene at the texels sweep's last eye, 8-okta
//              cumulus (1000-2800 m, a 10 km square) from inside the layer at
//              1900 m, and inside an overcast deck (600-1100 m, 12 km) at
//              850 m. psnr_worst_db: the first frame after a cut; psnr_db
//              and cost: after max(4, --frames) frames at rest (converged).
//   lighting   the lighting approximations (written to --lighting-csv)
//              against the Monte Carlo path tracer (all orders), on the
//              stored references of tests/clouds/octaves_vs_path_tracer_test.cpp
//              (tools/cloud_reference/lighting_views.h: 11 development and 5
//              held-out views, 300-500k paths a pixel): single scattering;
//              octaves alone (1..8, their a, b, c refitted here with the
//              diffusion term off, so they are at their best); octaves + the
//              diffusion term, the plugin's model (1..8, the defaults). Error:
//              the mean relative luminance error over a view's cloud pixels,
//              averaged over the views. Costs: the CPU twin's march
//              (march_cloud_ray, step 0.5 voxels) per ray over those pixels,
//              microseconds (one thread, median of 5 blocks); for the
//              plugin's model also the GL clouds pass with n octaves, direct
//              march at the defaults at the texels sweep's last eye, median
//              of `--frames` frames.
//
// Usage: atmo_clouds_error_cost --csv OUT.csv --lighting-csv OUT2.csv
//        [--width 640 --height 360 --frames 6 --path-frames 12 --only texels,threshold,direct,layer,quality,lighting]
#include <glad/gl.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>

#include "lighting_views.h"
#include "cloud_scene.h"
#include "atmo_support/image_metrics.h"
#include "core/clouds/cloud_lighting.h"
#include "core/clouds/cloud_optics.h"

namespace {

using cloud_bench::Camera;
using cloud_bench::Host;
using cloud_bench::median;
using atmo::support::Image;

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double mean(const std::vector<double>& v) {
  return v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / double(v.size());
}

struct Error {
  double psnr_db = 0.0, rmse = 0.0, psnr_cloud_db = 0.0;
};

// Whole frame (as the impostor test), and over the pixels the reference's clouds changed.
Error frame_error(const Image& test, const Image& ref, const Image& sky_only) {
  Error e;
  const atmo::support::ImageDiff d = atmo::support::compare_images(test, ref, 1.0);
  e.psnr_db = d.psnr_db;
  e.rmse = d.rmse;
  double sum = 0.0;
  size_t n = 0;
  for (size_t i = 0; i < ref.pixel_count(); ++i) {
    bool cloud = false;
    for (int c = 0; c < 3; ++c) cloud = cloud || std::abs(ref.rgba[4 * i + c] - sky_only.rgba[4 * i + c]) > 1.0f / 255;
    if (!cloud) continue;
    for (int c = 0; c < 3; ++c) {
      const double x = double(test.rgba[4 * i + c]) - ref.rgba[4 * i + c];
      sum += x * x;
    }
    n += 3;
  }
  const double mse = n ? sum / double(n) : 0.0;
  e.psnr_cloud_db = mse > 0.0 ? -10.0 * std::log10(mse) : std::numeric_limits<double>::infinity();
  return e;
}

struct Options {
  int width = 640, height = 360, frames = 6, path_frames = 12;
  std::string csv, lighting_csv, images_dir;
  std::set<std::string> only;
  bool wants(const std::string& s) const { return only.empty() || only.count(s); }
};

struct Row {
  std::string sweep, setting, label;  // no commas: the CSV is not quoted
  double cost_ms = 0.0, cost_median_ms = 0.0, cost_mean_ms = 0.0, query_ms = 0.0;
  Error err;
  double psnr_worst_db = 0.0;
  double rerendered = 0.0, impostors = 0.0, marched = 0.0, in_view = 0.0;
  int frames = 0;
};

class Study {
 public:
  explicit Study(const Options& o) : o_(o), host_(o.width, o.height) {
    layer_.type = ATMO_CLOUD_CUMULUS;
    layer_.coverage_oktas = 4;
    layer_.base_m = 1200.0;
    layer_.top_m = 2200.0;
    layer_.area_size_m = 6000.0;
    layer_.area_centre_enu_m[1] = 6000.0;
    layer_.seed = 11;
  }

  AtmoCloudsState state(uint32_t mode) const { return cloud_bench::clouds_state(&layer_, mode); }

  // set_clouds with the knobs, then a frame looking straight down (lights,
  // uploads, builds programs; no cloud in view) so that is not timed.
  void apply(const AtmoCloudsState& s) {
    const double t0 = now_s();
    host_.set_clouds(s);
    host_.frame(Camera{start_.east_m, start_.north_m, start_.height_m, -89.0});
    std::fprintf(stderr, "  set_clouds + lighting: %.1f s\n", now_s() - t0);
  }

  struct Frame {
    double ms = 0.0, query_ms = 0.0;
    atmo::gl::CloudDrawStats stats;
    Image image;
  };
  Frame frame(const Camera& cam, bool read = true) {
    Frame f;
    f.ms = host_.frame(cam, &f.query_ms);
    f.stats = host_.stats();
    if (read) f.image = host_.read();
    return f;
  }

  // The sky-only frame (for the cloud-pixel mask).
  Image sky_only(const Camera& cam) {
    host_.set_view(cam);
    host_.draw_sky();
    glFinish();
    return host_.read();
  }

  // The reference at each eye: the direct march, divisor 1, step 0.5.
  std::vector<Image> references(const std::vector<Camera>& eyes, std::vector<Image>* skies) {
    AtmoCloudsState s = state(ATMO_CLOUD_DRAW_DIRECT);
    s.march_resolution_divisor = 1;
    s.march_step_voxels = 0.5;
    apply(s);
    std::vector<Image> out;
    for (const Camera& c : eyes) {
      const double t0 = now_s();
      out.push_back(frame(c).image);
      skies->push_back(sky_only(c));
      std::fprintf(stderr, "  reference at east %.0f m: %.1f s\n", c.east_m, now_s() - t0);
    }
    return out;
  }

  // Warm-up at the start: frames until nothing is created or re-rendered (at most 6).
  void warm_up() {
    for (int i = 0; i < 6; ++i) {
      const Frame f = frame(start_, false);
      if (i > 0 && f.stats.impostors_created == 0 && f.stats.impostors_updated == 0) break;
    }
  }

  // With --images: the frame, and with a reference its difference x 20 (name_diff.png).
  void save(const std::string& name, const Image& img, const Image* ref = nullptr) {
    if (o_.images_dir.empty()) return;
    std::string error;
    atmo::support::write_png(o_.images_dir + "/" + name + ".png", img, &error);
    if (!ref) return;
    Image d = img;
    for (size_t i = 0; i < d.rgba.size(); ++i) d.rgba[i] = i % 4 == 3 ? 1.0f : 20.0f * std::abs(img.rgba[i] - ref->rgba[i]);
    atmo::support::write_png(o_.images_dir + "/" + name + "_diff.png", d, &error);
  }

  void run() {
    const double t_start = now_s();
    std::printf("renderer: %s, %dx%d\n", host_.gl().renderer().c_str(), o_.width, o_.height);
    std::vector<Camera> texel_path;
    Camera c = start_;
    for (int i = 0; i < o_.frames; ++i) {
      c.east_m += 5.0;
      texel_path.push_back(c);
    }
    const Camera end = texel_path.back();
    std::vector<Camera> path;
    c = start_;
    for (int i = 0; i < o_.path_frames; ++i) {
      c.east_m += 30.0;
      path.push_back(c);
    }
    std::fprintf(stderr, "references (direct march, divisor 1, step 0.5 voxels)\n");
    std::vector<Camera> eyes = {end};
    if (o_.wants("threshold")) eyes.insert(eyes.end(), path.begin(), path.end());
    std::vector<Image> skies;
    const std::vector<Image> refs = references(eyes, &skies);
    save("reference_end", refs[0]);

    for (int rule = 0; rule < 2 && o_.wants("texels"); ++rule) {
      for (uint32_t texels : {32u, 64u, 128u, 256u}) {
        std::fprintf(stderr, "impostor_texels %u%s\n", texels, rule ? ", impostor_max_pixels_per_texel 8" : "");
        AtmoCloudsState s = state(ATMO_CLOUD_DRAW_IMPOSTORS);
        s.impostor_texels = texels;
        // The second series lifts the texel rule (8 pixels a texel, the
        // largest allowed), so coarse impostors are not handed to the march:
        // the error of the resolution alone.
        if (rule) s.impostor_max_pixels_per_texel = 8.0;
        apply(s);
        warm_up();
        Row r;
        r.sweep = rule ? "impostors: texels; texel rule off (8 px/texel)" : "impostors: texels (moving 5 m/frame)";
        r.label = std::to_string(texels);
        r.setting = std::to_string(texels);
        std::vector<double> ms, q;
        Frame f;
        for (const Camera& cam : texel_path) {
          f = frame(cam, &cam == &texel_path.back());
          ms.push_back(f.ms);
          q.push_back(f.query_ms);
          r.rerendered += f.stats.impostors_updated + f.stats.impostors_created;
          r.impostors += f.stats.impostors_drawn;
          r.marched += f.stats.marched;
          r.in_view += f.stats.in_view;
        }
        finish(&r, ms, q, false);
        r.err = frame_error(f.image, refs[0], skies[0]);
        r.psnr_worst_db = r.err.psnr_db;
        save(std::string(rule ? "impostors_rule_off_texels_" : "impostors_texels_") + r.setting, f.image, &refs[0]);
        rows_.push_back(r);
        print(r);
      }
    }

    if (o_.wants("threshold")) {
      for (double deg : {0.15, 0.5, 1.0, 2.0, 4.0}) {
        std::fprintf(stderr, "impostor_angle_threshold_deg %.2f\n", deg);
        AtmoCloudsState s = state(ATMO_CLOUD_DRAW_IMPOSTORS);
        s.impostor_angle_threshold_deg = deg;
        apply(s);
        warm_up();
        Row r;
        r.sweep = "impostors: angle threshold in deg (path 30 m/frame)";
        std::ostringstream name;
        name << deg << " deg";
        r.setting = name.str();
        std::ostringstream label;
        label << deg;
        r.label = label.str();
        std::vector<double> ms, q, psnr, rmse, psnr_cloud;
        for (size_t i = 0; i < path.size(); ++i) {
          const Frame f = frame(path[i]);
          ms.push_back(f.ms);
          q.push_back(f.query_ms);
          const Error e = frame_error(f.image, refs[1 + i], skies[1 + i]);
          psnr.push_back(e.psnr_db);
          rmse.push_back(e.rmse);
          psnr_cloud.push_back(e.psnr_cloud_db);
          r.rerendered += f.stats.impostors_updated + f.stats.impostors_created;
          r.impostors += f.stats.impostors_drawn;
          r.marched += f.stats.marched;
          r.in_view += f.stats.in_view;
          std::fprintf(stderr, "    frame %zu: %.0f ms, %d re-rendered, %d stale left, PSNR %.2f dB\n", i, f.ms,
                       f.stats.impostors_updated + f.stats.impostors_created, f.stats.impostors_stale, e.psnr_db);
        }
        finish(&r, ms, q, true);
        r.err.psnr_db = mean(psnr);
        r.err.rmse = mean(rmse);
        r.err.psnr_cloud_db = mean(psnr_cloud);
        r.psnr_worst_db = *std::min_element(psnr.begin(), psnr.end());
        rows_.push_back(r);
        print(r);
      }
    }

    if (o_.wants("direct")) {
      for (uint32_t divisor : {1u, 2u, 4u})
        for (double step : {0.5, 1.0, 2.0}) {
          std::fprintf(stderr, "direct march, divisor %u, step %.1f\n", divisor, step);
          AtmoCloudsState s = state(ATMO_CLOUD_DRAW_DIRECT);
          s.march_resolution_divisor = divisor;
          s.march_step_voxels = step;
          apply(s);
          std::ostringstream name, label;
          name << "d" << divisor << " step " << step;
          label << step;
          steady_row("direct march: divisor " + std::to_string(divisor) + " (label: step in voxels)", name.str(),
                     label.str(), end, refs[0], skies[0]);
        }
    }
    // The layer march (ATMO_CLOUD_DRAW_LAYER): resolution and the step budget
    // every pixel every frame (the settings' overrides of the view's
    // cloud_quality, statically linked).
    if (o_.wants("layer")) {
      for (int divisor : {1, 2, 4})
        for (int steps : {48, 96, 192, 384}) {
          std::fprintf(stderr, "layer march, divisor %d, %d steps\n", divisor, steps);
          apply(state(ATMO_CLOUD_DRAW_LAYER));
          atmo::abi::CloudSettings& settings = host_.context()->clouds.settings;
          settings.layer_divisor = divisor;
          settings.layer_max_steps = steps;
          settings.layer_temporal = 0;
          steady_row("layer march: divisor " + std::to_string(divisor) + " (label: step budget)",
                     "d" + std::to_string(divisor) + " " + std::to_string(steps) + " steps", std::to_string(steps), end,
                     refs[0], skies[0]);
        }
      // The clipmap's width (level 0's reach, voxels a side), at the defaults otherwise.
      for (int size : {96, 192, 384}) {
        std::fprintf(stderr, "layer march, clipmap %d voxels a side\n", size);
        apply(state(ATMO_CLOUD_DRAW_LAYER));
        host_.context()->clouds.settings.layer_temporal = 0;
        host_.context()->clouds.settings.clipmap.size = size;
        ++host_.context()->clouds.version;  // the geometry, mips and levels made again at the new width
        steady_row("layer march: clipmap width (label: voxels a side)", "clipmap " + std::to_string(size),
                   std::to_string(size), end, refs[0], skies[0]);
      }
    }
    if (o_.wants("quality")) quality(end);
    write_csv();
    if (o_.wants("lighting")) lighting(end);
    summary();
    std::fprintf(stderr, "total %.0f s\n", now_s() - t_start);
  }

 private:
  // A still eye: a warm-up frame, then o_.frames timed; the last one's error against ref.
  void steady_row(const std::string& sweep, const std::string& setting, const std::string& label, const Camera& cam,
                  const Image& ref, const Image& sky) {
    frame(cam, false);  // warm-up
    Row r;
    r.sweep = sweep;
    r.setting = setting;
    r.label = label;
    std::vector<double> ms, q;
    Frame f;
    for (int i = 0; i < o_.frames; ++i) {
      f = frame(cam, i == o_.frames - 1);
      ms.push_back(f.ms);
      q.push_back(f.query_ms);
      r.marched += f.stats.marched;
      r.in_view += f.stats.in_view;
    }
    finish(&r, ms, q, false);
    r.err = frame_error(f.image, ref, sky);
    r.psnr_worst_db = r.err.psnr_db;
    rows_.push_back(r);
    print(r);
  }

  void finish(Row* r, const std::vector<double>& ms, const std::vector<double>& q, bool use_mean) {
    r->frames = int(ms.size());
    r->cost_median_ms = median(ms);
    r->cost_mean_ms = mean(ms);
    r->cost_ms = use_mean ? r->cost_mean_ms : r->cost_median_ms;
    r->query_ms = use_mean ? mean(q) : median(q);
    const double n = std::max(1.0, double(ms.size()));
    r->rerendered /= n;
    r->impostors /= n;
    r->marched /= n;
    r->in_view /= n;
  }

  // The cost knob (AtmoViewState.cloud_quality) on three views: this scene,
  // 8-okta cumulus from inside the layer, and inside an overcast deck. Per
  // level: the first frame at the eye after a cut (from the warm-up frame
  // looking down: psnr_worst_db), then --frames frames at rest (the image
  // converges in 4): cost = their median, psnr_db = the last one's.
  void quality(const Camera& scene_eye) {
    struct View {
      std::string name;
      AtmoCloudLayer layer;
      Camera eye;
    };
    std::vector<View> views;
    views.push_back({"4-okta scene", layer_, scene_eye});
    views.push_back({"8 oktas", cloud_bench::make_layer(ATMO_CLOUD_CUMULUS, 8, 1000.0, 2800.0, 10000.0, 5000.0, 11),
                     Camera{0.0, 200.0, 1900.0, 3.0}});
    const AtmoCloudLayer deck = cloud_bench::make_layer(ATMO_CLOUD_OVERCAST, 8, 600.0, 1100.0, 12000.0, 0.0, 11);
    views.push_back({"inside a deck", deck, Camera{0.0, 0.0, 850.0, 5.0}});
    struct Level {
      const char* name;
      uint32_t quality;
      int temporal;  // CloudSettings::layer_temporal (-1: the level's)
    };
    const Level levels[] = {{"low", ATMO_CLOUD_QUALITY_LOW, -1},
                            {"medium", ATMO_CLOUD_QUALITY_MEDIUM, -1},
                            {"medium no temporal", ATMO_CLOUD_QUALITY_MEDIUM, 0},
                            {"high", ATMO_CLOUD_QUALITY_HIGH, -1},
                            {"full", ATMO_CLOUD_QUALITY_FULL, -1}};
    const AtmoCloudLayer scene_layer = layer_;
    for (const View& v : views) {
      layer_ = v.layer;
      std::fprintf(stderr, "quality: %s: the reference (direct march, divisor 1, step 0.5 voxels)\n", v.name.c_str());
      host_.set_cloud_quality(ATMO_CLOUD_QUALITY_DEFAULT);
      std::vector<Image> skies;
      const Image ref = references({v.eye}, &skies)[0];
      save("quality_" + std::to_string(&v - views.data()) + "_reference", ref);
      for (const Level& l : levels) {
        std::fprintf(stderr, "quality: %s, %s\n", v.name.c_str(), l.name);
        host_.set_cloud_quality(l.quality);
        apply(state(ATMO_CLOUD_DRAW_LAYER));
        host_.context()->clouds.settings.layer_temporal = l.temporal;
        Row r;
        r.sweep = "quality: " + v.name;
        r.setting = l.name;
        r.label = l.name;
        host_.next_frame();
        const Frame cut = frame(v.eye);
        r.psnr_worst_db = frame_error(cut.image, ref, skies[0]).psnr_db;
        std::vector<double> ms, q;
        Frame f;
        for (int i = 0; i < std::max(4, o_.frames); ++i) {
          host_.next_frame();
          f = frame(v.eye);
          ms.push_back(f.ms);
          q.push_back(f.query_ms);
          r.in_view += f.stats.in_view;
        }
        finish(&r, ms, q, false);
        r.err = frame_error(f.image, ref, skies[0]);
        save("quality_" + std::to_string(&v - views.data()) + "_" + l.name, f.image, &ref);
        rows_.push_back(r);
        print(r);
      }
    }
    layer_ = scene_layer;
    host_.set_cloud_quality(ATMO_CLOUD_QUALITY_DEFAULT);
  }

  static void print(const Row& r) {
    std::printf("%-46s %-12s cost %8.1f ms (median %8.1f, mean %8.1f)  PSNR %6.2f dB (cloud px %6.2f, worst %6.2f)  "
                "RMSE %.5f  in view %.1f, impostors %.1f, marched %.1f, re-rendered %.2f/frame\n",
                r.sweep.c_str(), r.setting.c_str(), r.cost_ms, r.cost_median_ms, r.cost_mean_ms, r.err.psnr_db,
                r.err.psnr_cloud_db, r.psnr_worst_db, r.err.rmse, r.in_view, r.impostors, r.marched, r.rerendered);
    std::fflush(stdout);
  }

  void write_csv() {
    if (o_.csv.empty() || rows_.empty()) return;  // --only lighting keeps the last run's file
    std::ofstream f(o_.csv);
    f << "# atmo_clouds_error_cost " << o_.width << "x" << o_.height << " on " << host_.gl().renderer()
      << ": error against the direct march at divisor 1, step 0.5 voxels (PSNR of the displayed sRGB frame, peak 1);"
         " cost_ms: clouds pass wall ms per frame (median; the threshold path: mean)\n";
    f << "sweep,setting,label,cost_ms,cost_median_ms,cost_mean_ms,timer_query_ms,psnr_db,psnr_cloud_db,psnr_worst_db,rmse,"
         "in_view,impostors,marched,rerendered_per_frame,frames\n";
    char buf[512];
    for (const Row& r : rows_) {
      if (!std::isfinite(r.err.psnr_db)) continue;  // the reference against itself: listed in the summary
      std::snprintf(buf, sizeof buf, "%s,%s,%s,%.2f,%.2f,%.2f,%.2f,%.2f,%.2f,%.2f,%.6f,%.1f,%.1f,%.1f,%.2f,%d\n",
                    r.sweep.c_str(), r.setting.c_str(), r.label.c_str(), r.cost_ms, r.cost_median_ms, r.cost_mean_ms, r.query_ms,
                    r.err.psnr_db, r.err.psnr_cloud_db, r.psnr_worst_db, r.err.rmse, r.in_view, r.impostors, r.marched,
                    r.rerendered, r.frames);
      f << buf;
    }
    for (const Row& r : rows_) {
      if (std::isfinite(r.err.psnr_db)) continue;
      std::snprintf(buf, sizeof buf, "# reference (%s): cost %.2f ms median, %d frames\n", r.setting.c_str(),
                    r.cost_median_ms, r.frames);
      f << buf;
    }
  }

  // ---- (d) lighting approximations against the path tracer ----

  struct LightingRow {
    std::string series;
    int octaves = 0;
    double development = 0.0, held_out = 0.0, all = 0.0, bias = 0.0, worst = 0.0;
    std::string worst_view, worst_key;
    double cpu_us_per_ray = 0.0, gl_ms = -1.0;
  };

  // The model's error over the development and held-out views, and the CPU
  // twin's cost per ray (the views' rays lit by Sun, sky and ground together,
  // as the plugin lights them; 100 passes over all of them in 5 blocks, the
  // median block, one thread).
  LightingRow score(const std::string& series, const atmo::clouds::twin::CloudOctaves& oc,
                    const std::vector<atmo::clouds::reference::ViewRays>& rays) {
    namespace ref = atmo::clouds::reference;
    LightingRow r;
    r.series = series;
    r.octaves = oc.count;
    double bias = 0.0;
    int views = 0;
    for (const auto* set : {&ref::development_views(), &ref::held_out_views()}) {
      double sum = 0.0;
      for (const ref::LightingView& v : *set) {
        const ref::LightingErrors e = ref::compare_with_reference(v, oc);
        if (e.pixels == 0) throw std::runtime_error(std::string("no stored reference for view ") + v.key);
        sum += e.mean;
        bias += e.bias;
        if (e.mean > r.worst) r.worst = e.mean, r.worst_view = v.name, r.worst_key = v.key;
        ++views;
      }
      (set == &ref::development_views() ? r.development : r.held_out) = sum / double(set->size());
      r.all += sum;
    }
    r.all /= views;
    r.bias = bias / views;
    size_t n = 0;
    for (const ref::ViewRays& v : rays) n += v.directions.size();
    double volatile sink = 0.0;
    std::vector<double> block_us;
    const int passes = 100;
    for (int b = 0; b < 5; ++b) {
      const double t0 = now_s();
      for (int k = 0; k < passes / 5; ++k)
        for (const ref::ViewRays& v : rays)
          for (const glm::dvec3& d : v.directions)
            sink = sink + atmo::clouds::march_cloud_ray(v.cloud, v.depths, v.march, v.phase, oc, v.eye, d, 1e9).radiance.g;
      block_us.push_back((now_s() - t0) * 1e6 / double((passes / 5) * n));
    }
    r.cpu_us_per_ray = median(block_us);
    return r;
  }

  void lighting(const Camera& end) {
    namespace cl = atmo::clouds;
    namespace ref = atmo::clouds::reference;
    std::vector<ref::ViewRays> rays;
    size_t n_rays = 0;
    for (const auto* set : {&ref::development_views(), &ref::held_out_views()})
      for (const ref::LightingView& v : *set) {
        rays.push_back(ref::view_rays(v));
        n_rays += rays.back().directions.size();
      }
    std::fprintf(stderr, "lighting: %zu views, %zu cloud pixels\n", rays.size(), n_rays);

    // Octaves alone, at their best: the octaves' a, b, c refitted with the
    // diffusion term off (the fit of DISABLED_FitDefaults' second stage, on the
    // Sun's part over the development views, at the plugin's 6 octaves; the
    // ambient's parameters are the defaults', which do not depend on it).
    cl::twin::CloudOctaves alone = cl::default_octaves();
    alone.diffusion_strength = 0.0f;
    {
      const double t0 = now_s();
      auto objective = [&](const std::vector<double>& p) {
        for (double x : p)
          if (x < 0.0 || x > 1.0) return 1e9;
        cl::twin::CloudOctaves o = alone;
        o.extinction_scale = float(p[0]), o.scattering_scale = float(p[1]), o.eccentricity_scale = float(p[2]);
        double f = 0.0;
        for (const ref::LightingView& v : ref::development_views()) f += ref::compare_with_reference(v, o).sun;
        return f / double(ref::development_views().size());
      };
      std::vector<double> p = {alone.extinction_scale, alone.scattering_scale, alone.eccentricity_scale};
      for (int round = 0; round < 2; ++round) p = ref::nelder_mead(objective, p, 60);
      alone.extinction_scale = float(p[0]), alone.scattering_scale = float(p[1]), alone.eccentricity_scale = float(p[2]);
      std::printf("octaves alone, refitted with no diffusion term: a %.3f b %.3f c %.3f (%.0f s)\n",
                  alone.extinction_scale, alone.scattering_scale, alone.eccentricity_scale, now_s() - t0);
    }

    // Single scattering is the octaves' first point (one octave, no diffusion):
    // its own series, and the start of the octaves' line.
    std::vector<LightingRow> out;
    for (int n = 1; n <= 8; ++n) {
      cl::twin::CloudOctaves o = alone;
      o.count = n;
      out.push_back(score("octaves alone (refitted; no diffusion)", o, rays));
    }
    out.insert(out.begin(), out.front());
    out.front().series = "single scattering";
    for (int n = 1; n <= 8; ++n) {
      cl::twin::CloudOctaves o = cl::default_octaves();
      o.count = n;
      LightingRow r = score("octaves + diffusion (the plugin's model)", o, rays);
      // GL cost: the clouds pass, direct march at the defaults, with n octaves.
      AtmoCloudsState s = state(ATMO_CLOUD_DRAW_DIRECT);
      s.multiple_scattering_octaves = uint32_t(n);
      apply(s);
      frame(end, false);
      std::vector<double> ms;
      for (int i = 0; i < o_.frames; ++i) ms.push_back(frame(end, false).ms);
      r.gl_ms = median(ms);
      out.push_back(r);
    }
    std::ofstream f;
    if (!o_.lighting_csv.empty()) {
      f.open(o_.lighting_csv);
      f << "# atmo_clouds_error_cost: cloud lighting approximations against the path tracer (stored references, "
           "tools/cloud_reference/lighting_views.h: "
        << ref::development_views().size() << " development + " << ref::held_out_views().size()
        << " held-out views, " << n_rays
        << " cloud pixels); error = mean relative luminance error over a view's cloud pixels, averaged over the "
           "views; cpu_us_per_ray: march_cloud_ray, step 0.5 voxels, one thread; gl_ms: clouds pass, direct march "
           "at divisor 2 step 1, "
        << o_.width << "x" << o_.height << ", median (plugin's model only)\n";
      f << "series,octaves,label,development_pct,held_out_pct,all_views_pct,bias_pct,worst_view_pct,worst_view,"
           "cpu_us_per_ray,gl_ms\n";
    }
    for (const LightingRow& r : out) {
      std::printf("%-42s %d octaves: error %5.1f %% (development %5.1f, held out %5.1f; bias %+5.1f %%; worst %5.1f %%, "
                  "%s), CPU %.2f us/ray",
                  r.series.c_str(), r.octaves, 100 * r.all, 100 * r.development, 100 * r.held_out, 100 * r.bias,
                  100 * r.worst, r.worst_view.c_str(), r.cpu_us_per_ray);
      if (r.gl_ms >= 0.0) std::printf(", GL direct march %.1f ms", r.gl_ms);
      std::printf("\n");
      if (f) {
        char buf[512];
        std::snprintf(buf, sizeof buf, "%s,%d,%d,%.2f,%.2f,%.2f,%.2f,%.2f,%s,%.3f,%s\n", r.series.c_str(),
                      r.octaves, r.octaves, 100 * r.development, 100 * r.held_out, 100 * r.all, 100 * r.bias,
                      100 * r.worst, r.worst_key.c_str(), r.cpu_us_per_ray,
                      r.gl_ms >= 0.0 ? std::to_string(r.gl_ms).c_str() : "");
        f << buf;
      }
    }
    std::fflush(stdout);
  }

  // The speed-up of impostors over the direct march at equal quality.
  void summary() {
    const Row* imp = nullptr;
    for (const Row& r : rows_)
      if (r.sweep.rfind("impostors: texels (", 0) == 0 && r.setting == "128") imp = &r;
    if (!imp) return;
    const Row* best = nullptr;
    const Row* def = nullptr;
    for (const Row& r : rows_) {
      if (r.sweep.rfind("direct", 0) != 0) continue;
      if (r.setting == "d2 step 1") def = &r;
      if (r.err.psnr_db >= imp->err.psnr_db && (!best || r.cost_ms < best->cost_ms)) best = &r;
    }
    std::printf("default impostors (128 texels, 0.5 deg): %.1f ms, PSNR %.2f dB\n", imp->cost_ms, imp->err.psnr_db);
    if (best)
      std::printf("cheapest direct march at >= that PSNR: %s, %.1f ms, PSNR %.2f dB: impostors %.1fx faster\n",
                  best->setting.c_str(), best->cost_ms, best->err.psnr_db, best->cost_ms / imp->cost_ms);
    if (def)
      std::printf("default direct march (d2 step 1): %.1f ms, PSNR %.2f dB: impostors %.1fx faster\n", def->cost_ms,
                  def->err.psnr_db, def->cost_ms / imp->cost_ms);
  }

  Options o_;
  Host host_;
  AtmoCloudLayer layer_ = atmo::make<AtmoCloudLayer>(ATMO_TYPE_CLOUD_LAYER);
  const Camera start_{0.0, 0.0, 1700.0, 2.0};
  std::vector<Row> rows_;
};

}  // namespace

int main(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "%s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--csv") o.csv = next();
    else if (a == "--lighting-csv") o.lighting_csv = next();
    else if (a == "--images") o.images_dir = next();
    else if (a == "--width") o.width = std::stoi(next());
    else if (a == "--height") o.height = std::stoi(next());
    else if (a == "--frames") o.frames = std::max(1, std::stoi(next()));
    else if (a == "--path-frames") o.path_frames = std::max(1, std::stoi(next()));
    else if (a == "--only") {
      std::stringstream ss(next());
      std::string item;
      while (std::getline(ss, item, ',')) o.only.insert(item);
    } else {
      std::fprintf(stderr,
                   "usage: atmo_clouds_error_cost [--csv F] [--lighting-csv F] [--images DIR] [--width 640] "
                   "[--height 360] [--frames 6] [--path-frames 12] [--only texels,threshold,direct,layer,quality,lighting]\n");
      return 2;
    }
  }
  try {
    Study study(o);
    study.run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "atmo_clouds_error_cost: %s\n", e.what());
    return 1;
  }
  return 0;
}
