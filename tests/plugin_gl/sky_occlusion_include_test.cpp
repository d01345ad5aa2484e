// The host's surfaces under its own objects through atmo_sky_occlusion.glsl, in
// a host shader that includes it, drawn on llvmpipe through the real plugin:
//   - three objects (an aircraft of 20 spheres, a van of 6, a wall of 8) at
//     noon; each pixel the ground point or the point of a vertical wall plane
//     it sees (the sky's pixels a point 5 km along their ray);
//   - the frame the plugin uploaded, read back from its textures, against the
//     one core's make_occlusion_frame makes from the same inputs (the spheres
//     moved to the eye, the objects' bounds and stand-ins, the tiles' lists);
//   - every pixel against the include's C++ twin (shadows::twin::evaluate)
//     over that frame, at the position and normal the shader used;
//   - pixels far from every object get the unoccluded sky: get_lighting's SH9.
// And the ABI: bad spheres and poses named by index, the order of calls, no
// occluders, undersized structs, and nothing changed by a refused call.
#include <glad/gl.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "atmo_host_scene/sky_occlusion_binding.h"
#include "core/shadows/occlusion_frame.h"
#include "core/shadows/occlusion_twin.h"
#include "host_shader.h"
#include "plugin_gl_fixture.h"

namespace {

using namespace plugin_gl;
namespace shadows = atmo::shadows;

constexpr double kEyeHeightM = 2.0;
constexpr int kW = 320, kH = 200;
const glm::dmat4 kProjection = glm::perspective(glm::radians(50.0), double(kW) / kH, 0.5, 1e5);
constexpr double kPitchDeg = -8.0;
// 2024-07-03 11:18 UTC: local noon at Innsbruck, the Sun 66 degrees up in the south.
constexpr double kNoonUtc = 1.72e9 + 5520.0;
// The host's vertical wall: the plane north = 55 m facing the eye (normal south), 80 m wide, 15 m high.
constexpr double kWallNorthM = 55.0, kWallHalfWidthM = 40.0, kWallTopM = 15.0;
constexpr double kFarM = 5000.0;  // where a sky pixel's point is

const char* kVertex =
    "#version 330 core\nvoid main(){vec2 p=vec2((gl_VertexID<<1)&2,gl_VertexID&2);"
    "gl_Position=vec4(p*2.0-1.0,0.5,1.0);}\n";
// Each pixel's point (relative to the eye, world = ENU axes) and normal: the ground (2 m below the eye), the
// wall plane, or 5 km along the ray; the include's answer in two RGBA32F targets, the point in a third.
const char* kFragmentMain = R"(
uniform mat4 rel_from_clip;
uniform vec2 size;
uniform float eye_height;
uniform vec3 wall;  // north, half width, top
uniform float far_m;
layout(location = 0) out vec4 sky_sun;
layout(location = 1) out vec4 bounce_ao;
layout(location = 2) out vec4 point_kind;
void main() {
  vec2 ndc = gl_FragCoord.xy / size * 2.0 - 1.0;
  vec4 a = rel_from_clip * vec4(ndc, -1.0, 1.0);
  vec4 b = rel_from_clip * vec4(ndc, 1.0, 1.0);
  vec3 dir = normalize(b.xyz / b.w - a.xyz / a.w);
  float t = 1.0e30;
  float kind = 0.0;
  vec3 n = vec3(0.0, 0.0, 1.0);
  if (dir.z < -1.0e-4) {
    t = -eye_height / dir.z;
    kind = 1.0;
  }
  if (dir.y > 1.0e-4) {
    float tw = wall.x / dir.y;
    vec3 q = dir * tw;
    if (tw < t && abs(q.x) <= wall.y && q.z + eye_height >= 0.0 && q.z + eye_height <= wall.z) {
      t = tw;
      kind = 2.0;
      n = vec3(0.0, -1.0, 0.0);
    }
  }
  vec3 p = kind == 0.0 ? dir * far_m : dir * t;
  AtmoSkyOcclusion o = atmo_sky_occlusion(p, n);
  sky_sun = vec4(o.sky_lux, o.sun_visibility);
  bounce_ao = vec4(o.bounce_lux, o.sky_visibility);
  point_kind = vec4(p, kind);
}
)";

glm::dmat4 view_rotation() { return look(0.0, kPitchDeg); }
glm::dmat4 rel_from_clip() { return glm::inverse(kProjection * view_rotation()); }

// ---- The host's objects (world = ENU at Innsbruck, height 0) ----

struct HostObject {
  std::vector<AtmoOccluderSphere> spheres;
  glm::dvec3 albedo;
  glm::dmat4 world_from_object;
};

glm::dmat4 pose(double east, double north, double heading_deg) {
  return glm::rotate(glm::translate(glm::dmat4(1.0), glm::dvec3(east, north, 0.0)), glm::radians(-heading_deg),
                     glm::dvec3(0, 0, 1));
}

AtmoOccluderSphere sphere(double x, double y, double z, double r) { return {{x, y, z}, r}; }

// An aircraft of 20 spheres, nose along +y: fuselage, wings, fin.
HostObject aircraft(const glm::dmat4& world_from_object) {
  HostObject o{{}, glm::dvec3(0.7, 0.7, 0.72), world_from_object};
  for (int i = 0; i < 9; ++i) o.spheres.push_back(sphere(0.0, -10.0 + 2.5 * i, 2.2, 1.6));
  o.spheres.push_back(sphere(0.0, 12.2, 2.0, 1.1));  // nose
  for (const double x : {3.0, 5.5, 8.0, 10.5}) {
    o.spheres.push_back(sphere(x, 0.5, 1.8, 0.9));
    o.spheres.push_back(sphere(-x, 0.5, 1.8, 0.9));
  }
  o.spheres.push_back(sphere(0.0, -11.0, 4.0, 1.0));  // fin
  o.spheres.push_back(sphere(0.0, -12.0, 5.4, 0.8));
  return o;
}

