// Where the passes are known to fail: extreme places, heights, times and air.
// Every pixel must stay finite and non-negative (degrade, never NaN), and the
// image must not jump when a huge ECEF eye moves by a millimetre.
#include <glad/gl.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <cstdio>
#include <functional>
#include <vector>

#include "atmo_support/example_view.h"
#include "atmo_support/image_metrics.h"
#include "plugin_gl_fixture.h"

using namespace plugin_gl;

namespace {

// Host geometry at window depth 0.99995 (about 20 km) in the lower half, far plane above.
GLuint make_half_depth() { return atmo::support::make_split_depth_texture(kWidth, kHeight, 0.99995f); }

AtmoViewState view_at(double lat, double lon, double height, double heading, double pitch, GLuint depth) {
  auto vs = atmo::make<AtmoViewState>(ATMO_TYPE_VIEW_STATE);
  vs.eye_kind = ATMO_POSITION_GEODETIC;
  vs.eye_geodetic[0] = lat;
  vs.eye_geodetic[1] = lon;
  vs.eye_geodetic[2] = height;
  vs.world_frame = ATMO_WORLD_ENU;
  vs.world_origin_geodetic[0] = lat;
  vs.world_origin_geodetic[1] = lon;
  copy(look(heading, pitch), vs.view_from_world);
  copy(glm::perspective(glm::radians(70.0), double(kWidth) / kHeight, 1.0, 1e5), vs.clip_from_view);
  vs.viewport[2] = kWidth;
  vs.viewport[3] = kHeight;
  vs.depth_texture = depth;
  vs.exposure_scale = 1.0;
  return vs;
}

void set_utc(Fixture& f, double utc_posix_s, uint64_t host_frame_number = 0) {
  auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
  frame.utc_posix_s = utc_posix_s;
  frame.host_frame_number = host_frame_number;
  f.context->set_frame(frame);
}

size_t bad_pixels(const atmo::support::Image& img) {
  size_t bad = 0;
  for (size_t i = 0; i < img.pixel_count(); ++i)
    for (int c = 0; c < 3; ++c) {
      float v = img.rgba[i * 4 + c];
      if (!std::isfinite(v) || v < 0.0f) ++bad;
    }
  return bad;
}

}  // namespace

TEST(Robustness, FiniteAndNonNegativeEverywhereItIsKnownToFail) {
  Fixture f;
  GLuint depth = make_half_depth();
  const double times[] = {1718964000.0 /* noon */, 1718997000.0 /* sun -4° */, 1719010000.0 /* deep night */,
                          1703160000.0 /* December */};
  const double heights[] = {-400.0, 0.0, 1.0, 12000.0, 30000.0, 100000.0, 500000.0};
  const double latitudes[] = {90.0, -90.0, 0.0, 47.26};
  const double visibilities[] = {50.0, 40000.0, 500000.0};
  const double pitches[] = {-89.9, 0.0, 89.9};
  int renders = 0;
  for (double vis : visibilities) {
    // A new context per air, so its first frame draws that air. Within it the
    // latitudes change the model sphere: those tables come from the worker while
    // the frames keep the previous sphere's (every frame must be finite either way).
    f.fresh_context();
    auto atm = atmo::make<AtmoAtmosphereState>(ATMO_TYPE_ATMOSPHERE_STATE);
    atm.visibility_m = vis;
    f.context->set_atmosphere(atm);
    for (double t : times) {
      auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
      frame.utc_posix_s = t;
      f.context->set_frame(frame);
      for (double lat : latitudes)
        for (double h : heights)
          for (double pitch : pitches) {
            f.view->set(view_at(lat, 179.9999, h, 33.0, pitch, depth));
            f.target->bind();
            f.target->clear(0.1f, 0.1f, 0.1f, 1.0f);
            ASSERT_EQ(f.view->render(ATMO_PASS_SKY), ATMO_SUCCESS);
            ASSERT_EQ(f.view->render(ATMO_PASS_AERIAL_PERSPECTIVE), ATMO_SUCCESS);
            size_t bad = bad_pixels(f.target->read_color());
            ASSERT_EQ(bad, 0u) << "visibility " << vis << " m, time " << t << ", lat " << lat << ", height " << h
                               << " m, pitch " << pitch;
            ++renders;
          }
    }
  }
  std::printf("[ robustness ] %d renders (sky + aerial perspective), every pixel finite and >= 0\n", renders);
  glDeleteTextures(1, &depth);
}

