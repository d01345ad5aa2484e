#include "sample_renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <string_view>

#include <glad/gl.h>

#include "atmo_host_scene/depth_setup.h"
#include "atmo_host_scene/gl_program.h"
#include "atmo_host_scene/light_layouts.h"
#include "mesh.h"
#include "sphere_json.h"

namespace atmo::sample::embedded_glsl {
std::string_view find(std::string_view path);
}

namespace atmo::sample {

namespace hs = atmo::host_scene;

namespace {

constexpr AtmoResult kNotRun = INT32_MIN;
constexpr double kNearM = 1.0;
constexpr double kFarM = 200000.0;

const char* kToneMapVertex = R"(
void main() {
  // One triangle covering the viewport.
  vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
)";

// The plugin's display encoding (exposure is already in the HDR values):
// host_sdk/include/atmo/atmo_tone_map.glsl, embedded at build time, goes first.
const char* kToneMapFragment = R"(
uniform sampler2D u_hdr;
layout(location = 0) out vec4 o_color;
void main() {
  o_color = vec4(atmo_display_srgb(texelFetch(u_hdr, ivec2(gl_FragCoord.xy), 0).rgb), 1.0);
}
)";

// Used when the plugin gives no lighting, so the terrain still shows.
hs::SceneLighting fallback_lighting() {
  hs::SceneLighting l;
  l.sun_direction_enu = glm::normalize(glm::dvec3(-0.5, -0.5, 0.7));
  l.sun_illuminance_lux = glm::dvec3(100000.0);
  l.sky_ambient_lux = glm::dvec3(15000.0);
  return l;
}

}  // namespace

const char* section_name(int section) {
  static const char* const names[kSectionCount] = {"terrain",     "sky occlusion", "objects",     "sky",
                                                   "aerial perspective", "night sky", "clouds", "light glows",
                                                   "light points", "tone map"};
  return section >= 0 && section < kSectionCount ? names[section] : "?";
}

int section_pass(int section) {
  switch (section) {
    case kSectionSkyOcclusion: return ATMO_PASS_SKY_OCCLUSION;
    case kSectionSky: return ATMO_PASS_SKY;
    case kSectionAerialPerspective: return ATMO_PASS_AERIAL_PERSPECTIVE;
    case kSectionNightSky: return ATMO_PASS_NIGHT_SKY;
    case kSectionClouds: return ATMO_PASS_CLOUDS;
    case kSectionLightGlows: return ATMO_PASS_LIGHT_GLOWS;
    case kSectionLightPoints: return ATMO_PASS_LIGHT_POINTS;
  }
  return -1;
}

SampleRenderer::SampleRenderer(const std::string& plugin_path, AtmoGlProcLoader loader, bool verbose)
    : verbose_(verbose) {
  plugin_ = std::make_unique<atmo::Plugin>(plugin_path, "atmo-sample-host");
  auto services = atmo::make<AtmoHostServices>(ATMO_TYPE_HOST_SERVICES);
  services.user = this;
  services.log = &SampleRenderer::log_callback;
  // The plugin loads GL through the host's loader (copied at create_context).
  services.gl_get_proc_address = loader;
  context_ = std::make_unique<atmo::Context>(*plugin_, &services);
}

SampleRenderer::~SampleRenderer() {
  view_.reset();
  context_.reset();
  plugin_.reset();
}

void SampleRenderer::log_callback(void* user, int32_t severity, const char* message) {
  auto* self = static_cast<SampleRenderer*>(user);
  if (severity >= ATMO_LOG_WARNING || self->verbose_) {
    std::fprintf(stderr, "[atmo %s] %s\n", atmo::log_severity_name(severity), message ? message : "");
  }
  if (severity >= ATMO_LOG_ERROR) {
    const std::lock_guard<std::mutex> lock(self->log_mutex_);
    self->logged_errors_.push_back(std::string("log (") + atmo::log_severity_name(severity) + "): " + (message ? message : ""));
  }
  // The light passes' counts: "frame N, channel C: light points: ..." (abi/entry/fog.cpp). Kept per frame.
  static const char* const kinds[kLightDebugCount] = {"light clusters: ", "fog: ", "light points: "};
  const char* body = severity == ATMO_LOG_DEBUG && message ? std::strstr(message, ": ") : nullptr;
  if (!body || std::strncmp(message, "frame ", 6) != 0) return;
  body += 2;
  for (int k = 0; k < kLightDebugCount; ++k) {
    if (std::strncmp(body, kinds[k], std::strlen(kinds[k])) == 0) {
      const std::lock_guard<std::mutex> lock(self->log_mutex_);
      self->light_debug_[static_cast<size_t>(k)] = body;
    }
  }
}

