// What a frame shows is a function of the inputs, the frame state and the
// view, not of the order views are drawn in nor of which channels share a
// context (a process): the same 3-channel flight (the Sun moving, so the
// clouds are relit on workers; the visibility changing mid-flight, so new
// tables are built on a worker; impostor clouds, updated from the eye) drawn
//   A: one context, its three views in the order 0, 1, 2;
//   B: one context, in the order 2, 0, 1;
//   C: three contexts of one view each (three processes, in one);
// gives bit-identical images of each channel in every frame, and equal
// get_state_hash values (docs/MULTI_CHANNEL.md). Also each state-hash part
// follows its input.
#include <glad/gl.h>

#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "plugin_gl_fixture.h"

namespace {

using namespace plugin_gl;

constexpr int kW = 96, kH = 64;
constexpr int kChannels = 3;
constexpr double kStartUtc = 1.72e9;  // 2024-07-10 09:20 UTC at Innsbruck: the Sun ~50 degrees up
constexpr int kFrames = 4 + ATMO_DEFERRED_FRAMES;
constexpr int kAirFrame = 2;  // the visibility changes at this frame: new tables from ATMO_DEFERRED_FRAMES later

struct Layout {
  std::vector<std::unique_ptr<atmo::Context>> contexts;
  std::vector<std::unique_ptr<atmo::View>> views;  // by channel
  std::vector<int> order;                          // channels in drawing order
};

class Flight {
 public:
  Flight() {
    std::string error;
    gl_ = HeadlessGl::create(HeadlessGl::Profile::Core, &error);
    if (!gl_) throw std::runtime_error(error);
    services_.gl_get_proc_address = &HeadlessGl::get_proc_address;
    plugin_ = std::make_unique<atmo::Plugin>(ATMO_PLUGIN_PATH);
    target_ = OffscreenTarget::create(kW, kH, &error);
    if (!target_) throw std::runtime_error(error);
  }

  std::unique_ptr<atmo::Context> context() {
    auto c = std::make_unique<atmo::Context>(*plugin_, &services_);
    c->gl_init();
    AtmoCloudLayer layer = atmo::make<AtmoCloudLayer>(ATMO_TYPE_CLOUD_LAYER);
    layer.type = ATMO_CLOUD_CUMULUS;
    layer.coverage_oktas = 3;
    layer.base_m = 1200.0;
    layer.top_m = 2000.0;
    layer.area_size_m = 5000.0;
    layer.area_centre_enu_m[1] = 5000.0;
    layer.seed = 5;
    AtmoCloudsState s = atmo::make<AtmoCloudsState>(ATMO_TYPE_CLOUDS_STATE);
    s.origin_geodetic[0] = 47.26;
    s.origin_geodetic[1] = 11.35;
    s.layers = &layer;
    s.layer_count = 1;
    s.draw_mode = ATMO_CLOUD_DRAW_IMPOSTORS;
    s.light_update_threshold_deg = 0.2;  // relit every few frames as the Sun moves
    EXPECT_EQ(c->set_clouds(s), ATMO_SUCCESS);
    return c;
  }

  // One context with every channel, or (per_channel) a context per channel.
  Layout layout(bool per_channel, std::vector<int> order) {
    Layout l;
    l.order = std::move(order);
    if (!per_channel) l.contexts.push_back(context());
    for (int ch = 0; ch < kChannels; ++ch) {
      if (per_channel) l.contexts.push_back(context());
      l.views.push_back(std::make_unique<atmo::View>(*l.contexts.back(), uint32_t(ch)));
    }
    return l;
  }