TEST(Robustness, MillimetreMovesOfAnEcefEyeDoNotJitter) {
  Fixture f;
  auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
  frame.utc_posix_s = 1718964000.0;
  f.context->set_frame(frame);
  GLuint depth = make_half_depth();
  // Eye on the equator at 0° E, 1500 m up, in ECEF; ECEF world axes. Looking east, horizontal:
  // east = +Y, up = +X at (0°, 0°).
  auto vs = view_at(0.0, 0.0, 1500.0, 90.0, 0.0, depth);
  vs.eye_kind = ATMO_POSITION_ECEF;
  vs.world_frame = ATMO_WORLD_ECEF;
  vs.eye_ecef_m[0] = 6378137.0 + 1500.0;
  copy(glm::lookAt(glm::dvec3(0), glm::dvec3(0, 1, 0), glm::dvec3(1, 0, 0)), vs.view_from_world);
  atmo::support::Image previous;
  double worst_step = 0.0;
  for (int step = 0; step < 6; ++step) {
    vs.eye_ecef_m[0] = 6378137.0 + 1500.0 + 0.001 * step;
    vs.eye_ecef_m[1] = 0.001 * step;
    f.view->set(vs);
    f.target->bind();
    f.target->clear(0.2f, 0.2f, 0.2f, 1.0f);
    ASSERT_EQ(f.view->render(ATMO_PASS_SKY), ATMO_SUCCESS);
    ASSERT_EQ(f.view->render(ATMO_PASS_AERIAL_PERSPECTIVE), ATMO_SUCCESS);
    atmo::support::Image img = f.target->read_color();
    if (step > 0) {
      auto stats = atmo::support::relative_luminance_error(img, previous, 1.0);
      worst_step = std::max(worst_step, stats.max);
    }
    previous = img;
  }
  std::printf("[ robustness ] ECEF eye at 6 379 km moved in 1 mm steps: worst per-pixel relative change %.2e\n",
              worst_step);
  EXPECT_LT(worst_step, 1e-3);
  glDeleteTextures(1, &depth);
}

// The same camera given in the host's local ENU frame and in ECEF (the world
// moved by ~6.4e6 m): the 8-bit images may differ by at most one level.
TEST(Robustness, EcefWorldGivesTheSameImageAsALocalWorld) {
  Fixture f;
  auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
  frame.utc_posix_s = 1718989800.0;  // low sun: the most colour and gradient
  f.context->set_frame(frame);
  GLuint depth = make_half_depth();
  const double lat = 47.26, lon = 11.35, height = 900.0;
  auto local = view_at(lat, lon, height, 300.0, 3.0, depth);
  local.exposure_scale = 1.0 / (1.2 * 4096.0);  // EV100 12
  local.output_encoding = ATMO_OUTPUT_DISPLAY_SRGB;

  // ECEF: eye in ECEF metres, view rotation expressed in ECEF axes.
  auto ecef = local;
  ecef.eye_kind = ATMO_POSITION_ECEF;
  ecef.world_frame = ATMO_WORLD_ECEF;
  const double la = glm::radians(lat), lo = glm::radians(lon);
  const double semi_major = 6378137.0, e2 = 6.69437999014e-3;
  const double n = semi_major / std::sqrt(1.0 - e2 * std::sin(la) * std::sin(la));
  ecef.eye_ecef_m[0] = (n + height) * std::cos(la) * std::cos(lo);
  ecef.eye_ecef_m[1] = (n + height) * std::cos(la) * std::sin(lo);
  ecef.eye_ecef_m[2] = (n * (1.0 - e2) + height) * std::sin(la);
  const glm::dvec3 east(-std::sin(lo), std::cos(lo), 0.0);
  const glm::dvec3 north(-std::sin(la) * std::cos(lo), -std::sin(la) * std::sin(lo), std::cos(la));
  const glm::dvec3 up(std::cos(la) * std::cos(lo), std::cos(la) * std::sin(lo), std::sin(la));
  const glm::dmat3 ecef_from_enu(east, north, up);
  const glm::dmat4 view_enu = look(300.0, 3.0);
  const glm::dmat3 view_rotation = glm::dmat3(view_enu) * glm::transpose(ecef_from_enu);
  copy(glm::dmat4(view_rotation), ecef.view_from_world);

  auto render = [&](const AtmoViewState& vs) {
    f.view->set(vs);
    f.target->bind();
    f.target->clear(0.1f, 0.2f, 0.3f, 1.0f);
    EXPECT_EQ(f.view->render(ATMO_PASS_SKY), ATMO_SUCCESS);
    EXPECT_EQ(f.view->render(ATMO_PASS_AERIAL_PERSPECTIVE), ATMO_SUCCESS);
    return f.target->read_color();
  };
  atmo::support::Image a = render(local), b = render(ecef);
  int worst_levels = 0;
  for (size_t i = 0; i < a.pixel_count(); ++i)
    for (int c = 0; c < 3; ++c) {
      int la8 = static_cast<int>(std::lround(std::clamp(a.rgba[i * 4 + c], 0.0f, 1.0f) * 255.0f));
      int lb8 = static_cast<int>(std::lround(std::clamp(b.rgba[i * 4 + c], 0.0f, 1.0f) * 255.0f));
      worst_levels = std::max(worst_levels, std::abs(la8 - lb8));
    }
  std::printf("[ robustness ] local ENU world vs ECEF world (6.4e6 m coordinates): worst 8-bit difference %d level(s)\n",
              worst_levels);
  EXPECT_LE(worst_levels, 1);
  glDeleteTextures(1, &depth);
}

