#include "scene.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <string_view>

#include <osg/BlendFunc>
#include <osg/Depth>
#include <osg/Geode>
#include <osg/Geometry>
#include <osg/MatrixTransform>
#include <osg/ShapeDrawable>

namespace atmo::osg_host::embedded_glsl {
std::string_view find(std::string_view path);
}

namespace atmo::osg_host {

namespace hs = atmo::host_scene;

namespace {

// GLSL 3.30 in the compatibility profile: Debian's OSG is a GL2 build that feeds gl_Vertex, gl_Normal,
// gl_Color and the fixed-function matrices.
const char* kSurfaceVertex = R"(#version 330 compatibility
out vec3 v_normal_view;
out vec3 v_albedo;
void main() {
  gl_Position = ftransform();
  v_normal_view = gl_NormalMatrix * gl_Normal;
  v_albedo = gl_Color.rgb;
}
)";

// Radiance of a Lambertian surface, albedo / pi * irradiance (lux -> cd/m^2), times the exposure: the
// plugin's linear HDR units. The sky's irradiance is get_lighting's SH9 (ENU axes, lux).
const char* kSurfaceFragment = R"(#version 330 compatibility
in vec3 v_normal_view;
in vec3 v_albedo;
uniform mat3 u_enu_from_view;
uniform vec3 u_sun_direction_enu;
uniform vec3 u_sun_lux;
uniform vec3 u_sky_sh9[9];
uniform float u_exposure;
layout(location = 0) out vec4 o_color;
vec3 sky_irradiance(vec3 n) {
  float x = n.x, y = n.y, z = n.z;
  vec3 e = u_sky_sh9[0] * 0.282095
         + u_sky_sh9[1] * (0.488603 * y) + u_sky_sh9[2] * (0.488603 * z) + u_sky_sh9[3] * (0.488603 * x)
         + u_sky_sh9[4] * (1.092548 * x * y) + u_sky_sh9[5] * (1.092548 * y * z)
         + u_sky_sh9[6] * (0.315392 * (3.0 * z * z - 1.0)) + u_sky_sh9[7] * (1.092548 * x * z)
         + u_sky_sh9[8] * (0.546274 * (x * x - y * y));
  return max(e, vec3(0.0));
}
void main() {
  vec3 n = normalize(u_enu_from_view * normalize(v_normal_view));
  vec3 e = u_sun_lux * max(dot(n, u_sun_direction_enu), 0.0) + sky_irradiance(n);
  o_color = vec4(v_albedo * (1.0 / 3.14159265) * e * u_exposure, 1.0);
}
)";

const char* kToneMapVertex = R"(#version 330 compatibility
void main() { gl_Position = ftransform(); }
)";

const char* kToneMapFragment = R"(
uniform sampler2D u_hdr;
layout(location = 0) out vec4 o_color;
void main() {
  o_color = vec4(atmo_display_srgb(texelFetch(u_hdr, ivec2(gl_FragCoord.xy), 0).rgb), 1.0);
}
)";

const char* kHudVertex = R"(#version 330 compatibility
out vec2 v_uv;
void main() {
  gl_Position = ftransform();
  v_uv = gl_MultiTexCoord0.xy;
}
)";

// Checker (unit 0) times a two-texel tint (unit 1): wrong bindings on either unit change the pixels.
const char* kHudFragment = R"(#version 330 compatibility
in vec2 v_uv;
uniform sampler2D u_checker;
uniform sampler2D u_tint;
layout(location = 0) out vec4 o_color;
void main() {
  o_color = vec4(texture(u_checker, v_uv).rgb * texture(u_tint, vec2(v_uv.x, 0.5)).rgb, 1.0);
}
)";

osg::ref_ptr<osg::Program> make_program(const char* name, const std::string& vertex, const std::string& fragment) {
  osg::ref_ptr<osg::Program> program = new osg::Program;
  program->setName(name);
  program->addShader(new osg::Shader(osg::Shader::VERTEX, vertex));
  program->addShader(new osg::Shader(osg::Shader::FRAGMENT, fragment));
  return program;
}

osg::Vec4 albedo(float r, float g, float b) { return osg::Vec4(r, g, b, 1.0f); }

