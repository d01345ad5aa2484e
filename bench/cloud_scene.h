// cloud_scene.h — the host side shared by bench/clouds_bench.cpp and
// bench/clouds_error_cost.cpp: the plugin linked statically (atmo_negotiate,
// no dlopen), one context and one view on a headless GL context, an
// offscreen target, and the cloud pass driven through the C ABI. Static
// linking lets the benchmark reach the context's clouds (abi/objects.h) to
// keep exactly N instances of a generated layer and to read the renderer's
// CloudDrawStats (the numbers the plugin's "clouds: ..." debug line prints).
#pragma once

#include <glad/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <glm/gtc/matrix_transform.hpp>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "abi/objects.h"
#include "atmo/atmo.h"
#include "atmo/atmo.hpp"
#include "atmo_support/example_view.h"
#include "atmo_support/headless_gl.h"
#include "atmo_support/image.h"
#include "atmo_support/offscreen_target.h"

namespace cloud_bench {

constexpr double kOriginLatDeg = 47.26, kOriginLonDeg = 11.35;  // example_view_state's eye and the clouds' origin
constexpr double kUtcPosixS = 1.72e9;  // 2024-07-10 09:20 UTC: the Sun ~50 degrees up (tests/plugin_gl/cloud_impostor_test)
constexpr double kVerticalFovDeg = 60.0;

inline void log_to_stderr(void*, int32_t severity, const char* message) {
  if (severity >= ATMO_LOG_WARNING) std::fprintf(stderr, "[atmo] %s\n", message);
}

// The median (the mean of the two middle values for an even count); 0 for none.
inline double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

inline void copy(const glm::dmat4& m, double out[16]) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) out[c * 4 + r] = m[c][r];
}

// Heading 0 = north; +pitch looks up. View space: x right, y up, -z forward.
inline glm::dmat4 look(double heading_deg, double pitch_deg) {
  const double h = glm::radians(heading_deg), p = glm::radians(pitch_deg);
  const glm::dvec3 forward(std::sin(h) * std::cos(p), std::cos(h) * std::cos(p), std::sin(p));
  return glm::lookAt(glm::dvec3(0.0), forward, glm::dvec3(0, 0, 1));
}

// Where the camera is, in the clouds' ENU frame (origin at kOrigin*, height 0): metres east, north, up.
struct Camera {
  double east_m = 0.0, north_m = 0.0, height_m = 1000.0;
  double pitch_deg = 0.0;
};

class Host {
 public:
  Host(int width, int height) : width_(width), height_(height) {
    std::string error;
    gl_ = atmo::support::HeadlessGl::create(atmo::support::HeadlessGl::Profile::Core, &error);
    if (!gl_) throw std::runtime_error("no headless GL context: " + error);
    target_ = atmo::support::OffscreenTarget::create(width, height, &error);
    if (!target_) throw std::runtime_error("offscreen target: " + error);
    // Host depth at the far plane everywhere: no geometry, but the aerial
    // perspective pass runs (and builds its volume, as in a host's frame,
    // before the clouds pass that samples it).
    far_depth_ = atmo::support::make_depth_texture(width, height,
                                                   std::vector<float>(size_t(width) * size_t(height), 1.0f));
    auto info = atmo::make<AtmoNegotiateInfo>(ATMO_TYPE_NEGOTIATE_INFO);
    info.min_interface_version = ATMO_INTERFACE_VERSION_1;
    info.max_interface_version = ATMO_INTERFACE_VERSION_CURRENT;
    info.host_name = "atmo clouds bench";
    api_.header = ATMO_HEADER(ATMO_TYPE_PLUGIN_API, AtmoPluginApi);
    check(atmo_negotiate(&info, &api_), "atmo_negotiate");
    services_.log = &log_to_stderr;
    services_.gl_get_proc_address = &atmo::support::HeadlessGl::get_proc_address;
    auto create = atmo::make<AtmoContextCreateInfo>(ATMO_TYPE_CONTEXT_CREATE_INFO);
    create.services = &services_;
    check(api_.create_context(&create, &ctx_), "create_context");
    check(api_.gl_init(ctx_), "gl_init");
    auto view_info = atmo::make<AtmoViewCreateInfo>(ATMO_TYPE_VIEW_CREATE_INFO);
    check(api_.create_view(ctx_, &view_info, &view_), "create_view");
    auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
    frame.utc_posix_s = kUtcPosixS;
    check(api_.set_frame(ctx_, &frame), "set_frame");
    glGenQueries(1, &query_);
  }
  ~Host() {
    glDeleteQueries(1, &query_);
    glDeleteTextures(1, &far_depth_);
    api_.destroy_view(view_);
    api_.gl_shutdown(ctx_);
    api_.destroy_context(ctx_);
  }
  Host(const Host&) = delete;
  Host& operator=(const Host&) = delete;