// A view matrix must be a rigid transform and the projection well conditioned
// (docs/ABI.md): a finite but huge element (1e300), a scale, a shear, a
// reflection, a projective bottom row, a singular or near-singular projection
// are refused with OUT_OF_RANGE and a message naming the matrix, and leave the
// view as it was (the next frame draws the same image). Before these checks a
// 1e300 element was accepted and gave NaN directions.
TEST(Robustness, DegenerateViewMatricesAreRefusedAndChangeNothing) {
  Fixture f;
  set_utc(f, 1718964000.0);
  const AtmoViewState good = view_at(47.26, 11.35, 900.0, 30.0, 5.0, 0);
  auto render = [&] {
    f.target->bind();
    f.target->clear(0.0f, 0.0f, 0.0f, 1.0f);
    EXPECT_EQ(f.view->render(ATMO_PASS_SKY), ATMO_SUCCESS);
    return f.target->read_color();
  };
  f.view->set(good);
  const atmo::support::Image before = render();
  struct Case {
    const char* what;
    int matrix;  // 0: view_from_world, 1: clip_from_view
    std::function<void(double*)> edit;
    const char* message;
  };
  const std::vector<Case> cases = {
      {"view element 1e300", 0, [](double* m) { m[0] = 1e300; }, "view_from_world: the upper 3x3 is not a rotation"},
      {"view element -1e300 in the bottom row", 0, [](double* m) { m[3] = -1e300; }, "view_from_world[3]"},
      {"view scaled by 2", 0, [](double* m) { for (int i = 0; i < 11; ++i) if (i % 4 != 3) m[i] *= 2.0; }, "not a rotation"},
      {"view sheared by 0.01", 0, [](double* m) { m[4] += 0.01; }, "not a rotation"},
      {"view mirrored", 0, [](double* m) { m[0] = -m[0]; m[4] = -m[4]; m[8] = -m[8]; }, "reflection"},
      {"view projective (w row 0.5)", 0, [](double* m) { m[15] = 0.5; }, "view_from_world[15] = 0.5"},
      {"view all zero", 0, [](double* m) { std::fill(m, m + 16, 0.0); }, "not a rotation"},
      {"projection element 1e300", 1, [](double* m) { m[0] = 1e300; }, "clip_from_view is singular or ill-conditioned"},
      {"projection all zero", 1, [](double* m) { std::fill(m, m + 16, 0.0); }, "clip_from_view is singular"},
      {"projection rank 3 (no w row)", 1, [](double* m) { m[11] = 0.0; }, "clip_from_view is singular"},
      {"projection near-singular (x scale 1e-12)", 1, [](double* m) { m[0] = 1e-12; }, "ill-conditioned"},
  };
  for (const Case& c : cases) {
    AtmoViewState vs = good;
    c.edit(c.matrix == 0 ? vs.view_from_world : vs.clip_from_view);
    const AtmoResult r = f.plugin->api().set_view(f.view->handle(), &vs);
    const std::string message = f.context->last_error();
    std::printf("[ robustness ] %-42s -> %s: %s\n", c.what, f.plugin->result_string(r).c_str(), message.c_str());
    EXPECT_EQ(r, ATMO_ERROR_OUT_OF_RANGE) << c.what;
    EXPECT_NE(message.find(c.message), std::string::npos) << c.what << ": " << message;
  }
  const atmo::support::Image after = render();
  const auto diff = atmo::support::compare_images(before, after, 1.0);
  EXPECT_EQ(diff.max_abs, 0.0) << "a refused view changed the image";
  EXPECT_EQ(diff.nonfinite_b, 0u);
}