// A quad in the HUD's pixel coordinates at eye-space z (orthographic, near -1, far 1: a larger z is nearer).
osg::ref_ptr<osg::Geometry> hud_quad(float x0, float y0, float x1, float y1, float z, const osg::Vec4& colour) {
  osg::ref_ptr<osg::Geometry> g = new osg::Geometry;
  osg::ref_ptr<osg::Vec3Array> v = new osg::Vec3Array;
  v->push_back({x0, y0, z});
  v->push_back({x1, y0, z});
  v->push_back({x1, y1, z});
  v->push_back({x0, y1, z});
  osg::ref_ptr<osg::Vec2Array> uv = new osg::Vec2Array;
  uv->push_back({0, 0});
  uv->push_back({1, 0});
  uv->push_back({1, 1});
  uv->push_back({0, 1});
  osg::ref_ptr<osg::Vec4Array> c = new osg::Vec4Array;
  c->push_back(colour);
  g->setVertexArray(v.get());
  g->setTexCoordArray(0, uv.get());
  g->setColorArray(c.get(), osg::Array::BIND_OVERALL);
  g->addPrimitiveSet(new osg::DrawArrays(GL_QUADS, 0, 4));
  g->setUseDisplayList(false);
  return g;
}

osg::ref_ptr<osg::Texture2D> rgb_texture(int width, int height, const std::vector<unsigned char>& rgb) {
  osg::ref_ptr<osg::Image> image = new osg::Image;
  image->allocateImage(width, height, 1, GL_RGB, GL_UNSIGNED_BYTE);
  image->setInternalTextureFormat(GL_RGB8);
  std::copy(rgb.begin(), rgb.end(), image->data());
  osg::ref_ptr<osg::Texture2D> texture = new osg::Texture2D(image.get());
  texture->setFilter(osg::Texture::MIN_FILTER, osg::Texture::NEAREST);
  texture->setFilter(osg::Texture::MAG_FILTER, osg::Texture::NEAREST);
  texture->setWrap(osg::Texture::WRAP_S, osg::Texture::CLAMP_TO_EDGE);
  texture->setWrap(osg::Texture::WRAP_T, osg::Texture::CLAMP_TO_EDGE);
  texture->setResizeNonPowerOfTwoHint(false);
  return texture;
}

}  // namespace

osg::ref_ptr<osg::Node> make_terrain(const hs::Terrain& terrain) {
  const int n = terrain.grid();
  const double size = terrain.options().size_m, step = size / (n - 1), half = 0.5 * size;
  const std::vector<float>& h = terrain.heights();
  const auto z = [&](int i, int j) {
    i = std::clamp(i, 0, n - 1);
    j = std::clamp(j, 0, n - 1);
    return static_cast<double>(h[static_cast<size_t>(j) * n + i]) - hs::curvature_drop_m(-half + i * step, -half + j * step);
  };
  osg::ref_ptr<osg::Vec3Array> vertices = new osg::Vec3Array;
  osg::ref_ptr<osg::Vec3Array> normals = new osg::Vec3Array;
  osg::ref_ptr<osg::Vec4Array> colours = new osg::Vec4Array;
  const double relief = std::max(terrain.options().relief_m, 1.0);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      vertices->push_back(osg::Vec3(float(-half + i * step), float(-half + j * step), float(z(i, j))));
      osg::Vec3 normal(float(z(i - 1, j) - z(i + 1, j)), float(z(i, j - 1) - z(i, j + 1)), float(2.0 * step));
      normal.normalize();
      normals->push_back(normal);
      // Grass on the plain, rock on the hill tops.
      const float t = float(std::clamp(h[static_cast<size_t>(j) * n + i] / relief, 0.0, 1.0));
      colours->push_back(albedo(0.09f + 0.09f * t, 0.13f + 0.03f * t, 0.05f + 0.08f * t));
    }
  }
  osg::ref_ptr<osg::DrawElementsUInt> triangles = new osg::DrawElementsUInt(GL_TRIANGLES);
  for (int j = 0; j + 1 < n; ++j) {
    for (int i = 0; i + 1 < n; ++i) {
      const unsigned a = unsigned(j * n + i), b = a + 1, c = a + unsigned(n), d = c + 1;
      for (unsigned index : {a, b, d, a, d, c}) triangles->push_back(index);
    }
  }
  osg::ref_ptr<osg::Geometry> ground = new osg::Geometry;
  ground->setVertexArray(vertices.get());
  ground->setNormalArray(normals.get(), osg::Array::BIND_PER_VERTEX);
  ground->setColorArray(colours.get(), osg::Array::BIND_PER_VERTEX);
  ground->addPrimitiveSet(triangles.get());
  ground->setUseDisplayList(false);
  ground->setUseVertexBufferObjects(true);

  // The runway: a dark strip along its heading, draped 0.3 m over the (flat) ground around it.
  const hs::TerrainOptions& o = terrain.options();
  const double heading = osg::DegreesToRadians(o.runway_heading_deg);
  const osg::Vec3d along(std::sin(heading), std::cos(heading), 0.0), across(along.y(), -along.x(), 0.0);
  osg::ref_ptr<osg::Vec3Array> strip = new osg::Vec3Array;
  const int segments = 30;
  for (int s = 0; s <= segments; ++s) {
    const double u = -0.5 * o.runway_length_m + o.runway_length_m * s / segments;
    for (int side = -1; side <= 1; side += 2) {
      osg::Vec3d p = along * u + across * (0.5 * o.runway_width_m * side);
      p.z() = terrain.height_at(p.x(), p.y()) - hs::curvature_drop_m(p.x(), p.y()) + 0.3;
      strip->push_back(p);
    }
  }
  osg::ref_ptr<osg::Geometry> runway = new osg::Geometry;
  runway->setVertexArray(strip.get());
  osg::ref_ptr<osg::Vec3Array> up = new osg::Vec3Array;
  up->push_back(osg::Vec3(0, 0, 1));
  runway->setNormalArray(up.get(), osg::Array::BIND_OVERALL);
  osg::ref_ptr<osg::Vec4Array> asphalt = new osg::Vec4Array;
  asphalt->push_back(albedo(0.07f, 0.07f, 0.07f));
  runway->setColorArray(asphalt.get(), osg::Array::BIND_OVERALL);
  runway->addPrimitiveSet(new osg::DrawArrays(GL_TRIANGLE_STRIP, 0, GLsizei(strip->size())));
  runway->setUseDisplayList(false);

  osg::ref_ptr<osg::Geode> geode = new osg::Geode;
  geode->setName("terrain");
  geode->addDrawable(ground.get());
  geode->addDrawable(runway.get());
  return geode;
}