// A van of 6 spheres (2 x 3).
HostObject van(const glm::dmat4& world_from_object) {
  HostObject o{{}, glm::dvec3(0.8, 0.8, 0.8), world_from_object};
  for (const double y : {-1.8, 0.0, 1.8})
    for (const double x : {-0.8, 0.8}) o.spheres.push_back(sphere(x, y, 1.1, 1.05));
  return o;
}

// A wall of 8 spheres (4 across, 2 up).
HostObject wall(const glm::dmat4& world_from_object) {
  HostObject o{{}, glm::dvec3(0.4, 0.35, 0.3), world_from_object};
  for (int i = 0; i < 4; ++i)
    for (const double z : {1.5, 4.3}) o.spheres.push_back(sphere(2.8 * i, 0.0, z, 1.5));
  return o;
}

std::vector<HostObject> apron() {
  return {aircraft(pose(4.0, 38.0, 20.0)), van(pose(-7.0, 16.0, 90.0)), wall(pose(9.0, 22.0, -30.0))};
}

// The ABI's structs over host objects (they point into `objects`, which must outlive them).
struct OccludersInput {
  std::vector<AtmoOccluderObject> objects;
  AtmoOccludersState state = atmo::make<AtmoOccludersState>(ATMO_TYPE_OCCLUDERS_STATE);

  explicit OccludersInput(const std::vector<HostObject>& host, uint32_t flags = 0) {
    for (const HostObject& h : host) {
      AtmoOccluderObject o{};
      o.spheres = h.spheres.data();
      o.sphere_count = static_cast<uint32_t>(h.spheres.size());
      o.sphere_size = sizeof(AtmoOccluderSphere);
      for (int c = 0; c < 3; ++c) o.albedo[c] = h.albedo[c];
      copy(h.world_from_object, o.world_from_object);
      objects.push_back(o);
    }
    state.world_frame = ATMO_WORLD_ENU;
    state.object_size = sizeof(AtmoOccluderObject);
    state.world_origin_geodetic[0] = 47.26;
    state.world_origin_geodetic[1] = 11.35;
    state.world_origin_geodetic[2] = 0.0;
    state.objects = objects.data();
    state.object_count = static_cast<uint32_t>(objects.size());
    state.flags = flags;
  }
};


// ---- Read-back ----

template <typename T>
std::vector<T> read_texture(GLuint texture, GLenum format, GLenum type, int components, int* w, int* h) {
  glBindTexture(GL_TEXTURE_2D, texture);
  glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_WIDTH, w);
  glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_HEIGHT, h);
  std::vector<T> out(size_t(*w) * size_t(*h) * size_t(components));
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glGetTexImage(GL_TEXTURE_2D, 0, format, type, out.data());
  glBindTexture(GL_TEXTURE_2D, 0);
  return out;
}

// The frame the include reads, from the plugin's textures and the struct's uniforms (the layouts the include's
// header states: a sphere a texel 1024 a row, 4 texels an object 256 objects a row, a tile a texel, 4096
// entries a row).
shadows::OcclusionFrame frame_from_gl(const AtmoSkyOcclusion& o, size_t spheres, size_t objects,
                                      std::vector<glm::vec4>* tables) {
  shadows::OcclusionFrame f;
  int w = 0, h = 0;
  const std::vector<float> tab = read_texture<float>(o.tables, GL_RGBA, GL_FLOAT, 4, &w, &h);
  tables->clear();
  for (size_t i = 0; i + 3 < tab.size(); i += 4) tables->emplace_back(tab[i], tab[i + 1], tab[i + 2], tab[i + 3]);
  const std::vector<float> sp = read_texture<float>(o.spheres, GL_RGBA, GL_FLOAT, 4, &w, &h);
  EXPECT_EQ(w, 1024);
  for (size_t i = 0; i < spheres && 4 * i + 3 < sp.size(); ++i) f.spheres.push_back(glm::make_vec4(&sp[4 * i]));
  const std::vector<float> ob = read_texture<float>(o.objects, GL_RGBA, GL_FLOAT, 4, &w, &h);
  EXPECT_EQ(w, 1024);
  for (size_t i = 0; i < 4 * objects && 4 * i + 3 < ob.size(); ++i) f.objects.push_back(glm::make_vec4(&ob[4 * i]));
  const std::vector<uint32_t> tiles = read_texture<uint32_t>(o.tiles, GL_RG_INTEGER, GL_UNSIGNED_INT, 2, &w, &h);
  f.tiles_x = w;
  f.tiles_y = h;
  for (size_t i = 0; i + 1 < tiles.size(); i += 2) f.tiles.emplace_back(tiles[i], tiles[i + 1]);
  f.tile_objects = read_texture<uint32_t>(o.tile_objects, GL_RED_INTEGER, GL_UNSIGNED_INT, 1, &w, &h);
  EXPECT_EQ(w, 4096);
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) f.tile_from_position[c][r] = float(o.tile_from_position[c * 4 + r]);
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) f.enu_from_world[c][r] = float(o.enu_from_world[c * 3 + r]);
  for (int i = 0; i < 4; ++i) {
    f.grid[i] = float(o.grid[i]);
    f.limits[i] = float(o.limits[i]);
    f.sun[i] = float(o.sun[i]);
  }
  for (int i = 0; i < 3; ++i) f.sun_lux[i] = float(o.sun_lux[i]);
  std::memcpy(f.sky.sky_sh9.data(), o.sky_sh9, sizeof(o.sky_sh9));
  std::memcpy(f.sky.sun_sh9.data(), o.sun_sh9, sizeof(o.sun_sh9));
  std::memcpy(f.sky.transfer.data(), o.transfer, sizeof(o.transfer));
  f.longest_tile_list = o.longest_tile_list;
  return f;
}