// Within the tolerance: float round-off of a host's matrices (1e-6 per
// element), an infinite reversed-Z projection with near 0.01 m and a
// perspective from 1e-4 m to 1e7 m are accepted and draw finite images.
TEST(Robustness, RoundedViewsAndExtremeButSoundProjectionsAreAccepted) {
  Fixture f;
  set_utc(f, 1718964000.0);
  AtmoViewState rounded = view_at(47.26, 11.35, 900.0, 30.0, 5.0, 0);
  for (int i = 0; i < 12; ++i) rounded.view_from_world[i] += (i % 2 ? 1e-6 : -1e-6);
  AtmoViewState infinite = view_at(47.26, 11.35, 900.0, 30.0, 5.0, 0);
  const double t = 1.0 / std::tan(glm::radians(35.0)), near = 0.01;
  const double p[16] = {t / (double(kWidth) / kHeight), 0, 0, 0, 0, t, 0, 0, 0, 0, 0, -1, 0, 0, near, 0};
  std::copy(p, p + 16, infinite.clip_from_view);
  infinite.depth_convention = ATMO_DEPTH_REVERSED_ZERO_TO_ONE;
  AtmoViewState deep = view_at(47.26, 11.35, 900.0, 30.0, 5.0, 0);
  copy(glm::perspective(glm::radians(70.0), double(kWidth) / kHeight, 1e-4, 1e7), deep.clip_from_view);
  for (const AtmoViewState* vs : {&rounded, &infinite, &deep}) {
    ASSERT_EQ(f.plugin->api().set_view(f.view->handle(), vs), ATMO_SUCCESS) << f.context->last_error();
    f.target->bind();
    f.target->clear(0.0f, 0.0f, 0.0f, 1.0f);
    ASSERT_EQ(f.view->render(ATMO_PASS_SKY), ATMO_SUCCESS);
    EXPECT_EQ(bad_pixels(f.target->read_color()), 0u);
  }
}