std::vector<std::string> SampleRenderer::take_logged_errors() {
  const std::lock_guard<std::mutex> lock(log_mutex_);
  std::vector<std::string> out;
  out.swap(logged_errors_);
  return out;
}

bool SampleRenderer::gl_init(uint64_t terrain_seed, std::string* error) {
  try {
    context_->gl_init();
    view_ = std::make_unique<atmo::View>(*context_, 0);
  } catch (const atmo::Error& e) {
    if (error) *error = e.what();
    return false;
  }
  hs::TerrainOptions options;
  options.seed = terrain_seed;
  options.draw_light_points = false;  // the plugin's light points pass draws them
  terrain_ = std::make_unique<hs::Terrain>(options);
  if (!terrain_->gl_init(error)) return false;
  const std::string fragment = std::string(embedded_glsl::find("atmo/atmo_tone_map.glsl")) + kToneMapFragment;
  tone_map_program_ = hs::build_program(kToneMapVertex, fragment.c_str(), "", "sample tone map", error);
  if (!tone_map_program_) return false;
  glGenVertexArrays(1, &empty_vao_);
  timers_.gl_init(kSectionCount);
  return true;
}

void SampleRenderer::gl_shutdown() {
  timers_.gl_shutdown();
  release_targets();
  if (tone_map_program_) glDeleteProgram(tone_map_program_);
  if (empty_vao_) glDeleteVertexArrays(1, &empty_vao_);
  tone_map_program_ = empty_vao_ = 0;
  if (terrain_) terrain_->gl_shutdown();
  object_gl_.gl_shutdown();
  view_.reset();
  try {
    context_->gl_shutdown();
  } catch (const atmo::Error& e) {
    std::fprintf(stderr, "atmo-sample-host: %s\n", e.what());
  }
}

void SampleRenderer::release_targets() {
  if (scene_fbo_) glDeleteFramebuffers(1, &scene_fbo_);
  if (atmo_fbo_) glDeleteFramebuffers(1, &atmo_fbo_);
  if (hdr_color_) glDeleteTextures(1, &hdr_color_);
  if (depth_) glDeleteTextures(1, &depth_);
  scene_fbo_ = atmo_fbo_ = hdr_color_ = depth_ = 0;
  target_width_ = target_height_ = 0;
}

bool SampleRenderer::ensure_targets(int width, int height, std::string* error) {
  if (width == target_width_ && height == target_height_ && scene_fbo_) return true;
  release_targets();
  auto make_texture = [&](GLenum internal_format, GLenum format, GLenum type) {
    GLuint texture = 0;
    glGenTextures(1, &texture);
    glBindTexture(GL_TEXTURE_2D, texture);
    glTexImage2D(GL_TEXTURE_2D, 0, static_cast<GLint>(internal_format), width, height, 0, format, type, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glBindTexture(GL_TEXTURE_2D, 0);
    return texture;
  };
  hdr_color_ = make_texture(GL_RGBA16F, GL_RGBA, GL_HALF_FLOAT);
  depth_ = make_texture(GL_DEPTH_COMPONENT32F, GL_DEPTH_COMPONENT, GL_FLOAT);

  glGenFramebuffers(1, &scene_fbo_);
  glBindFramebuffer(GL_FRAMEBUFFER, scene_fbo_);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, hdr_color_, 0);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, depth_, 0);
  const GLenum scene_status = glCheckFramebufferStatus(GL_FRAMEBUFFER);

  glGenFramebuffers(1, &atmo_fbo_);
  glBindFramebuffer(GL_FRAMEBUFFER, atmo_fbo_);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, hdr_color_, 0);
  const GLenum atmo_status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);

  if (scene_status != GL_FRAMEBUFFER_COMPLETE || atmo_status != GL_FRAMEBUFFER_COMPLETE) {
    if (error) {
      char text[128];
      std::snprintf(text, sizeof text, "HDR framebuffer incomplete (0x%04x, 0x%04x)", scene_status, atmo_status);
      *error = text;
    }
    release_targets();
    return false;
  }
  target_width_ = width;
  target_height_ = height;
  return true;
}