  // Frame k of the flight for every channel of `l`, in its order: images and state hashes by channel.
  void draw(Layout& l, int k, std::vector<std::vector<float>>* images, std::vector<AtmoStateHash>* hashes) {
    images->assign(kChannels, {});
    hashes->assign(kChannels, atmo::make<AtmoStateHash>(ATMO_TYPE_STATE_HASH));
    for (auto& c : l.contexts) {
      auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
      frame.host_frame_number = uint64_t(k);
      frame.utc_posix_s = kStartUtc + 90.0 * k;  // the Sun moves ~0.35 degrees a frame
      c->set_frame(frame);
      if (k == kAirFrame) {
        auto air = atmo::make<AtmoAtmosphereState>(ATMO_TYPE_ATMOSPHERE_STATE);
        air.visibility_m = 9000.0;
        c->set_atmosphere(air);
      }
    }
    for (int ch : l.order) {
      atmo::View& v = *l.views[size_t(ch)];
      const glm::dmat4 projection = glm::perspective(glm::radians(45.0), double(kW) / kH, 1.0, 1e5);
      AtmoViewState vs = innsbruck_view(1600.0, -40.0 + 40.0 * ch, 2.0, projection);
      vs.viewport[2] = kW;
      vs.viewport[3] = kH;
      vs.eye_geodetic[0] += 250.0 * k / 111180.0;  // north, 250 m a frame
      vs.exposure_scale = 1e-4;
      vs.output_encoding = ATMO_OUTPUT_DISPLAY_SRGB;
      v.set(vs);
      EXPECT_TRUE(v.state_hash(&(*hashes)[size_t(ch)]));
      target_->bind();
      glViewport(0, 0, kW, kH);
      glClearColor(0, 0, 0, 1);
      glClear(GL_COLOR_BUFFER_BIT);
      EXPECT_EQ(v.render(ATMO_PASS_SKY), ATMO_SUCCESS);
      v.render(ATMO_PASS_CLOUDS);
      glFinish();
      (*images)[size_t(ch)] = target_->read_color().rgba;
    }
  }