namespace {

// A cumulus layer (procedural) at Innsbruck, in an array of `count` layers
// `stride` bytes apart, each in a heap block of exactly count * stride bytes
// (ASan sees any read past it).
struct LayerArray {
  std::vector<unsigned char> bytes;
  AtmoCloudsState state = atmo::make<AtmoCloudsState>(ATMO_TYPE_CLOUDS_STATE);
  LayerArray(uint32_t count, uint32_t stride, uint32_t layer_size) : bytes(size_t(count) * stride) {
    AtmoCloudLayer l = atmo::make<AtmoCloudLayer>(ATMO_TYPE_CLOUD_LAYER);
    l.type = ATMO_CLOUD_CUMULUS;
    l.coverage_oktas = 1;
    l.base_m = 1200.0;
    l.top_m = 1600.0;
    l.area_size_m = 500.0;  // the smallest: a quick build
    for (uint32_t i = 0; i < count; ++i) std::memcpy(&bytes[size_t(i) * stride], &l, std::min<size_t>(sizeof(l), stride));
    state.origin_geodetic[0] = 47.26;
    state.origin_geodetic[1] = 11.35;
    state.layers = reinterpret_cast<const AtmoCloudLayer*>(bytes.data());
    state.layer_count = count;
    state.layer_size = layer_size;
  }
  AtmoCloudLayer* layer(uint32_t i, uint32_t stride) { return reinterpret_cast<AtmoCloudLayer*>(&bytes[size_t(i) * stride]); }
};

// `count` lights 50 m north of the origin, `stride` bytes apart in an exactly sized block.
struct LightArray {
  std::vector<unsigned char> bytes;
  AtmoLightsState state = atmo::make<AtmoLightsState>(ATMO_TYPE_LIGHTS_STATE);
  LightArray(uint32_t count, uint32_t stride, uint32_t light_size) : bytes(size_t(count) * stride) {
    AtmoLightPoint p{};
    p.position_m[1] = 50.0;
    p.intensity_cd = 1000.0;
    p.color[0] = p.color[1] = p.color[2] = 1.0;
    for (uint32_t i = 0; i < count; ++i) std::memcpy(&bytes[size_t(i) * stride], &p, std::min<size_t>(sizeof(p), stride));
    state.world_frame = ATMO_WORLD_ENU;
    state.world_origin_geodetic[0] = 47.26;
    state.world_origin_geodetic[1] = 11.35;
    state.lights = reinterpret_cast<const AtmoLightPoint*>(bytes.data());
    state.light_count = count;
    state.light_size = light_size;
  }
};

struct CountingAllocator {
  int allocations = 0, deallocations = 0;
  size_t bytes = 0;
  std::vector<void*> live;
  static void* allocate(void* user, size_t size, size_t alignment) {
    auto* a = static_cast<CountingAllocator*>(user);
    void* p = std::aligned_alloc(alignment, (size + alignment - 1) / alignment * alignment);
    ++a->allocations;
    a->bytes += size;
    a->live.push_back(p);
    return p;
  }
  static void deallocate(void* user, void* p) {
    auto* a = static_cast<CountingAllocator*>(user);
    ++a->deallocations;
    a->live.erase(std::find(a->live.begin(), a->live.end(), p));
    std::free(p);
  }
};

struct LogLines {
  std::vector<std::string> lines;
  static void log(void* user, int32_t, const char* message) { static_cast<LogLines*>(user)->lines.push_back(message); }
  bool has(const std::string& text) const {
    return std::any_of(lines.begin(), lines.end(), [&](const std::string& l) { return l.find(text) != std::string::npos; });
  }
};

}  // namespace