bool SampleRenderer::load_objects(const std::string& dir, std::string* error) {
  object_meshes_.clear();
  object_mesh_.clear();
  object_spheres_.clear();
  objects_loaded_ = false;
  const char* const stems[] = {"aircraft", "vehicle", "building"};
  try {
    for (const char* stem : stems)
      object_meshes_.push_back(spheres::read_mesh((std::filesystem::path(dir) / (std::string(stem) + ".obj")).string()));
    for (const ApronObject& o : apron_objects()) {
      size_t mesh = 0;
      while (std::string(stems[mesh]) != o.stem) ++mesh;
      object_mesh_.push_back(mesh);
      const spheres::SphereSet set =
          spheres::read_sphere_set((std::filesystem::path(dir) / (std::string(o.stem) + ".spheres.json")).string());
      object_spheres_.push_back(hs::occluder_spheres(set));
    }
  } catch (const std::exception& e) {
    if (error) *error = e.what();
    return false;
  }
  std::vector<const spheres::TriangleMesh*> meshes;
  for (const spheres::TriangleMesh& m : object_meshes_) meshes.push_back(&m);
  if (!object_gl_.gl_init(meshes, error)) return false;
  objects_loaded_ = true;
  return true;
}

std::vector<hs::ObjectInstance> SampleRenderer::apron_instances(uint64_t frame_number) const {
  std::vector<hs::ObjectInstance> out;
  const std::vector<ApronObject>& apron = apron_objects();
  for (size_t i = 0; i < apron.size(); ++i) {
    const ApronObject o = i == kApronMovingVehicle ? apron_vehicle_pose(frame_number) : apron[i];
    const double east = o.position_enu_m.x, north = o.position_enu_m.y;
    const glm::dvec3 p(east, north, terrain_->height_at(east, north) - hs::curvature_drop_m(east, north));
    hs::ObjectInstance instance;
    instance.mesh = object_mesh_.at(i);
    instance.enu_from_object = hs::enu_from_object_pose(p, o.heading_deg);
    instance.albedo = o.albedo;
    out.push_back(instance);
  }
  return out;
}