osg::ref_ptr<osg::Node> make_models(const hs::Terrain& terrain) {
  osg::ref_ptr<osg::Group> models = new osg::Group;
  models->setName("models");
  // Each model stands on the ground at (east, north).
  const auto place = [&](double east, double north, osg::Shape* shape, const osg::Vec4& colour) {
    const double ground = terrain.height_at(east, north) - hs::curvature_drop_m(east, north);
    osg::ref_ptr<osg::MatrixTransform> at = new osg::MatrixTransform(osg::Matrixd::translate(east, north, ground));
    osg::ref_ptr<osg::ShapeDrawable> drawable = new osg::ShapeDrawable(shape);
    drawable->setColor(colour);
    drawable->setUseDisplayList(false);
    at->addChild(drawable.get());
    models->addChild(at.get());
  };
  // A hangar north of the runway's approach end: walls and an arched roof along its length.
  const osg::Vec4 hangar = albedo(0.45f, 0.47f, 0.50f);
  place(-1300.0, 160.0, new osg::Box(osg::Vec3(0, 0, 9), 90.0f, 60.0f, 18.0f), hangar);
  osg::ref_ptr<osg::Cylinder> roof = new osg::Cylinder(osg::Vec3(0, 0, 18), 30.0f, 90.0f);
  roof->setRotation(osg::Quat(osg::PI_2, osg::Vec3(0, 1, 0)));
  place(-1300.0, 160.0, roof.get(), hangar);
  // The control tower: a shaft, its cab and roof.
  const osg::Vec4 concrete = albedo(0.55f, 0.53f, 0.50f);
  place(-900.0, 260.0, new osg::Cylinder(osg::Vec3(0, 0, 16), 4.0f, 32.0f), concrete);
  place(-900.0, 260.0, new osg::Box(osg::Vec3(0, 0, 35), 11.0f, 11.0f, 6.0f), albedo(0.20f, 0.30f, 0.35f));
  place(-900.0, 260.0, new osg::Cone(osg::Vec3(0, 0, 38.5), 8.0f, 4.0f), albedo(0.60f, 0.15f, 0.10f));
  // Fuel tanks.
  for (int k = 0; k < 3; ++k)
    place(-700.0 + 25.0 * k, 200.0, new osg::Cylinder(osg::Vec3(0, 0, 6), 9.0f, 12.0f), albedo(0.70f, 0.70f, 0.68f));
  return models;
}