// One convention for every array (atmo.h, ARRAYS): the stride is the
// `<element>_size` field beside the pointer, 0 the version-1 size, else a
// multiple of 8 in [version-1 size, ATMO_ARRAY_ELEMENT_SIZE_MAX]. Undersized,
// huge, wild and unaligned strides are refused with the field named, and no
// byte past count * stride is read (each array sits in a block of exactly that
// size; the ASan build must stay clean). Before, the cloud layers' stride was
// layers[0].header.struct_size and the lights' light_size was unbounded: a
// 1 MiB first struct_size or a 1 GiB light_size read far past the arrays.
TEST(Robustness, ArrayStridesAreBoundedWithOneConvention) {
  Fixture f;
  const auto& api = f.plugin->api();
  const AtmoContext ctx = f.context->handle();
  struct Case {
    const char* what;
    AtmoResult result;
    const char* message;
  };
  auto report = [&](const Case& c, AtmoResult r) {
    const std::string e = r == ATMO_SUCCESS ? "" : f.context->last_error();
    std::printf("[ robustness ] %-52s -> %s %s\n", c.what, f.plugin->result_string(r).c_str(), e.c_str());
    EXPECT_EQ(r, c.result) << c.what << ": " << e;
    if (c.message) {
      EXPECT_NE(e.find(c.message), std::string::npos) << c.what << ": " << e;
    }
  };
  // The version-1 strides (AtmoLightPoint grew flags after them: 104 bytes now).
  const uint32_t v1_layer = sizeof(AtmoCloudLayer), v1_light = 96u;
  ASSERT_EQ(v1_layer, 168u);
  ASSERT_EQ(sizeof(AtmoLightPoint), 104u);
  const uint32_t max = ATMO_ARRAY_ELEMENT_SIZE_MAX;
  {  // cloud layers: (count, stride of the bytes, layer_size field)
    struct LayerCase {
      Case c;
      uint32_t count, stride, layer_size;
      uint32_t first_struct_size;  // 0: as made
    };
    const LayerCase cases[] = {
        {{"layers: layer_size 0 (version 1), 2 layers", ATMO_SUCCESS, nullptr}, 2, v1_layer, 0, 0},
        {{"layers: grown stride 256, 2 layers", ATMO_SUCCESS, nullptr}, 2, 256, 256, 0},
        {{"layers: the largest stride, 2 layers", ATMO_SUCCESS, nullptr}, 2, max, max, 0},
        {{"layers: layer_size 100", ATMO_ERROR_STRUCT_TOO_SMALL, "AtmoCloudsState.layer_size is 100 bytes, version 1 needs 168"}, 2, 168, 100, 0},
        {{"layers: layer_size max + 8", ATMO_ERROR_OUT_OF_RANGE, "AtmoCloudsState.layer_size = 1032"}, 2, 168, max + 8, 0},
        {{"layers: layer_size 0xffffffff", ATMO_ERROR_OUT_OF_RANGE, "AtmoCloudsState.layer_size = 4294967295"}, 2, 168, 0xffffffffu, 0},
        {{"layers: layer_size 172 (not a multiple of 8)", ATMO_ERROR_OUT_OF_RANGE, "multiple of 8"}, 2, 172, 172, 0},
        {{"layers: first struct_size 1 MiB (the old stride)", ATMO_ERROR_OUT_OF_RANGE, "layers[0].header.struct_size = 1048576 is larger than AtmoCloudsState.layer_size (168)"}, 2, 168, 0, 1u << 20},
        {{"layers: first struct_size 176 over stride 168", ATMO_ERROR_OUT_OF_RANGE, "larger than AtmoCloudsState.layer_size"}, 1, 168, 168, 176},
    };
    for (const LayerCase& lc : cases) {
      LayerArray a(lc.count, lc.stride, lc.layer_size);
      if (lc.first_struct_size) a.layer(0, lc.stride)->header.struct_size = lc.first_struct_size;
      report(lc.c, api.set_clouds(ctx, &a.state));
    }
  }
  {  // lights
    struct LightCase {
      Case c;
      uint32_t count, stride, light_size;
    };
    const LightCase cases[] = {
        {{"lights: light_size 0 (version 1), 3 lights", ATMO_SUCCESS, nullptr}, 3, v1_light, 0},
        {{"lights: grown stride 128, 3 lights", ATMO_SUCCESS, nullptr}, 3, 128, 128},
        {{"lights: the largest stride, 3 lights", ATMO_SUCCESS, nullptr}, 3, max, max},
        {{"lights: light_size 64", ATMO_ERROR_STRUCT_TOO_SMALL, "AtmoLightsState.light_size is 64 bytes, version 1 needs 96"}, 3, 96, 64},
        {{"lights: light_size 1 GiB", ATMO_ERROR_OUT_OF_RANGE, "AtmoLightsState.light_size = 1073741824"}, 3, 96, 1u << 30},
        {{"lights: light_size 0xffffffff", ATMO_ERROR_OUT_OF_RANGE, "AtmoLightsState.light_size = 4294967295"}, 3, 96, 0xffffffffu},
        {{"lights: light_size 100 (not a multiple of 8)", ATMO_ERROR_OUT_OF_RANGE, "multiple of 8"}, 3, 100, 100},
    };
    for (const LightCase& lc : cases) {
      LightArray a(lc.count, lc.stride, lc.light_size);
      report(lc.c, api.set_lights(ctx, &a.state));
    }
  }
}