void SampleRenderer::send_occluders(const SceneSettings& settings, uint64_t frame_number, FrameReport* report) {
  const bool wanted = objects_loaded_ && settings.objects == ObjectsChoice::Apron && settings.object_shadows;
  if (!wanted) {
    if (occluders_sent_) context_->check(api().set_occluders(context_->handle(), nullptr), "set_occluders");
    occluders_sent_ = false;
    return;
  }
  if (!api().set_occluders) throw atmo::Error(ATMO_ERROR_INCOMPATIBLE_VERSION, "set_occluders: the plugin predates sky occlusion (not in its table)");
  const std::vector<hs::ObjectInstance> instances = apron_instances(frame_number);
  const uint32_t flags = settings.object_bounce ? 0u : static_cast<uint32_t>(ATMO_OCCLUSION_NO_BOUNCE);
  // The ENU frame of the airfield datum, as the view's (make_view_state).
  const hs::Geodetic& o = settings.origin;
  const bool moved = o.latitude_deg != occluders_origin_.latitude_deg ||
                     o.longitude_deg != occluders_origin_.longitude_deg || o.height_m != occluders_origin_.height_m;
  if (!occluders_sent_ || flags != occluder_flags_ || moved) {
    std::vector<AtmoOccluderObject> objects;
    for (size_t i = 0; i < instances.size(); ++i) {
      AtmoOccluderObject object{};
      object.spheres = object_spheres_[i].data();
      object.sphere_count = static_cast<uint32_t>(object_spheres_[i].size());
      object.sphere_size = sizeof(AtmoOccluderSphere);
      for (int c = 0; c < 3; ++c) object.albedo[c] = instances[i].albedo[c];
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) object.world_from_object[c * 4 + r] = instances[i].enu_from_object[c][r];
      objects.push_back(object);
    }
    auto state = atmo::make<AtmoOccludersState>(ATMO_TYPE_OCCLUDERS_STATE);
    state.world_frame = ATMO_WORLD_ENU;
    state.object_size = sizeof(AtmoOccluderObject);
    state.world_origin_geodetic[0] = o.latitude_deg;
    state.world_origin_geodetic[1] = o.longitude_deg;
    state.world_origin_geodetic[2] = o.height_m;
    state.objects = objects.data();
    state.object_count = static_cast<uint32_t>(objects.size());
    state.flags = flags;
    context_->check(api().set_occluders(context_->handle(), &state), "set_occluders");
    occluders_sent_ = true;
    occluder_flags_ = flags;
    occluders_origin_ = o;
  } else {
    // Each frame only the driving van moves: its pose alone, without its spheres.
    double pose[16];
    const glm::dmat4& m = instances[kApronMovingVehicle].enu_from_object;
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) pose[c * 4 + r] = m[c][r];
    auto poses = atmo::make<AtmoOccluderPoses>(ATMO_TYPE_OCCLUDER_POSES);
    poses.first = static_cast<uint32_t>(kApronMovingVehicle);
    poses.count = 1;
    poses.world_from_object = pose;
    context_->check(api().set_occluder_poses(context_->handle(), &poses), "set_occluder_poses");
  }
  report->occluders = static_cast<uint32_t>(instances.size());
}