// The same frame from core's make_occlusion_frame: the host's objects, the eye 2 m above the world's origin
// (the eye's ENU axes are the world's), the view's projection and rotation; the sky's light as the plugin gave it.
shadows::OcclusionFrame frame_on_cpu(const std::vector<HostObject>& host, const AtmoSkyOcclusion& o, uint32_t flags,
                                     std::vector<shadows::OccluderObject>* keep) {
  keep->clear();
  std::vector<glm::dmat4> poses;
  for (const HostObject& h : host) {
    std::vector<glm::dvec4> spheres;
    for (const AtmoOccluderSphere& s : h.spheres)
      if (s.radius_m > 0.0) spheres.emplace_back(s.centre_m[0], s.centre_m[1], s.centre_m[2], s.radius_m);
    keep->push_back(shadows::make_occluder_object(spheres, h.albedo));
    poses.push_back(glm::translate(glm::dmat4(1.0), glm::dvec3(0.0, 0.0, -kEyeHeightM)) * h.world_from_object);
  }
  std::vector<const shadows::OccluderObject*> objects;
  for (const shadows::OccluderObject& k : *keep) objects.push_back(&k);
  shadows::SkyTransfer sky;
  std::memcpy(sky.sky_sh9.data(), o.sky_sh9, sizeof(o.sky_sh9));
  std::memcpy(sky.sun_sh9.data(), o.sun_sh9, sizeof(o.sun_sh9));
  std::memcpy(sky.transfer.data(), o.transfer, sizeof(o.transfer));
  shadows::OcclusionLimits limits;
  limits.bounce = !(flags & ATMO_OCCLUSION_NO_BOUNCE);
  limits.hybrid = !(flags & ATMO_OCCLUSION_OPTIMAL_LINEAR);
  return shadows::make_occlusion_frame(objects, poses, kProjection * view_rotation(), glm::dmat3(1.0), kW, kH, sky,
                                       glm::dvec3(o.sun[0], o.sun[1], o.sun[2]),
                                       glm::dvec3(o.sun_lux[0], o.sun_lux[1], o.sun_lux[2]), limits);
}

// The tile's list of objects (its entries in order).
std::vector<uint32_t> tile_list(const shadows::OcclusionFrame& f, size_t tile) {
  const glm::uvec2 t = f.tiles[tile];
  return std::vector<uint32_t>(f.tile_objects.begin() + t.x, f.tile_objects.begin() + t.x + t.y);
}

double max_abs_diff(const glm::vec4& a, const glm::vec4& b) {
  return double(glm::max(glm::max(std::abs(a.x - b.x), std::abs(a.y - b.y)), glm::max(std::abs(a.z - b.z), std::abs(a.w - b.w))));
}

// E(n) from 9 coefficients (c0..c8 rgb), in double, Y_k as AtmoLighting documents them.
glm::dvec3 sh9_at(const double (*sh9)[3], const glm::dvec3& n) {
  const double y[9] = {0.282095, 0.488603 * n.y, 0.488603 * n.z, 0.488603 * n.x, 1.092548 * n.x * n.y,
                       1.092548 * n.y * n.z, 0.315392 * (3.0 * n.z * n.z - 1.0), 1.092548 * n.x * n.z,
                       0.546274 * (n.x * n.x - n.y * n.y)};
  glm::dvec3 e(0.0);
  for (int k = 0; k < 9; ++k) e += y[k] * glm::dvec3(sh9[k][0], sh9[k][1], sh9[k][2]);
  return e;
}

struct Targets {
  GLuint fbo = 0, colour[3] = {0, 0, 0};
  Targets() {
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glGenTextures(3, colour);
    for (int i = 0; i < 3; ++i) {
      glBindTexture(GL_TEXTURE_2D, colour[i]);
      glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, kW, kH, 0, GL_RGBA, GL_FLOAT, nullptr);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
      glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + i, GL_TEXTURE_2D, colour[i], 0);
    }
    const GLenum buffers[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
    glDrawBuffers(3, buffers);
    EXPECT_EQ(glCheckFramebufferStatus(GL_FRAMEBUFFER), GLenum(GL_FRAMEBUFFER_COMPLETE));
    glBindTexture(GL_TEXTURE_2D, 0);
  }
  ~Targets() {
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteFramebuffers(1, &fbo);
    glDeleteTextures(3, colour);
  }
  // Attachment i, RGBA, GL's row order (row 0 at the bottom).
  std::vector<float> read(int i) const {
    std::vector<float> out(size_t(kW) * kH * 4);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
    glReadBuffer(GL_COLOR_ATTACHMENT0 + i);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, kW, kH, GL_RGBA, GL_FLOAT, out.data());
    return out;
  }
};

struct Scene {
  Fixture f;

  Scene() {
    f.set_utc(kNoonUtc);
    AtmoViewState vs = innsbruck_view(kEyeHeightM, 0.0, kPitchDeg, kProjection);
    vs.viewport[2] = kW;
    vs.viewport[3] = kH;
    f.view->set(vs);
  }
  const AtmoPluginApi& api() const { return f.plugin->api(); }

  AtmoResult get(AtmoSkyOcclusion* o) {
    *o = atmo::make<AtmoSkyOcclusion>(ATMO_TYPE_SKY_OCCLUSION);
    return api().get_sky_occlusion(f.view->handle(), o);
  }