namespace {

// A host file service over one file's bytes, misbehaving on request.
struct HostFiles {
  enum Mode { kHonest, kReturnsMoreThanAsked, kNeverEnds } mode = kHonest;
  std::vector<unsigned char> content;
  size_t offset = 0;
  int opens = 0, closes = 0;
  uint64_t largest_request = 0;
  static void* open(void* user, const char*) {
    auto* h = static_cast<HostFiles*>(user);
    ++h->opens;
    h->offset = 0;
    return h;
  }
  static int64_t read(void* user, void*, void* buffer, uint64_t size) {
    auto* h = static_cast<HostFiles*>(user);
    h->largest_request = std::max(h->largest_request, size);
    if (h->mode == kReturnsMoreThanAsked) return static_cast<int64_t>(size) + 100;  // writes nothing
    if (h->mode == kNeverEnds) {
      std::memset(buffer, 0, static_cast<size_t>(size));
      return static_cast<int64_t>(size);
    }
    const size_t n = std::min<size_t>(static_cast<size_t>(size), h->content.size() - h->offset);
    std::memcpy(buffer, h->content.data() + h->offset, n);
    h->offset += n;
    return static_cast<int64_t>(n);
  }
  static void close(void* user, void*) { ++static_cast<HostFiles*>(user)->closes; }
};

std::vector<unsigned char> file_bytes(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  std::vector<unsigned char> out;
  if (!f) return out;
  unsigned char b[65536];
  size_t n;
  while ((n = std::fread(b, 1, sizeof(b), f)) > 0) out.insert(out.end(), b, b + n);
  std::fclose(f);
  return out;
}

}  // namespace

// The host's file service (atmo.h): a file_read that returns more than the
// buffer it was given fails the read (nothing past the buffer is used; before,
// the plugin copied that many bytes from its 64 KiB buffer), a file that never
// ends fails at ATMO_FILE_SIZE_MAX (before, the plugin read forever), and an
// honest one loads the VDB. Each open is closed.
TEST(Robustness, TheHostFileServiceIsBoundedByTheBufferAndTheSizeCap) {
  HostFiles files;
  files.content = file_bytes(std::string(ATMO_SOURCE_DIR) + "/config/scenarios/clouds/cumulus_single.vdb");
  ASSERT_GT(files.content.size(), 1000u);
  Fixture f;
  f.services.user = &files;
  f.services.file_open = &HostFiles::open;
  f.services.file_read = &HostFiles::read;
  f.services.file_close = &HostFiles::close;
  f.fresh_context();
  AtmoCloudLayer l = atmo::make<AtmoCloudLayer>(ATMO_TYPE_CLOUD_LAYER);
  l.type = ATMO_CLOUD_VDB_FILE;
  l.vdb_path = "clouds/cumulus_single.vdb";
  AtmoCloudsState s = atmo::make<AtmoCloudsState>(ATMO_TYPE_CLOUDS_STATE);
  s.origin_geodetic[0] = 47.26;
  s.origin_geodetic[1] = 11.35;
  s.layers = &l;
  s.layer_count = 1;
  const auto& api = f.plugin->api();

  files.mode = HostFiles::kReturnsMoreThanAsked;
  EXPECT_EQ(api.set_clouds(f.context->handle(), &s), ATMO_ERROR_IO);
  std::string e = f.context->last_error();
  std::printf("[ robustness ] file_read returns more than asked: %s\n", e.c_str());
  const std::string expected = "file_read returned " + std::to_string(files.largest_request + 100) +
                               " bytes for a buffer of " + std::to_string(files.largest_request);
  EXPECT_NE(e.find(expected), std::string::npos) << e;

  files.mode = HostFiles::kNeverEnds;
  EXPECT_EQ(api.set_clouds(f.context->handle(), &s), ATMO_ERROR_IO);
  e = f.context->last_error();
  std::printf("[ robustness ] a file that never ends: %s\n", e.c_str());
  EXPECT_NE(e.find("is larger than " + std::to_string(ATMO_FILE_SIZE_MAX) + " bytes"), std::string::npos) << e;

  files.mode = HostFiles::kHonest;
  EXPECT_EQ(api.set_clouds(f.context->handle(), &s), ATMO_SUCCESS) << f.context->last_error();
  EXPECT_EQ(files.opens, 3);
  EXPECT_EQ(files.closes, 3);
}