  int width() const { return width_; }
  int height() const { return height_; }
  AtmoContext_T* context() { return ctx_; }
  atmo::support::OffscreenTarget& target() { return *target_; }
  const atmo::support::HeadlessGl& gl() const { return *gl_; }

  void check(AtmoResult r, const char* what) const {
    if (r < 0)
      throw std::runtime_error(std::string(what) + ": " + api_.result_string(r) + ": " +
                               (ctx_ ? api_.last_error(ctx_) : ""));
  }

  void set_utc(double utc_posix_s) {
    utc_posix_s_ = utc_posix_s;
    auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
    frame.utc_posix_s = utc_posix_s;
    frame.host_frame_number = frame_number_;
    check(api_.set_frame(ctx_, &frame), "set_frame");
  }
  // The next frame (host_frame_number + 1), at the same time.
  void next_frame() {
    ++frame_number_;
    set_utc(utc_posix_s_);
  }
  // The views' AtmoViewState.cloud_quality from the next set_view on.
  void set_cloud_quality(uint32_t quality) { cloud_quality_ = quality; }

  // The Sun's apparent elevation at the view's eye (set_view first), degrees.
  double sun_elevation_deg() {
    auto l = atmo::make<AtmoLighting>(ATMO_TYPE_LIGHTING);
    check(api_.get_lighting(view_, &l), "get_lighting");
    return glm::degrees(l.sun_elevation_rad);
  }

  // set_clouds through the ABI (the layers and knobs as a host gives them).
  void set_clouds(const AtmoCloudsState& s) { check(api_.set_clouds(ctx_, &s), "set_clouds"); }

  // Keeps the `n` instances of the current field nearest to the camera whose
  // bounding spheres lie wholly inside its view frustum (so all n are in view
  // at `cam`), drops the rest, and bumps the field's versions as set_clouds
  // does (the renderer re-uploads and starts its impostors over). Returns how
  // many were kept (< n when the layer has too few in view).
  size_t keep_nearest_in_view(size_t n, const Camera& cam) {
    atmo::abi::ContextClouds& c = ctx_->clouds;
    const glm::dvec3 eye(cam.east_m, cam.north_m, cam.height_m);
    const glm::dmat3 view_from_enu(look(0.0, cam.pitch_deg));
    const double ty = std::tan(glm::radians(kVerticalFovDeg / 2)), tx = ty * double(width_) / height_;
    const double cx = std::cos(std::atan(tx)), cy = std::cos(std::atan(ty));
    std::vector<std::pair<double, size_t>> candidates;
    for (size_t i = 0; i < c.field.instances.size(); ++i) {
      const atmo::clouds::CloudInstance& in = c.field.instances[i];
      const atmo::clouds::CloudVolume& v = c.field.prototypes[size_t(in.prototype)];
      const glm::dvec3 rel = v.centre_at(in.origin_enu_m) - eye;
      const glm::dvec3 p = view_from_enu * rel;
      const double d = -p.z, r = v.bounding_radius_m();
      // Distance to the side planes of the frustum (positive inside) > r.
      if (d <= r || (d * tx - std::abs(p.x)) * cx <= r || (d * ty - std::abs(p.y)) * cy <= r) continue;
      candidates.push_back({glm::length(rel), i});
    }
    std::sort(candidates.begin(), candidates.end());
    candidates.resize(std::min(n, candidates.size()));
    std::vector<atmo::clouds::CloudInstance> kept;
    for (const auto& k : candidates) kept.push_back(c.field.instances[k.second]);
    c.field.instances = std::move(kept);
    c.ray_index = atmo::clouds::build_cloud_ray_index(c.field);  // as build_clouds
    // As build_clouds: the light is taken at the clouds' mean centre height.
    c.mean_centre_height_m = 0.0;
    for (const atmo::clouds::CloudInstance& i : c.field.instances)
      c.mean_centre_height_m += c.field.prototypes[size_t(i.prototype)].centre_at(i.origin_enu_m).z;
    c.mean_centre_height_m /= double(std::max<size_t>(1, c.field.instances.size()));
    ++c.version;
    c.field_version = c.version;
    return c.field.instances.size();
  }

  size_t instance_count() const { return ctx_->clouds.field.instances.size(); }