bool SampleRenderer::set_clouds(const SceneSettings& settings, std::string* message) {
  // The one place the weather becomes an AtmoCloudsState (window and headless).
  const CloudSettings& clouds = settings.clouds;
  std::vector<std::string> paths(clouds.layers.size());
  std::vector<AtmoCloudLayer> layers;
  for (size_t i = 0; i < clouds.layers.size(); ++i) {
    const CloudLayerSettings& in = clouds.layers[i];
    auto l = atmo::make<AtmoCloudLayer>(ATMO_TYPE_CLOUD_LAYER);
    l.type = static_cast<uint32_t>(in.type);
    if (in.type == ATMO_CLOUD_VDB_FILE) {
      // Relative to the working directory (the plugin would read it next to libatmo.so).
      std::error_code ignored;
      paths[i] = in.vdb_path.empty() ? in.vdb_path : std::filesystem::absolute(in.vdb_path, ignored).string();
      l.vdb_path = paths[i].c_str();
      l.vdb_grid = in.vdb_grid.empty() ? nullptr : in.vdb_grid.c_str();
      l.position_enu_m[0] = in.area_east_km * 1000.0;
      l.position_enu_m[1] = in.area_north_km * 1000.0;
      l.position_enu_m[2] = in.base_m;
    } else {
      l.coverage_oktas = in.coverage_oktas;
      l.base_m = in.base_m;
      l.top_m = in.top_m;
      l.area_centre_enu_m[0] = in.area_east_km * 1000.0;
      l.area_centre_enu_m[1] = in.area_north_km * 1000.0;
      l.area_size_m = in.area_size_km * 1000.0;
      l.seed = in.seed;
    }
    layers.push_back(l);
  }
  auto state = atmo::clouds_state(settings.origin.latitude_deg, settings.origin.longitude_deg,
                                  settings.origin.height_m, layers.data(), static_cast<uint32_t>(layers.size()));
  state.draw_mode = static_cast<uint32_t>(clouds.draw_mode);
  state.setup = static_cast<uint32_t>(clouds.setup);
  state.march_resolution_divisor = clouds.march_resolution_divisor;

  const auto start = std::chrono::steady_clock::now();
  size_t logged_before = 0;
  {
    const std::lock_guard<std::mutex> lock(log_mutex_);
    logged_before = logged_errors_.size();
  }
  // The plugin's error-level log lines of a refused call are said in *message: not a frame's errors.
  const auto refused = [&](std::string text) {
    *message = std::move(text);
    const std::lock_guard<std::mutex> lock(log_mutex_);
    logged_errors_.resize(std::min(logged_errors_.size(), logged_before));
    return false;
  };
  try {
    const AtmoResult r = context_->set_clouds(state);
    // A file that failed to load (the plugin logged each one; last_error names the first).
    if (r < 0) return refused("set_clouds: " + plugin_->result_string(r) + ": " + context_->last_error());
  } catch (const std::exception& e) {  // atmo::Error (refused), or a plugin without clouds
    return refused(e.what());
  }
  char text[96];
  std::snprintf(text, sizeof text, "set_clouds: %zu layer(s) in %.2f s", layers.size(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  *message = text;
  return true;
}

std::vector<AtmoLightPoint> SampleRenderer::draped(std::vector<AtmoLightPoint> lights) const {
  // The layouts stand on the datum plane; this host's ground has hills and
  // falls away with the Earth's curvature, as the terrain's own lights do.
  for (AtmoLightPoint& l : lights) {
    const double east = l.position_m[0], north = l.position_m[1];
    l.position_m[2] += terrain_->height_at(east, north) - hs::curvature_drop_m(east, north);
  }
  return lights;
}

void SampleRenderer::send_lights(const SceneSettings& settings, FrameReport* report) {
  // Group 0: the runway's or the airport's lights; group 1: the town's. A
  // group is the host's unit of change: the town's slider re-sends only it.
  const auto group0 = [](LightsChoice c) {
    return c == LightsChoice::AirportTown ? LightsChoice::Airport : c;
  };
  const auto town = [](const SceneSettings& s) { return s.lights == LightsChoice::AirportTown ? s.town_lights : 0u; };
  // A new airfield datum moves every light (the groups' ENU origin).
  const hs::Geodetic& o = settings.origin;
  const bool moved = o.latitude_deg != last_lights_origin_.latitude_deg ||
                     o.longitude_deg != last_lights_origin_.longitude_deg || o.height_m != last_lights_origin_.height_m;
  const bool send0 = !lights_sent_ || moved || group0(settings.lights) != group0(last_lights_);
  const bool send1 = !lights_sent_ || moved || town(settings) != last_town_lights_;
  if (!send0 && !send1) return;
  std::vector<AtmoLightPoint> lights[2];
  if (send0 && settings.lights == LightsChoice::Runway) lights[0] = terrain_->atmo_light_points();
  if (send0 && group0(settings.lights) == LightsChoice::Airport)
    lights[0] = draped(hs::airport_lights(sample_airport()));
  if (send1 && town(settings) > 0) lights[1] = draped(hs::town_lights(sample_town(town(settings))));
  // Group 0 first: the town's largest count leaves room for the airport only
  // (all groups together hold at most ATMO_LIGHTS_MAX).
  const auto start = std::chrono::steady_clock::now();
  for (uint32_t g = 0; g < 2; ++g) {
    if (!(g == 0 ? send0 : send1)) continue;
    context_->set_lights(atmo::lights_state(g, lights[g], settings.origin.latitude_deg, settings.origin.longitude_deg,
                                            settings.origin.height_m));
    group_lights_[g] = static_cast<uint32_t>(lights[g].size());
  }
  report->set_lights_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  lights_sent_ = true;
  last_lights_origin_ = o;
  last_lights_ = settings.lights;
  last_town_lights_ = town(settings);
}

FrameReport SampleRenderer::render_frame(const SceneSettings& settings, uint64_t frame_number, unsigned target_fbo,
                                         int width, int height, bool wait_for_timings, bool finish_sections) {
  const auto cpu_start = std::chrono::steady_clock::now();
  FrameReport report;
  report.pass_results.fill(kNotRun);
  report.gpu_ms.fill(std::nan(""));
  report.wall_ms.fill(std::nan(""));
  report.scene_lighting = fallback_lighting();
  {
    const std::lock_guard<std::mutex> lock(log_mutex_);
    for (std::string& line : light_debug_) line.clear();
  }

  std::string error;
  if (width <= 0 || height <= 0) return report;  // minimised window
  if (!ensure_targets(width, height, &error)) {
    report.errors.push_back(error);
    return report;
  }
  if (!hs::depth_convention_supported(settings.depth_convention)) {
    report.errors.push_back(std::string("depth convention ") + hs::to_string(settings.depth_convention) +
                            " needs glClipControl (GL 4.5 or ARB_clip_control)");
    return report;
  }

  hs::ViewSetup setup;
  setup.world_origin = settings.origin;
  setup.pose = settings.pose;
  setup.vfov_rad = glm::radians(settings.vfov_deg);
  setup.near_m = kNearM;
  setup.far_m = kFarM;
  setup.depth_convention = settings.depth_convention;
  setup.viewport = {0, 0, width, height};
  setup.depth_texture = depth_;
  setup.output_encoding = ATMO_OUTPUT_LINEAR_HDR;
  setup.exposure_scale = hs::exposure_scale_from_ev100(settings.ev100);
  setup.cloud_quality = settings.clouds.quality;

  // World and view state first: the terrain is lit by the plugin's sun.
  bool plugin_ready = true;
  try {
    if (settings.visibility_m != last_visibility_m_) {
      auto air = atmo::make<AtmoAtmosphereState>(ATMO_TYPE_ATMOSPHERE_STATE);
      air.visibility_m = settings.visibility_m;
      context_->set_atmosphere(air);
      last_visibility_m_ = settings.visibility_m;
    }
    if (settings.fog_visibility_m != last_fog_visibility_m_ || settings.fog_top_m != last_fog_top_m_) {
      // Each change of the RVR slider: set_fog is cheap for a phase function
      // the process has seen (its tables are kept), so no need to wait for the drag's end.
      if (settings.fog_visibility_m > 0.0) {
        auto fog = atmo::make<AtmoFogState>(ATMO_TYPE_FOG_STATE);
        fog.visibility_m = settings.fog_visibility_m;
        fog.top_height_m = settings.origin.height_m + settings.fog_top_m;
        context_->set_fog(fog);
      } else {
        context_->clear_fog();
      }
      last_fog_visibility_m_ = settings.fog_visibility_m;
      last_fog_top_m_ = settings.fog_top_m;
    }
    // The lights, in fog or clear air (the points pass draws them in both);
    // glow threshold the default, 1/2000 of the view's white.
    send_lights(settings, &report);
    send_occluders(settings, frame_number, &report);
    auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
    frame.host_frame_number = frame_number;
    frame.utc_posix_s = settings.utc_posix_s;
    frame.deferred_frames = settings.deferred_frames;
    context_->set_frame(frame);
    view_->set(hs::make_view_state(setup));
    report.lighting = view_->lighting();
    report.scene_lighting = hs::lighting_from_atmo(report.lighting);
    // The plugin's lights (in its fog or clear air), for the terrain's own shader (atmo_fog_lights.glsl).
    const auto lighting_start = std::chrono::steady_clock::now();
    report.fog_lighting = view_->fog_lighting();
    report.fog_lighting_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - lighting_start).count();
  } catch (const atmo::Error& e) {
    report.errors.push_back(e.what());
    plugin_ready = false;
  }

  // finish_sections: each section's work done inside its own query and wall time.
  auto section_start = std::chrono::steady_clock::now();
  const auto begin = [&](int section) {
    if (finish_sections) {
      glFinish();
      section_start = std::chrono::steady_clock::now();
    }
    timers_.begin(section);
  };
  const auto end = [&](int section) {
    if (finish_sections) {
      glFinish();
      report.wall_ms[static_cast<size_t>(section)] =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - section_start).count();
    }
    timers_.end();
  };
  timers_.begin_frame();
  {
    const hs::DepthSetup depth(settings.depth_convention);
    glBindFramebuffer(GL_FRAMEBUFFER, scene_fbo_);
    glViewport(0, 0, width, height);
    glDisable(GL_SCISSOR_TEST);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

    begin(kSectionTerrain);
    terrain_->draw(setup, report.scene_lighting,
                   report.fog_lighting.light_count > 0 ? &report.fog_lighting : nullptr);
    end(kSectionTerrain);

    // The objects (docs/SKY_OCCLUSION.md): their sky shadow, Sun shadow and bounce on the terrain by the plugin's
    // pass (every surface facing up; the colour-only framebuffer, the pass reads the depth), then the objects
    // themselves, which shade their own surfaces through atmo_sky_occlusion.glsl with their own normals.
    const bool objects = objects_loaded_ && settings.objects == ObjectsChoice::Apron;
    const bool shadows = objects && occluders_sent_ && plugin_ready;
    if (shadows) {
      glBindFramebuffer(GL_FRAMEBUFFER, atmo_fbo_);
      begin(kSectionSkyOcclusion);
      try {
        auto info = atmo::make<AtmoPassInfo>(ATMO_TYPE_PASS_INFO);
        info.pass = ATMO_PASS_SKY_OCCLUSION;
        info.flags = ATMO_PASS_SKY_OCCLUSION_NORMAL_UP;
        report.pass_results[ATMO_PASS_SKY_OCCLUSION] =
            context_->check(api().render_pass(view_->handle(), &info), "render_pass(ATMO_PASS_SKY_OCCLUSION)");
      } catch (const atmo::Error& e) {
        report.pass_results[ATMO_PASS_SKY_OCCLUSION] = e.code();
        report.errors.push_back(e.what());
      }
      end(kSectionSkyOcclusion);
    }
    if (objects) {
      glBindFramebuffer(GL_FRAMEBUFFER, scene_fbo_);
      begin(kSectionObjects);
      auto occlusion = atmo::make<AtmoSkyOcclusion>(ATMO_TYPE_SKY_OCCLUSION);
      if (shadows) {
        const auto occlusion_start = std::chrono::steady_clock::now();
        try {
          context_->check(api().get_sky_occlusion(view_->handle(), &occlusion), "get_sky_occlusion");
        } catch (const atmo::Error& e) {
          report.errors.push_back(e.what());
        }
        report.sky_occlusion_cpu_ms =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - occlusion_start).count();
        report.longest_tile_list = occlusion.longest_tile_list;
      }
      object_gl_.draw(setup, hs::object_lighting_from_atmo(report.lighting), apron_instances(frame_number),
                      shadows ? &occlusion : nullptr);
      end(kSectionObjects);
    }

    if (plugin_ready) {
      glBindFramebuffer(GL_FRAMEBUFFER, atmo_fbo_);
      for (int section = kSectionSky; section <= kSectionLightPoints; ++section) {
        const int pass = section_pass(section);
        if (pass == ATMO_PASS_NIGHT_SKY && !settings.night_sky) continue;
        begin(section);
        try {
          report.pass_results[static_cast<size_t>(pass)] = view_->render(static_cast<AtmoPassKind>(pass));
        } catch (const atmo::Error& e) {
          report.pass_results[static_cast<size_t>(pass)] = e.code();
          report.errors.push_back(e.what());
        }
        end(section);
      }
    }
  }

  begin(kSectionToneMap);
  glBindFramebuffer(GL_FRAMEBUFFER, target_fbo);
  glViewport(0, 0, width, height);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glUseProgram(tone_map_program_);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, hdr_color_);
  glUniform1i(glGetUniformLocation(tone_map_program_, "u_hdr"), 0);
  glBindVertexArray(empty_vao_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glBindTexture(GL_TEXTURE_2D, 0);
  glUseProgram(0);
  end(kSectionToneMap);
  timers_.end_frame(wait_for_timings);

  for (size_t i = 0; i < report.gpu_ms.size(); ++i) report.gpu_ms[i] = timers_.milliseconds()[i];
  report.timings_valid = timers_.has_results();
  report.group_lights = group_lights_;
  report.lights_sent = group_lights_[0] + group_lights_[1];
  {
    const std::lock_guard<std::mutex> lock(log_mutex_);
    report.light_debug = light_debug_;
  }
  for (std::string& message : take_logged_errors()) report.errors.push_back(std::move(message));
  const GLenum gl_error = glGetError();
  if (gl_error != GL_NO_ERROR) {
    char text[64];
    std::snprintf(text, sizeof text, "GL error 0x%04x after the frame", gl_error);
    report.errors.push_back(text);
  }
  report.cpu_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - cpu_start).count();
  return report;
}

}  // namespace atmo::sample