// What atmo.h says the host allocator serves: each context and view object,
// given back when destroyed; the tables and the frame's work use the C++ heap
// (so drawing adds no allocation through it).
TEST(Robustness, TheHostAllocatorServesTheContextAndViewObjectsAndBalances) {
  CountingAllocator counter;
  Fixture f;
  f.services.user = &counter;
  f.services.allocate = &CountingAllocator::allocate;
  f.services.deallocate = &CountingAllocator::deallocate;
  f.fresh_context();  // a context and one view through the allocator
  {
    atmo::View second(*f.context, 1);
    EXPECT_EQ(counter.allocations, 3);
    set_utc(f, 1718964000.0);
    second.set(view_at(47.26, 11.35, 900.0, 30.0, 5.0, 0));
    f.target->bind();
    EXPECT_EQ(second.render(ATMO_PASS_SKY), ATMO_SUCCESS);
    auto atm = atmo::make<AtmoAtmosphereState>(ATMO_TYPE_ATMOSPHERE_STATE);
    atm.visibility_m = 20000.0;
    f.context->set_atmosphere(atm);
    EXPECT_EQ(counter.allocations, 3) << "drawing and set_atmosphere allocate through the host";
  }
  EXPECT_EQ(counter.deallocations, 1);  // the second view
  f.view.reset();
  f.context.reset();
  std::printf("[ robustness ] host allocator: %d allocations (%zu bytes), %d deallocations\n", counter.allocations,
              counter.bytes, counter.deallocations);
  EXPECT_EQ(counter.allocations, 3);
  EXPECT_EQ(counter.deallocations, 3);
  EXPECT_TRUE(counter.live.empty());
  f.services.allocate = nullptr;
  f.services.deallocate = nullptr;
  f.services.user = nullptr;
}

// host_frame_number and channel_id name the frame and the view in the passes'
// log lines (atmo.h); application_name names the application in the stderr
// fallback's lines. Before, all three were stored and never used.
TEST(Robustness, FrameNumberChannelAndApplicationNameAppearInTheLogs) {
  LogLines log;
  Fixture f;
  f.services.user = &log;
  f.services.log = &LogLines::log;
  f.fresh_context();
  atmo::View view(*f.context, 7);
  set_utc(f, 1719010000.0 /* night */, 4242);
  auto fog = atmo::make<AtmoFogState>(ATMO_TYPE_FOG_STATE);
  fog.visibility_m = 400.0;
  f.context->set_fog(fog);
  LightArray lights(1, sizeof(AtmoLightPoint), sizeof(AtmoLightPoint));
  f.context->set_lights(lights.state);
  view.set(view_at(47.26, 11.35, 2.0, 0.0, 0.0, 0));
  f.target->bind();
  EXPECT_GE(view.render(ATMO_PASS_LIGHT_GLOWS), 0);
  for (const std::string& l : log.lines)
    if (l.find("frame 4242") != std::string::npos) std::printf("[ robustness ] log: %s\n", l.c_str());
  EXPECT_TRUE(log.has("frame 4242, channel 7: fog: ")) << "no glow pass log line names the frame and channel";
  f.services.log = nullptr;
  f.services.user = nullptr;

  // No log sink: errors go to stderr, naming the application.
  auto info = atmo::make<AtmoContextCreateInfo>(ATMO_TYPE_CONTEXT_CREATE_INFO);
  info.application_name = "robustness-test-app";
  AtmoContext quiet = nullptr;
  const auto& api = f.plugin->api();
  ASSERT_EQ(api.create_context(&info, &quiet), ATMO_SUCCESS);
  std::fflush(stderr);
  std::FILE* capture = std::tmpfile();
  ASSERT_NE(capture, nullptr);
  const int saved = dup(fileno(stderr));
  dup2(fileno(capture), fileno(stderr));
  auto bad = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
  bad.utc_posix_s = std::nan("");
  EXPECT_EQ(api.set_frame(quiet, &bad), ATMO_ERROR_NON_FINITE_VALUE);
  std::fflush(stderr);
  dup2(saved, fileno(stderr));
  close(saved);
  std::rewind(capture);
  char text[1024] = {};
  const size_t n = std::fread(text, 1, sizeof(text) - 1, capture);
  std::fclose(capture);
  const std::string got(text, n);
  std::printf("[ robustness ] stderr: %s", got.c_str());
  EXPECT_NE(got.find("[atmo] robustness-test-app: error: set_frame: AtmoFrameState.utc_posix_s"), std::string::npos)
      << got;
  api.destroy_context(quiet);
}