  void set_view(const Camera& cam, uint32_t encoding = ATMO_OUTPUT_DISPLAY_SRGB) {
    AtmoViewState vs = atmo::support::example_view_state(width_, height_, far_depth_, cam.height_m);
    copy(look(0.0, cam.pitch_deg), vs.view_from_world);
    copy(glm::perspective(glm::radians(kVerticalFovDeg), double(width_) / height_, 1.0, 1e5), vs.clip_from_view);
    // ENU offsets to latitude and longitude (tens of km: the local radii suffice).
    vs.eye_geodetic[0] += cam.north_m / 111180.0;
    vs.eye_geodetic[1] += cam.east_m / (111320.0 * std::cos(glm::radians(kOriginLatDeg)));
    vs.exposure_scale = 1e-4;
    vs.output_encoding = encoding;
    vs.cloud_quality = cloud_quality_;
    check(api_.set_view(view_, &vs), "set_view");
  }

  AtmoResult render(AtmoPassKind pass) {
    auto info = atmo::make<AtmoPassInfo>(ATMO_TYPE_PASS_INFO);
    info.pass = static_cast<uint32_t>(pass);
    AtmoResult r = api_.render_pass(view_, &info);
    check(r, "render_pass");
    return r;
  }

  // The host's frame before the clouds: clear, sky, aerial perspective (untimed).
  void draw_sky() {
    target_->bind();
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    render(ATMO_PASS_SKY);
    render(ATMO_PASS_AERIAL_PERSPECTIVE);
  }

  // The clouds pass alone: wall time from a drained queue to glFinish, ms (on
  // llvmpipe rasterisation is deferred, so a timer query can miss it); the
  // GL timer query's value in *query_ms.
  double clouds_ms(double* query_ms = nullptr) { return pass_ms(ATMO_PASS_CLOUDS, query_ms); }

  // One pass alone, timed as clouds_ms.
  double pass_ms(AtmoPassKind pass, double* query_ms = nullptr) {
    glFinish();
    const auto start = std::chrono::steady_clock::now();
    glBeginQuery(GL_TIME_ELAPSED, query_);
    render(pass);
    glEndQuery(GL_TIME_ELAPSED);
    glFinish();
    const auto end = std::chrono::steady_clock::now();
    GLuint64 ns = 0;
    glGetQueryObjectui64v(query_, GL_QUERY_RESULT, &ns);
    if (query_ms) *query_ms = double(ns) * 1e-6;
    return std::chrono::duration<double, std::milli>(end - start).count();
  }

  // A whole frame: sky and aerial perspective, then the timed clouds pass.
  double frame(const Camera& cam, double* query_ms = nullptr) {
    set_view(cam);
    draw_sky();
    return clouds_ms(query_ms);
  }

  atmo::support::Image read() const { return target_->read_color(); }
  const atmo::gl::CloudDrawStats& stats() const { return ctx_->cloud_renderer.last_stats(); }
  size_t impostor_bytes() const { return ctx_->cloud_renderer.impostor_bytes(); }

 private:
  int width_, height_;
  std::unique_ptr<atmo::support::HeadlessGl> gl_;
  std::unique_ptr<atmo::support::OffscreenTarget> target_;
  GLuint far_depth_ = 0, query_ = 0;
  double utc_posix_s_ = kUtcPosixS;
  uint64_t frame_number_ = 0;
  uint32_t cloud_quality_ = ATMO_CLOUD_QUALITY_DEFAULT;
  AtmoPluginApi api_{};
  AtmoHostServices services_ = atmo::make<AtmoHostServices>(ATMO_TYPE_HOST_SERVICES);
  AtmoContext ctx_ = nullptr;
  AtmoView view_ = nullptr;
};

// A procedural layer: its square `area_m` a side centred `north_m` north of the clouds' origin.
inline AtmoCloudLayer make_layer(uint32_t type, uint32_t oktas, double base_m, double top_m, double area_m,
                                 double north_m, uint32_t seed) {
  AtmoCloudLayer l = atmo::make<AtmoCloudLayer>(ATMO_TYPE_CLOUD_LAYER);
  l.type = type;
  l.coverage_oktas = oktas;
  l.base_m = base_m;
  l.top_m = top_m;
  l.area_size_m = area_m;
  l.area_centre_enu_m[1] = north_m;
  l.seed = seed;
  return l;
}

// setup: AtmoCloudSetup (the accuracy benches wait: each frame a function of its inputs).
inline AtmoCloudsState clouds_state(const AtmoCloudLayer* layer, uint32_t draw_mode,
                                    uint32_t setup = ATMO_CLOUD_SETUP_WAIT) {
  AtmoCloudsState s = atmo::make<AtmoCloudsState>(ATMO_TYPE_CLOUDS_STATE);
  s.setup = setup;
  s.origin_geodetic[0] = kOriginLatDeg;
  s.origin_geodetic[1] = kOriginLonDeg;
  s.layers = layer;
  s.layer_count = layer ? 1 : 0;
  s.draw_mode = draw_mode;
  return s;
}

}  // namespace cloud_bench