 private:
  std::unique_ptr<HeadlessGl> gl_;
  AtmoHostServices services_ = atmo::make<AtmoHostServices>(ATMO_TYPE_HOST_SERVICES);
  std::unique_ptr<atmo::Plugin> plugin_;
  std::unique_ptr<OffscreenTarget> target_;
};

const char* kPartName[ATMO_STATE_HASH_PART_COUNT] = {"frame", "air", "clouds", "fog", "lights", "occluders", "view"};

TEST(Determinism, ViewOrderAndContextsPerChannelChangeNoPixel) {
  Flight f;
  Layout a = f.layout(false, {0, 1, 2}), b = f.layout(false, {2, 0, 1}), c = f.layout(true, {0, 1, 2});
  std::vector<float> first_air[kChannels];
  bool air_changed_at_due = false;
  for (int k = 0; k < kFrames; ++k) {
    std::vector<std::vector<float>> ia, ib, ic;
    std::vector<AtmoStateHash> ha, hb, hc;
    f.draw(a, k, &ia, &ha);
    f.draw(b, k, &ib, &hb);
    f.draw(c, k, &ic, &hc);
    for (int ch = 0; ch < kChannels; ++ch) {
      EXPECT_TRUE(ia[size_t(ch)] == ib[size_t(ch)]) << "frame " << k << " channel " << ch << ": order 2, 0, 1";
      EXPECT_TRUE(ia[size_t(ch)] == ic[size_t(ch)]) << "frame " << k << " channel " << ch << ": a context each";
      for (const auto* h : {&hb, &hc}) {
        EXPECT_EQ((*h)[size_t(ch)].hash, ha[size_t(ch)].hash) << "frame " << k << " channel " << ch;
        for (int p = 0; p < ATMO_STATE_HASH_PART_COUNT; ++p)
          EXPECT_EQ((*h)[size_t(ch)].parts[p], ha[size_t(ch)].parts[p]) << "frame " << k << ": " << kPartName[p];
      }
      // Every channel shares the state; only the view part differs.
      EXPECT_EQ(ha[size_t(ch)].hash, ha[0].hash) << "frame " << k;
      if (ch > 0) {
        EXPECT_NE(ha[size_t(ch)].parts[ATMO_STATE_HASH_VIEW], ha[0].parts[ATMO_STATE_HASH_VIEW]);
      }
      EXPECT_EQ(ha[size_t(ch)].host_frame_number, uint64_t(k));
    }
    if (k == kAirFrame + int(ATMO_DEFERRED_FRAMES) - 1) {
      for (int ch = 0; ch < kChannels; ++ch) first_air[ch] = ia[size_t(ch)];
    }
    if (k == kAirFrame + int(ATMO_DEFERRED_FRAMES)) air_changed_at_due = ia[1] != first_air[1];
    std::printf("frame %2d: hash %016llx (air %016llx, clouds %016llx)\n", k,
                static_cast<unsigned long long>(ha[0].hash),
                static_cast<unsigned long long>(ha[0].parts[ATMO_STATE_HASH_AIR]),
                static_cast<unsigned long long>(ha[0].parts[ATMO_STATE_HASH_CLOUDS]));
  }
  EXPECT_TRUE(air_changed_at_due) << "the new visibility shows at its frame";
}

// Each part follows its own input, and only it.
TEST(Determinism, StateHashPartsFollowTheirInputs) {
  Fixture fx;
  fx.set_utc(kStartUtc);
  fx.view->set(innsbruck_view(100.0, 0.0, 0.0, glm::perspective(1.0, 1.5, 1.0, 1e5)));
  auto take = [&] {
    AtmoStateHash h;
    EXPECT_TRUE(fx.view->state_hash(&h));
    return h;
  };
  const AtmoStateHash h0 = take();
  EXPECT_EQ(take().hash, h0.hash) << "nothing changed";
  auto changed = [&](const AtmoStateHash& a, const AtmoStateHash& b) {
    std::vector<int> parts;
    for (int p = 0; p < ATMO_STATE_HASH_PART_COUNT; ++p)
      if (a.parts[p] != b.parts[p]) parts.push_back(p);
    return parts;
  };
  auto fog = atmo::make<AtmoFogState>(ATMO_TYPE_FOG_STATE);
  fog.extinction_per_m = 0.01;
  fx.context->set_fog(fog);
  const AtmoStateHash h1 = take();
  EXPECT_EQ(changed(h0, h1), std::vector<int>{ATMO_STATE_HASH_FOG});
  auto air = atmo::make<AtmoAtmosphereState>(ATMO_TYPE_ATMOSPHERE_STATE);
  air.visibility_m = 7000.0;
  fx.context->set_atmosphere(air);
  const AtmoStateHash h2 = take();
  EXPECT_EQ(changed(h1, h2), std::vector<int>{ATMO_STATE_HASH_AIR}) << "the air asked for, its tables due later";
  auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
  frame.utc_posix_s = kStartUtc;
  frame.host_frame_number = ATMO_DEFERRED_FRAMES;
  fx.context->set_frame(frame);
  const AtmoStateHash h3 = take();  // the tables switch now
  EXPECT_EQ(changed(h2, h3), (std::vector<int>{ATMO_STATE_HASH_FRAME, ATMO_STATE_HASH_AIR}));
  EXPECT_EQ(h3.host_frame_number, uint64_t(ATMO_DEFERRED_FRAMES));
  AtmoViewState vs = innsbruck_view(100.0, 10.0, 0.0, glm::perspective(1.0, 1.5, 1.0, 1e5));
  fx.view->set(vs);
  const AtmoStateHash h4 = take();
  EXPECT_EQ(changed(h3, h4), std::vector<int>{ATMO_STATE_HASH_VIEW});
  EXPECT_EQ(h4.hash, h3.hash) << "the view is not in the shared hash";
  // AtmoFrameState.deferred_frames: new tables asked for at frame 8 with 2 frames' room are in use at frame 10.
  auto at = [&](uint64_t n, uint32_t deferred) {
    auto fs = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
    fs.utc_posix_s = kStartUtc;
    fs.host_frame_number = n;
    fs.deferred_frames = deferred;
    fx.context->set_frame(fs);
    return take();
  };
  at(8, 2);
  air.visibility_m = 12000.0;
  fx.context->set_atmosphere(air);
  const AtmoStateHash asked = take();
  EXPECT_EQ(at(9, 2).parts[ATMO_STATE_HASH_AIR], asked.parts[ATMO_STATE_HASH_AIR]) << "not yet";
  EXPECT_NE(at(10, 2).parts[ATMO_STATE_HASH_AIR], asked.parts[ATMO_STATE_HASH_AIR]) << "switched at 8 + 2";
  auto wild = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
  wild.utc_posix_s = kStartUtc;
  wild.deferred_frames = 200000;
  EXPECT_EQ(fx.plugin->api().set_frame(fx.context->handle(), &wild), ATMO_ERROR_OUT_OF_RANGE);
  // A smaller (older) struct is refused like any other.
  AtmoStateHash small = atmo::make<AtmoStateHash>(ATMO_TYPE_STATE_HASH);
  small.header.struct_size = 8;
  EXPECT_EQ(fx.plugin->api().get_state_hash(fx.view->handle(), &small), ATMO_ERROR_STRUCT_TOO_SMALL);
}

}  // namespace