  // The host shader's three targets (sky_lux + sun visibility, bounce + sky visibility, point + kind).
  std::vector<std::vector<float>> draw(const AtmoSkyOcclusion& o) {
    const std::string include = read_text(std::string(ATMO_SOURCE_DIR) + "/host_sdk/include/atmo/atmo_sky_occlusion.glsl");
    EXPECT_FALSE(include.empty());
    const HostProgram host(kVertex, "#version 330 core\n" + include + kFragmentMain);
    EXPECT_TRUE(host.linked());
    glUseProgram(host.id());
    const glm::mat4 m(rel_from_clip());
    glUniformMatrix4fv(host.uniform("rel_from_clip"), 1, GL_FALSE, glm::value_ptr(m));
    glUniform2f(host.uniform("size"), float(kW), float(kH));
    glUniform1f(host.uniform("eye_height"), float(kEyeHeightM));
    glUniform3f(host.uniform("wall"), float(kWallNorthM), float(kWallHalfWidthM), float(kWallTopM));
    glUniform1f(host.uniform("far_m"), float(kFarM));
    std::vector<std::vector<float>> out;
    {
      Targets targets;  // first: it binds its textures on unit 0
      const atmo::host_scene::SkyOcclusionBinding binding(host.id(), o, 0);  // as a host binds them
      glViewport(0, 0, kW, kH);
      glDisable(GL_BLEND);
      glDisable(GL_DEPTH_TEST);
      draw_full_screen_triangle();
      glFinish();
      for (int i = 0; i < 3; ++i) out.push_back(targets.read(i));
    }
    for (int i = 0; i < 5; ++i) {
      glActiveTexture(GL_TEXTURE0 + i);
      glBindTexture(GL_TEXTURE_2D, 0);
    }
    glActiveTexture(GL_TEXTURE0);
    return out;
  }
};