SceneLighting::SceneLighting() {
  program_ = make_program("atmo-osg-host surfaces", kSurfaceVertex, kSurfaceFragment);
  sun_direction_ = new osg::Uniform("u_sun_direction_enu", osg::Vec3(0, 0, 1));
  sun_lux_ = new osg::Uniform("u_sun_lux", osg::Vec3());
  sh9_ = new osg::Uniform(osg::Uniform::FLOAT_VEC3, "u_sky_sh9", 9);
  exposure_ = new osg::Uniform("u_exposure", 1.0f);
  enu_from_view_ = new osg::Uniform("u_enu_from_view", osg::Matrix3());
  for (osg::Uniform* u : {sun_direction_.get(), sun_lux_.get(), sh9_.get(), exposure_.get(), enu_from_view_.get()})
    u->setDataVariance(osg::Object::DYNAMIC);
}

void SceneLighting::attach(osg::StateSet* stateset) const {
  stateset->setAttribute(program_.get());
  for (osg::Uniform* u : {sun_direction_.get(), sun_lux_.get(), sh9_.get(), exposure_.get(), enu_from_view_.get()})
    stateset->addUniform(u);
}

void SceneLighting::set(const AtmoLighting* lighting, const osg::Matrixd& view, double exposure_scale) {
  osg::Vec3 sun(-0.5f, -0.5f, 0.7f), sun_lux(100000.0f, 100000.0f, 100000.0f);
  sun.normalize();
  std::array<osg::Vec3, 9> sh9{};
  sh9[0] = osg::Vec3(1.0f, 1.0f, 1.0f) * (15000.0f / 0.282095f);  // 15 klux from every direction
  if (lighting) {
    sun = osg::Vec3(float(lighting->sun_direction_enu[0]), float(lighting->sun_direction_enu[1]),
                    float(lighting->sun_direction_enu[2]));
    sun_lux = osg::Vec3(float(lighting->sun_illuminance_lux[0]), float(lighting->sun_illuminance_lux[1]),
                        float(lighting->sun_illuminance_lux[2]));
    for (int k = 0; k < 9; ++k)
      sh9[size_t(k)] = osg::Vec3(float(lighting->sky_irradiance_sh9[k][0]), float(lighting->sky_irradiance_sh9[k][1]),
                                 float(lighting->sky_irradiance_sh9[k][2]));
  }
  sun_direction_->set(sun);
  sun_lux_->set(sun_lux);
  for (unsigned k = 0; k < 9; ++k) sh9_->setElement(k, sh9[k]);
  exposure_->set(float(exposure_scale));
  // OSG multiplies row vectors (v' = v M) and uploads its matrices as they lie in memory, which GLSL reads
  // as the transpose: the mat3 whose GLSL product takes a view-space normal to ENU is the upper 3x3 of
  // OSG's inverse view matrix, element for element.
  const osg::Matrixd world_from_view = osg::Matrixd::inverse(view);
  osg::Matrix3 m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m(r, c) = float(world_from_view(r, c));
  enu_from_view_->set(m);
}

osg::ref_ptr<osg::Camera> make_tone_map_camera(osg::Texture2D* hdr_color, int width, int height, GLenum buffer) {
  osg::ref_ptr<osg::Camera> camera = new osg::Camera;
  camera->setName("tone map");
  camera->setRenderOrder(osg::Camera::POST_RENDER, 0);
  camera->setReferenceFrame(osg::Transform::ABSOLUTE_RF);
  camera->setProjectionMatrixAsOrtho2D(0, 1, 0, 1);
  camera->setViewMatrix(osg::Matrixd::identity());
  camera->setViewport(0, 0, width, height);
  camera->setClearMask(0);
  camera->setDrawBuffer(buffer);
  camera->setReadBuffer(buffer);
  camera->setAllowEventFocus(false);
  osg::ref_ptr<osg::Geometry> quad = hud_quad(0, 0, 1, 1, 0, osg::Vec4(1, 1, 1, 1));
  osg::StateSet* ss = quad->getOrCreateStateSet();
  const std::string fragment = "#version 330 compatibility\n" +
                               std::string(embedded_glsl::find("atmo/atmo_tone_map.glsl")) + kToneMapFragment;
  ss->setAttribute(make_program("atmo-osg-host tone map", kToneMapVertex, fragment).get());
  ss->setTextureAttribute(0, hdr_color);
  ss->addUniform(new osg::Uniform("u_hdr", 0));
  ss->setMode(GL_DEPTH_TEST, osg::StateAttribute::OFF);
  ss->setMode(GL_LIGHTING, osg::StateAttribute::OFF);
  camera->addChild(quad.get());
  return camera;
}

osg::ref_ptr<osg::Camera> make_hud_camera(int width, int height, GLenum buffer, std::array<int, 4>* panel) {
  osg::ref_ptr<osg::Camera> camera = new osg::Camera;
  camera->setName("HUD");
  camera->setRenderOrder(osg::Camera::POST_RENDER, 1);
  camera->setReferenceFrame(osg::Transform::ABSOLUTE_RF);
  camera->setProjectionMatrixAsOrtho(0, width, 0, height, -1, 1);
  camera->setViewMatrix(osg::Matrixd::identity());
  camera->setViewport(0, 0, width, height);
  camera->setClearMask(GL_DEPTH_BUFFER_BIT);
  camera->setDrawBuffer(buffer);
  camera->setReadBuffer(buffer);
  camera->setAllowEventFocus(false);
  osg::StateSet* hud_state = camera->getOrCreateStateSet();
  hud_state->setMode(GL_LIGHTING, osg::StateAttribute::OFF);
  hud_state->setMode(GL_DEPTH_TEST, osg::StateAttribute::ON);
  hud_state->setAttribute(new osg::Depth(osg::Depth::LESS));

  // Whole pixels, so both frames cover exactly the same ones.
  const int w = std::max(16, width / 4), h = std::max(8, height / 5), x = 8, y = 8;
  *panel = {x, y, w, h};
  const float x0 = float(x), y0 = float(y), x1 = float(x + w), y1 = float(y + h);

  // 1. The textured panel (program, units 0 and 1).
  osg::ref_ptr<osg::Geometry> base = hud_quad(x0, y0, x1, y1, 0.0f, osg::Vec4(1, 1, 1, 1));
  osg::StateSet* ss = base->getOrCreateStateSet();
  std::vector<unsigned char> checker;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) {
      const bool odd = ((i + j) & 1) != 0;
      checker.insert(checker.end(), {static_cast<unsigned char>(odd ? 230 : 40), static_cast<unsigned char>(odd ? 230 : 90),
                                     static_cast<unsigned char>(odd ? 230 : 160)});
    }
  ss->setTextureAttribute(0, rgb_texture(4, 4, checker).get());
  ss->setTextureAttribute(1, rgb_texture(2, 1, {255, 200, 160, 160, 220, 255}).get());
  ss->setAttribute(make_program("atmo-osg-host HUD", kHudVertex, kHudFragment).get());
  ss->addUniform(new osg::Uniform("u_checker", 0));
  ss->addUniform(new osg::Uniform("u_tint", 1));
  ss->setRenderBinDetails(1, "RenderBin");
  camera->addChild(base.get());

  // 2. A fixed-function quad (no program) in front of the panel's middle.
  osg::ref_ptr<osg::Geometry> solid = hud_quad(x0 + w / 3, y0 + h / 4, x0 + 2 * w / 3, y1 - h / 4, 0.5f,
                                               osg::Vec4(1.0f, 0.8f, 0.0f, 1.0f));
  solid->getOrCreateStateSet()->setAttribute(new osg::Program);  // an empty program: fixed function
  solid->getOrCreateStateSet()->setRenderBinDetails(2, "RenderBin");
  camera->addChild(solid.get());

  // 3. Half-transparent red blended over the panel's right end.
  osg::ref_ptr<osg::Geometry> glass = hud_quad(x1 - w / 4, y0, x1, y1, 0.25f, osg::Vec4(0.9f, 0.1f, 0.1f, 0.5f));
  osg::StateSet* glass_state = glass->getOrCreateStateSet();
  glass_state->setAttribute(new osg::Program);
  glass_state->setAttributeAndModes(new osg::BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA), osg::StateAttribute::ON);
  glass_state->setRenderBinDetails(3, "RenderBin");
  camera->addChild(glass.get());

  // 4. Green behind the panel (farther): hidden by the depth test, shown by a broken one.
  osg::ref_ptr<osg::Geometry> hidden = hud_quad(x0, y0, x0 + w / 4, y1, -0.5f, osg::Vec4(0.0f, 1.0f, 0.0f, 1.0f));
  hidden->getOrCreateStateSet()->setAttribute(new osg::Program);
  hidden->getOrCreateStateSet()->setRenderBinDetails(4, "RenderBin");
  camera->addChild(hidden.get());
  return camera;
}

}  // namespace atmo::osg_host