double median_of(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// The whole path, for the default flags (bounce, hybrid) and the two cheaper ones.
TEST(SkyOcclusionInclude, HostShaderMatchesTheTwinOverTheFrameThePluginUploaded) {
  Scene s;
  const std::vector<HostObject> host = apron();
  const auto lighting = s.f.view->lighting();
  for (const uint32_t flags : {0u, uint32_t(ATMO_OCCLUSION_NO_BOUNCE), uint32_t(ATMO_OCCLUSION_OPTIMAL_LINEAR)}) {
    SCOPED_TRACE("flags " + std::to_string(flags));
    OccludersInput input(host, flags);
    ASSERT_EQ(s.api().set_occluders(s.f.context->handle(), &input.state), ATMO_SUCCESS) << s.f.context->last_error();
    AtmoSkyOcclusion o;
    ASSERT_EQ(s.get(&o), ATMO_SUCCESS) << s.f.context->last_error();
    EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
    ASSERT_EQ(o.object_count, 3u);
    ASSERT_NE(o.tables, 0u);
    ASSERT_NE(o.tile_objects, 0u);
    const std::vector<std::vector<float>> img = s.draw(o);
    EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));

    // The uploaded frame against core's.
    std::vector<shadows::OccluderObject> keep;
    const shadows::OcclusionFrame cpu = frame_on_cpu(host, o, flags, &keep);
    // The spheres' texture holds every sphere and then the groups' texels.
    std::vector<glm::vec4> tables;
    const shadows::OcclusionFrame gpu = frame_from_gl(o, cpu.spheres.size(), host.size(), &tables);
    EXPECT_EQ(tables, shadows::occlusion_tables().texels) << "atmo_occ_tables is core's table";
    ASSERT_EQ(gpu.spheres.size(), cpu.spheres.size());
    ASSERT_EQ(gpu.objects.size(), cpu.objects.size());
    double sphere_off = 0.0, object_off = 0.0, matrix_off = 0.0;
    for (size_t i = 0; i < cpu.spheres.size(); ++i) sphere_off = std::max(sphere_off, max_abs_diff(gpu.spheres[i], cpu.spheres[i]));
    for (size_t i = 0; i < cpu.objects.size(); ++i) object_off = std::max(object_off, max_abs_diff(gpu.objects[i], cpu.objects[i]));
    for (int c = 0; c < 4; ++c) {
      const glm::vec4 a = gpu.tile_from_position[c], b = cpu.tile_from_position[c];
      matrix_off = std::max(matrix_off, max_abs_diff(a, b) / std::max(1.0, double(glm::length(b))));
    }
    for (int c = 0; c < 3; ++c)
      matrix_off = std::max(matrix_off, max_abs_diff(glm::vec4(gpu.enu_from_world[c], 0.0f), glm::vec4(cpu.enu_from_world[c], 0.0f)));
    ASSERT_EQ(gpu.tiles_x, cpu.tiles_x);
    ASSERT_EQ(gpu.tiles_y, cpu.tiles_y);
    int lists_differ = 0;
    for (size_t t = 0; t < cpu.tiles.size(); ++t) lists_differ += tile_list(gpu, t) != tile_list(cpu, t);
    std::printf("flags %u: uploaded frame vs core's: spheres off by %.1e m, objects (bound, stand-in, albedo, index) "
                "by %.1e, matrices by %.1e; %d of %zu tiles' lists differ; longest list %u (core %u); grid (%g, %g, "
                "%g, %g)\n",
                flags, sphere_off, object_off, matrix_off, lists_differ, cpu.tiles.size(), o.longest_tile_list,
                cpu.longest_tile_list, o.grid[0], o.grid[1], o.grid[2], o.grid[3]);
    EXPECT_LT(sphere_off, 1e-4);
    EXPECT_LT(object_off, 1e-4);
    EXPECT_LT(matrix_off, 1e-5);
    EXPECT_EQ(lists_differ, 0);
    EXPECT_EQ(o.longest_tile_list, cpu.longest_tile_list);
    EXPECT_EQ(gpu.grid, cpu.grid);
    EXPECT_EQ(gpu.limits, cpu.limits);

    // Every pixel against the twin over the uploaded frame, at the shader's own point and normal.
    std::vector<double> sky_err;
    double sky_worst = 0.0, sun_worst = 0.0, ao_worst = 0.0, bounce_worst = 0.0, far_worst = 0.0, far_sh9_worst = 0.0;
    double min_ao = 1.0, min_sun = 1.0, max_bounce = 0.0;
    int pixels[3] = {0, 0, 0}, far = 0, shaded = 0, worst_x = 0, worst_y = 0;
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        const size_t i = (size_t(y) * kW + x) * 4;
        const float* a = &img[0][i];
        const float* b = &img[1][i];
        const float* q = &img[2][i];
        const int kind = int(q[3] + 0.5f);
        ++pixels[kind];
        const glm::vec3 p(q[0], q[1], q[2]);
        const glm::vec3 n = kind == 2 ? glm::vec3(0.0f, -1.0f, 0.0f) : glm::vec3(0.0f, 0.0f, 1.0f);
        const shadows::twin::AtmoSkyOcclusion want = shadows::twin::evaluate(gpu, p, n);
        // The unoccluded sky at this normal (the include's own SH9, in double).
        glm::dvec3 open(0.0);
        {
          const shadows::twin::AtmoOccSh y9 = shadows::twin::atmo_occ_basis(n);
          const float c[9] = {y9.a.x, y9.a.y, y9.a.z, y9.a.w, y9.b.x, y9.b.y, y9.b.z, y9.b.w, y9.c.x};
          for (int k = 0; k < 9; ++k)
            for (int ch = 0; ch < 3; ++ch) open[ch] += double(c[k]) * o.sky_sh9[3 * k + ch];
        }
        double sky_e = 0.0, bounce_e = 0.0;
        for (int ch = 0; ch < 3; ++ch) {
          sky_e = std::max(sky_e, std::abs(double(a[ch]) - want.sky_lux[ch]) / open[ch]);
          bounce_e = std::max(bounce_e, std::abs(double(b[ch]) - want.bounce_lux[ch]) / open[ch]);
        }
        sky_err.push_back(sky_e);
        if (sky_e > sky_worst) sky_worst = sky_e, worst_x = x, worst_y = y;
        bounce_worst = std::max(bounce_worst, bounce_e);
        sun_worst = std::max(sun_worst, std::abs(double(a[3]) - want.sun_visibility));
        ao_worst = std::max(ao_worst, std::abs(double(b[3]) - want.sky_visibility));
        if (kind != 0) {
          min_ao = std::min(min_ao, double(b[3]));
          min_sun = std::min(min_sun, double(a[3]));
          max_bounce = std::max(max_bounce, double(b[1]) / open.y);
          if (want.sky_visibility < 0.99f) ++shaded;
        }
        // Far from every object (each one's bound under the include's cull angle): the unoccluded sky, which
        // is get_lighting's SH9 (what a host shades with when there are no occluders).
        bool far_from_all = true;
        for (size_t k = 0; k < host.size(); ++k) {
          const glm::vec4 bound = gpu.objects[4 * k];
          if (glm::length(glm::vec3(bound) - p) * gpu.limits.x <= bound.w * 1.01f) far_from_all = false;
        }
        if (far_from_all) {
          ++far;
          const glm::dvec3 lit = sh9_at(lighting.sky_irradiance_sh9, glm::dvec3(n));
          for (int ch = 0; ch < 3; ++ch) {
            far_worst = std::max(far_worst, std::abs(double(a[ch]) - open[ch]) / open[ch]);
            far_sh9_worst = std::max(far_sh9_worst, std::abs(double(a[ch]) - lit[ch]) / lit[ch]);
          }
          EXPECT_EQ(a[3], 1.0f);
          EXPECT_EQ(b[3], 1.0f);
          EXPECT_EQ(b[0], 0.0f);
        }
      }
    std::printf("flags %u: %d ground, %d wall, %d sky pixels; %d shaded (sky visibility < 0.99), down to %.3f, the "
                "Sun's visibility down to %.3f, bounce up to %.3f of the open sky\n",
                flags, pixels[1], pixels[2], pixels[0], shaded, min_ao, min_sun, max_bounce);
    std::printf("flags %u: host shader vs twin: sky_lux relative to the unoccluded median %.1e, worst %.1e (pixel "
                "%d, %d); sun visibility worst %.1e; sky visibility worst %.1e; bounce worst %.1e of the unoccluded\n",
                flags, median_of(sky_err), sky_worst, worst_x, worst_y, sun_worst, ao_worst, bounce_worst);
    std::printf("flags %u: %d pixels far from every object: sky_lux vs the include's SH9 worst %.1e, vs "
                "get_lighting's SH9 worst %.1e\n",
                flags, far, far_worst, far_sh9_worst);
    // GLSL leaves asin and acos loosely specified: llvmpipe's are off by up to 3.9e-4 and 1.6e-4 rad, which the
    // Sun's cover (an angle difference over the Sun's radius, 4.7e-3 rad) and the hybrid exponential's switch
    // between squarings turn into differences far above these bounds; atan(y, x) forms agree within 1.5e-4.
    EXPECT_LE(sky_worst, 1e-3);
    EXPECT_LE(sun_worst, 2e-3);
    EXPECT_LE(ao_worst, 2e-3);
    EXPECT_LE(bounce_worst, 1e-3);
    EXPECT_GT(pixels[1], kW * kH / 3);
    EXPECT_GT(pixels[2], kW * kH / 50);
    EXPECT_GT(far, kW * kH / 20);
    EXPECT_LE(far_worst, 1e-5);
    EXPECT_LE(far_sh9_worst, 1e-3);
    // The objects do shade: deep sky shadow, full Sun shadow, and (with the bounce) reflected light.
    EXPECT_GT(shaded, kW * kH / 20);
    EXPECT_LT(min_ao, 0.7);
    EXPECT_LT(min_sun, 0.01);
    if (flags & ATMO_OCCLUSION_NO_BOUNCE) {
      EXPECT_EQ(max_bounce, 0.0);
    } else {
      EXPECT_GT(max_bounce, 0.01);
    }
  }
}

// ---- The ABI ----

// What a host sees of the occluders: get_sky_occlusion's struct and the spheres it uploaded.
struct Seen {
  AtmoSkyOcclusion o;
  std::vector<float> spheres;
  bool operator==(const Seen& other) const {
    return std::memcmp(&o, &other.o, sizeof(o)) == 0 && spheres == other.spheres;
  }
};

Seen seen(Scene& s) {
  Seen out;
  EXPECT_EQ(s.get(&out.o), ATMO_SUCCESS) << s.f.context->last_error();
  int w = 0, h = 0;
  if (out.o.spheres) out.spheres = read_texture<float>(out.o.spheres, GL_RGBA, GL_FLOAT, 4, &w, &h);
  return out;
}

bool names(const std::string& message, const std::string& what) { return message.find(what) != std::string::npos; }

TEST(SkyOcclusionAbi, BadSpheresAndPosesAreRefusedByIndexAndChangeNothing) {
  Scene s;
  const std::vector<HostObject> host = apron();
  OccludersInput good(host);
  ASSERT_EQ(s.api().set_occluders(s.f.context->handle(), &good.state), ATMO_SUCCESS) << s.f.context->last_error();
  const Seen before = seen(s);
  ASSERT_EQ(before.o.object_count, 3u);
  const AtmoContext ctx = s.f.context->handle();

  struct Bad {
    const char* what;
    double radius;
    AtmoResult code;
  };
  for (const Bad& bad : {Bad{"NaN", std::nan(""), ATMO_ERROR_NON_FINITE_VALUE},
                         Bad{"negative", -1.0, ATMO_ERROR_OUT_OF_RANGE},
                         Bad{"infinite", INFINITY, ATMO_ERROR_NON_FINITE_VALUE},
                         Bad{"over 1e5 m", 2e5, ATMO_ERROR_OUT_OF_RANGE}}) {
    std::vector<HostObject> edited = host;
    edited[1].spheres[3].radius_m = bad.radius;
    OccludersInput in(edited);
    EXPECT_EQ(s.api().set_occluders(ctx, &in.state), bad.code) << bad.what;
    const std::string message = s.f.context->last_error();
    std::printf("radius %s: %s\n", bad.what, message.c_str());
    EXPECT_TRUE(names(message, "objects[1].spheres[3].radius_m")) << message;
    EXPECT_TRUE(seen(s) == before) << bad.what << ": the previous occluders are unchanged";
  }
  {  // A centre that is not finite.
    std::vector<HostObject> edited = host;
    edited[2].spheres[5].centre_m[1] = std::nan("");
    OccludersInput in(edited);
    EXPECT_EQ(s.api().set_occluders(ctx, &in.state), ATMO_ERROR_NON_FINITE_VALUE);
    EXPECT_TRUE(names(s.f.context->last_error(), "objects[2].spheres[5].centre_m[1]")) << s.f.context->last_error();
    EXPECT_TRUE(seen(s) == before);
  }
  {  // A pose that scales (not rigid): the object is named.
    std::vector<HostObject> edited = host;
    edited[2].world_from_object = glm::scale(edited[2].world_from_object, glm::dvec3(1.5));
    OccludersInput in(edited);
    EXPECT_EQ(s.api().set_occluders(ctx, &in.state), ATMO_ERROR_OUT_OF_RANGE);
    const std::string message = s.f.context->last_error();
    std::printf("scaled pose: %s\n", message.c_str());
    EXPECT_TRUE(names(message, "objects[2].world_from_object")) << message;
    EXPECT_TRUE(seen(s) == before);
  }
  {  // A reflection.
    std::vector<HostObject> edited = host;
    edited[0].world_from_object = glm::scale(edited[0].world_from_object, glm::dvec3(-1.0, 1.0, 1.0));
    OccludersInput in(edited);
    EXPECT_EQ(s.api().set_occluders(ctx, &in.state), ATMO_ERROR_OUT_OF_RANGE);
    EXPECT_TRUE(names(s.f.context->last_error(), "objects[0].world_from_object")) << s.f.context->last_error();
    EXPECT_TRUE(seen(s) == before);
  }
  {  // Albedo outside [0, 1].
    std::vector<HostObject> edited = host;
    edited[1].albedo.y = 1.5;
    OccludersInput in(edited);
    EXPECT_EQ(s.api().set_occluders(ctx, &in.state), ATMO_ERROR_OUT_OF_RANGE);
    EXPECT_TRUE(names(s.f.context->last_error(), "objects[1].albedo[1]")) << s.f.context->last_error();
    EXPECT_TRUE(seen(s) == before);
  }
  {  // Unknown flags.
    OccludersInput in(host, 8u);
    EXPECT_EQ(s.api().set_occluders(ctx, &in.state), ATMO_ERROR_INVALID_ARGUMENT);
    EXPECT_TRUE(seen(s) == before);
  }

  // set_occluder_poses: out of range, a bad pose among good ones (nothing moves), then a good move.
  std::vector<double> two(32);
  copy(pose(0.0, 30.0, 0.0), two.data());
  copy(pose(3.0, 30.0, 45.0), two.data() + 16);
  auto poses = atmo::make<AtmoOccluderPoses>(ATMO_TYPE_OCCLUDER_POSES);
  poses.world_from_object = two.data();
  poses.first = 2;
  poses.count = 2;
  EXPECT_EQ(s.api().set_occluder_poses(ctx, &poses), ATMO_ERROR_OUT_OF_RANGE);
  std::printf("poses [2, 4) of 3: %s\n", s.f.context->last_error().c_str());
  EXPECT_TRUE(names(s.f.context->last_error(), "[2, 4)")) << s.f.context->last_error();
  poses.first = 4;
  poses.count = 0;
  EXPECT_EQ(s.api().set_occluder_poses(ctx, &poses), ATMO_ERROR_OUT_OF_RANGE);
  poses.first = 0xFFFFFFFFu;
  poses.count = 2;
  EXPECT_EQ(s.api().set_occluder_poses(ctx, &poses), ATMO_ERROR_OUT_OF_RANGE) << "first + count wraps";
  EXPECT_TRUE(seen(s) == before);
  poses.first = 1;
  poses.count = 2;
  two[16 + 0] = 2.0;  // the second pose scales along x
  EXPECT_EQ(s.api().set_occluder_poses(ctx, &poses), ATMO_ERROR_OUT_OF_RANGE);
  std::printf("scaled pose in set_occluder_poses: %s\n", s.f.context->last_error().c_str());
  EXPECT_TRUE(names(s.f.context->last_error(), "world_from_object[1]")) << s.f.context->last_error();
  EXPECT_TRUE(seen(s) == before) << "a refused set_occluder_poses moves nothing, not even the good first pose";
  poses.world_from_object = nullptr;
  EXPECT_EQ(s.api().set_occluder_poses(ctx, &poses), ATMO_ERROR_INVALID_ARGUMENT);
  EXPECT_TRUE(seen(s) == before);
  copy(pose(3.0, 30.0, 45.0), two.data() + 16);
  poses.world_from_object = two.data();
  EXPECT_EQ(s.api().set_occluder_poses(ctx, &poses), ATMO_SUCCESS) << s.f.context->last_error();
  const Seen moved = seen(s);
  EXPECT_FALSE(moved.spheres == before.spheres) << "the objects moved";
  // Moving them back gives the first frame again, bit for bit.
  copy(host[1].world_from_object, two.data());
  copy(host[2].world_from_object, two.data() + 16);
  EXPECT_EQ(s.api().set_occluder_poses(ctx, &poses), ATMO_SUCCESS) << s.f.context->last_error();
  EXPECT_TRUE(seen(s) == before);
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

TEST(SkyOcclusionAbi, UndersizedStructsAndStridesAreRefused) {
  Scene s;
  const std::vector<HostObject> host = apron();
  OccludersInput good(host);
  const AtmoContext ctx = s.f.context->handle();
  ASSERT_EQ(s.api().set_occluders(ctx, &good.state), ATMO_SUCCESS) << s.f.context->last_error();
  const Seen before = seen(s);
  {
    OccludersInput in(host);
    in.state.header.struct_size = 56;
    EXPECT_EQ(s.api().set_occluders(ctx, &in.state), ATMO_ERROR_STRUCT_TOO_SMALL);
    std::printf("56-byte AtmoOccludersState: %s\n", s.f.context->last_error().c_str());
    in.state.header.struct_size = sizeof(AtmoOccludersState);
    in.state.header.type = ATMO_TYPE_OCCLUDER_POSES;
    EXPECT_EQ(s.api().set_occluders(ctx, &in.state), ATMO_ERROR_WRONG_STRUCT_TYPE);
  }
  {
    OccludersInput in(host);
    in.state.object_size = 160;
    EXPECT_EQ(s.api().set_occluders(ctx, &in.state), ATMO_ERROR_STRUCT_TOO_SMALL);
    std::printf("160-byte objects: %s\n", s.f.context->last_error().c_str());
    EXPECT_TRUE(names(s.f.context->last_error(), "object_size")) << s.f.context->last_error();
  }
  {
    OccludersInput in(host);
    in.objects[2].sphere_size = 24;
    EXPECT_EQ(s.api().set_occluders(ctx, &in.state), ATMO_ERROR_STRUCT_TOO_SMALL);
    std::printf("24-byte spheres: %s\n", s.f.context->last_error().c_str());
    EXPECT_TRUE(names(s.f.context->last_error(), "objects[2].sphere_size")) << s.f.context->last_error();
  }
  EXPECT_TRUE(seen(s) == before);
  {
    auto poses = atmo::make<AtmoOccluderPoses>(ATMO_TYPE_OCCLUDER_POSES);
    poses.header.struct_size = 24;
    EXPECT_EQ(s.api().set_occluder_poses(ctx, &poses), ATMO_ERROR_STRUCT_TOO_SMALL);
  }
  {
    AtmoSkyOcclusion o = atmo::make<AtmoSkyOcclusion>(ATMO_TYPE_SKY_OCCLUSION);
    o.header.struct_size = 2312 - 8;  // below the version-1 size
    EXPECT_EQ(s.api().get_sky_occlusion(s.f.view->handle(), &o), ATMO_ERROR_STRUCT_TOO_SMALL);
    EXPECT_EQ(o.object_count, 0u) << "an error leaves the host's struct as it was";
    // A host compiled before the image (2312 bytes): filled up to there, the rest of its memory untouched.
    AtmoSkyOcclusion older = atmo::make<AtmoSkyOcclusion>(ATMO_TYPE_SKY_OCCLUSION);
    older.header.struct_size = 2312;
    older.image[0] = 12345u;
    EXPECT_EQ(s.api().get_sky_occlusion(s.f.view->handle(), &older), ATMO_SUCCESS);
    EXPECT_EQ(older.object_count, 3u);
    EXPECT_EQ(older.image[0], 12345u) << "nothing written past the host's struct";
    EXPECT_EQ(s.api().get_sky_occlusion(s.f.view->handle(), nullptr), ATMO_ERROR_INVALID_ARGUMENT);
  }
  // A host built with larger structs (a later version's): its arrays' strides are honoured.
  {
    struct BigObject {
      AtmoOccluderObject o;
      double future[2];
    };
    struct BigSphere {
      AtmoOccluderSphere s;
      double future;
    };
    std::vector<std::vector<BigSphere>> spheres;
    std::vector<BigObject> objects;
    for (const AtmoOccluderObject& o : good.objects) {
      std::vector<BigSphere> list;
      for (uint32_t k = 0; k < o.sphere_count; ++k) list.push_back({o.spheres[k], 1e300});
      spheres.push_back(list);
    }
    for (size_t i = 0; i < good.objects.size(); ++i) {
      BigObject b{good.objects[i], {NAN, NAN}};
      b.o.spheres = &spheres[i][0].s;
      b.o.sphere_size = sizeof(BigSphere);
      objects.push_back(b);
    }
    AtmoOccludersState state = good.state;
    state.objects = &objects[0].o;
    state.object_size = sizeof(BigObject);
    EXPECT_EQ(s.api().set_occluders(ctx, &state), ATMO_SUCCESS) << s.f.context->last_error();
    EXPECT_TRUE(seen(s) == before) << "the same objects through larger strides";
  }
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

TEST(SkyOcclusionAbi, OrderOfCallsAndNoOccluders) {
  Fixture f;
  const AtmoPluginApi& api = f.plugin->api();
  AtmoSkyOcclusion o = atmo::make<AtmoSkyOcclusion>(ATMO_TYPE_SKY_OCCLUSION);
  // The occluders may come first (no GL, no frame, no view needed).
  const std::vector<HostObject> host = apron();  // the input points into it
  OccludersInput in(host);
  ASSERT_EQ(api.set_occluders(f.context->handle(), &in.state), ATMO_SUCCESS) << f.context->last_error();
  EXPECT_EQ(api.get_sky_occlusion(f.view->handle(), &o), ATMO_ERROR_CALL_OUT_OF_ORDER);
  EXPECT_TRUE(names(f.context->last_error(), "set_frame")) << f.context->last_error();
  f.set_utc(kNoonUtc);
  EXPECT_EQ(api.get_sky_occlusion(f.view->handle(), &o), ATMO_ERROR_CALL_OUT_OF_ORDER);
  std::printf("before set_view: %s\n", f.context->last_error().c_str());
  EXPECT_TRUE(names(f.context->last_error(), "set_view")) << f.context->last_error();
  EXPECT_EQ(o.object_count, 0u);
  AtmoViewState vs = innsbruck_view(kEyeHeightM, 0.0, kPitchDeg, kProjection);
  f.view->set(vs);
  EXPECT_EQ(api.get_sky_occlusion(f.view->handle(), &o), ATMO_SUCCESS) << f.context->last_error();
  EXPECT_EQ(o.object_count, 3u);

  // None: NULL, then an empty set; object_count 0 and no textures, ATMO_STATUS_NOTHING_TO_DRAW.
  ASSERT_EQ(api.set_occluders(f.context->handle(), nullptr), ATMO_SUCCESS);
  o.object_count = 7;
  EXPECT_EQ(api.get_sky_occlusion(f.view->handle(), &o), ATMO_STATUS_NOTHING_TO_DRAW);
  EXPECT_EQ(o.object_count, 0u);
  EXPECT_EQ(o.tables, 0u);
  EXPECT_EQ(o.spheres, 0u);
  ASSERT_EQ(api.set_occluders(f.context->handle(), &in.state), ATMO_SUCCESS);
  EXPECT_EQ(api.get_sky_occlusion(f.view->handle(), &o), ATMO_SUCCESS);
  EXPECT_EQ(o.object_count, 3u);
  OccludersInput none(std::vector<HostObject>{});
  ASSERT_EQ(api.set_occluders(f.context->handle(), &none.state), ATMO_SUCCESS) << f.context->last_error();
  EXPECT_EQ(api.get_sky_occlusion(f.view->handle(), &o), ATMO_STATUS_NOTHING_TO_DRAW);
  EXPECT_EQ(o.object_count, 0u);
  // Poses with no objects: only the empty range is allowed.
  auto poses = atmo::make<AtmoOccluderPoses>(ATMO_TYPE_OCCLUDER_POSES);
  EXPECT_EQ(api.set_occluder_poses(f.context->handle(), &poses), ATMO_SUCCESS) << f.context->last_error();
  poses.count = 1;
  EXPECT_EQ(api.set_occluder_poses(f.context->handle(), &poses), ATMO_ERROR_OUT_OF_RANGE);
  EXPECT_EQ(api.set_occluder_poses(f.context->handle(), nullptr), ATMO_ERROR_INVALID_ARGUMENT);

  // After gl_shutdown get_sky_occlusion needs gl_init again.
  ASSERT_EQ(api.set_occluders(f.context->handle(), &in.state), ATMO_SUCCESS);
  ASSERT_EQ(api.gl_shutdown(f.context->handle()), ATMO_SUCCESS);
  EXPECT_EQ(api.get_sky_occlusion(f.view->handle(), &o), ATMO_ERROR_CALL_OUT_OF_ORDER);
  EXPECT_TRUE(names(f.context->last_error(), "gl_init")) << f.context->last_error();
  ASSERT_EQ(api.gl_init(f.context->handle()), ATMO_SUCCESS);
  EXPECT_EQ(api.get_sky_occlusion(f.view->handle(), &o), ATMO_SUCCESS) << f.context->last_error();
  EXPECT_NE(o.tables, 0u);
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

}  // namespace
