#include "atmo_host_scene/objects.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <fstream>
#include <iterator>
#include <optional>

#include <glad/gl.h>

#include "atmo_host_scene/gl_program.h"
#include "atmo_host_scene/sky_occlusion_binding.h"

namespace atmo::host_scene {

namespace {

const char* kVertex = R"(
layout(location = 0) in vec3 a_position;  // object frame, m
layout(location = 1) in vec3 a_normal;    // object frame, the face's
uniform mat4 u_clip_from_rel;    // projection * view rotation; positions are eye-relative
uniform mat4 u_rel_from_object;  // the object's pose, less the eye's position (ENU axes)
out vec3 v_normal;
out vec3 v_rel;
#ifdef LOG_DEPTH
out float v_w;
#endif
void main() {
  vec4 rel = u_rel_from_object * vec4(a_position, 1.0);
  gl_Position = u_clip_from_rel * rel;
  v_normal = mat3(u_rel_from_object) * a_normal;
  v_rel = rel.xyz;
#ifdef LOG_DEPTH
  v_w = gl_Position.w;  // = view-space distance along -z for a perspective matrix
#endif
}
)";

const char* kFragment = R"(
in vec3 v_normal;
in vec3 v_rel;  // the fragment's position relative to the eye, ENU (the view's world axes)
#ifdef LOG_DEPTH
in float v_w;
uniform float u_log_c;
uniform float u_log_inv;  // 1 / log2(C * far + 1)
#endif
uniform vec3 u_sky_sh9[9];  // get_lighting's sky irradiance, lux (atmo.h's basis, ENU)
uniform vec3 u_sun_dir;
uniform vec3 u_sun_lux;
uniform vec3 u_albedo;
uniform float u_exposure;
layout(location = 0) out vec4 o_color;
void main() {
  vec3 n = normalize(v_normal);
  vec3 sun = u_sun_lux * max(dot(n, u_sun_dir), 0.0);
#ifdef SKY_OCCLUSION
  // The objects' sky shadow, Sun shadow and bounce on this surface (atmo_sky_occlusion.glsl, pasted above).
  AtmoSkyOcclusion o = atmo_sky_occlusion(v_rel, n);
  vec3 e = o.sky_lux + o.bounce_lux + sun * o.sun_visibility;
#else
  vec3 sky = u_sky_sh9[0] * 0.282095 + u_sky_sh9[1] * (0.488603 * n.y) + u_sky_sh9[2] * (0.488603 * n.z) +
             u_sky_sh9[3] * (0.488603 * n.x) + u_sky_sh9[4] * (1.092548 * n.x * n.y) +
             u_sky_sh9[5] * (1.092548 * n.y * n.z) + u_sky_sh9[6] * (0.315392 * (3.0 * n.z * n.z - 1.0)) +
             u_sky_sh9[7] * (1.092548 * n.x * n.z) + u_sky_sh9[8] * (0.546274 * (n.x * n.x - n.y * n.y));
  vec3 e = max(sky, vec3(0.0)) + sun;
#endif
  o_color = vec4(u_albedo * (1.0 / 3.14159265) * e * u_exposure, 1.0);
#ifdef LOG_DEPTH
  gl_FragDepth = log2(u_log_c * v_w + 1.0) * u_log_inv;
#endif
}
)";

struct Vertex {
  float position[3];
  float normal[3];
};

// Saves and restores the GL state draw() changes.
class SavedState {
 public:
  SavedState() {
    glGetIntegerv(GL_CURRENT_PROGRAM, &program_);
    glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &vao_);
    blend_ = glIsEnabled(GL_BLEND);
    cull_ = glIsEnabled(GL_CULL_FACE);
    glGetIntegerv(GL_CULL_FACE_MODE, &cull_mode_);
    glGetIntegerv(GL_FRONT_FACE, &front_face_);
    GLboolean mask = GL_TRUE;
    glGetBooleanv(GL_DEPTH_WRITEMASK, &mask);
    depth_mask_ = mask;
  }
  ~SavedState() {
    glUseProgram(static_cast<GLuint>(program_));
    glBindVertexArray(static_cast<GLuint>(vao_));
    blend_ ? glEnable(GL_BLEND) : glDisable(GL_BLEND);
    cull_ ? glEnable(GL_CULL_FACE) : glDisable(GL_CULL_FACE);
    glCullFace(static_cast<GLenum>(cull_mode_));
    glFrontFace(static_cast<GLenum>(front_face_));
    glDepthMask(depth_mask_ ? GL_TRUE : GL_FALSE);
  }
  SavedState(const SavedState&) = delete;
  SavedState& operator=(const SavedState&) = delete;

 private:
  GLint program_ = 0, vao_ = 0, cull_mode_ = GL_BACK, front_face_ = GL_CCW;
  GLboolean blend_ = GL_FALSE, cull_ = GL_FALSE, depth_mask_ = GL_TRUE;
};

}  // namespace

ObjectLighting object_lighting_from_atmo(const AtmoLighting& lighting) {
  ObjectLighting out;
  for (int k = 0; k < 9; ++k)
    out.sky_irradiance_sh9[k] = glm::dvec3(lighting.sky_irradiance_sh9[k][0], lighting.sky_irradiance_sh9[k][1],
                                           lighting.sky_irradiance_sh9[k][2]);
  const glm::dvec3 sun(lighting.sun_direction_enu[0], lighting.sun_direction_enu[1], lighting.sun_direction_enu[2]);
  const double len = glm::length(sun);
  out.sun_direction_enu = len > 0.0 ? sun / len : glm::dvec3(0.0, 0.0, 1.0);
  out.sun_illuminance_lux = glm::dvec3(lighting.sun_illuminance_lux[0], lighting.sun_illuminance_lux[1],
                                       lighting.sun_illuminance_lux[2]);
  return out;
}

glm::dvec3 object_irradiance(const ObjectLighting& l, const glm::dvec3& normal) {
  const glm::dvec3 n = glm::normalize(normal);
  const double y[9] = {0.282095,       0.488603 * n.y,       0.488603 * n.z,
                       0.488603 * n.x, 1.092548 * n.x * n.y, 1.092548 * n.y * n.z,
                       0.315392 * (3.0 * n.z * n.z - 1.0), 1.092548 * n.x * n.z, 0.546274 * (n.x * n.x - n.y * n.y)};
  glm::dvec3 sky(0.0);
  for (int k = 0; k < 9; ++k) sky += l.sky_irradiance_sh9[k] * y[k];
  return glm::max(sky, glm::dvec3(0.0)) + l.sun_illuminance_lux * std::max(glm::dot(n, l.sun_direction_enu), 0.0);
}

glm::dmat4 enu_from_object_pose(const glm::dvec3& position_enu_m, double heading_deg) {
  const double h = glm::radians(heading_deg);
  const glm::dvec3 forward(std::sin(h), std::cos(h), 0.0);  // object x
  const glm::dvec3 left(-std::cos(h), std::sin(h), 0.0);    // object y: up x forward
  glm::dmat4 m(1.0);
  m[0] = glm::dvec4(forward, 0.0);
  m[1] = glm::dvec4(left, 0.0);
  m[2] = glm::dvec4(0.0, 0.0, 1.0, 0.0);
  m[3] = glm::dvec4(position_enu_m, 1.0);
  return m;
}

bool ObjectMeshes::gl_init(const std::vector<const spheres::TriangleMesh*>& meshes, std::string* error) {
  gl_shutdown();
  std::vector<Vertex> vertices;
  meshes_.clear();
  for (size_t m = 0; m < meshes.size(); ++m) {
    const spheres::TriangleMesh* mesh = meshes[m];
    if (!mesh || mesh->triangles.empty()) {
      *error = "host_scene objects: mesh " + std::to_string(m) + " has no triangles";
      meshes_.clear();
      return false;
    }
    Range range;
    range.first = static_cast<int>(vertices.size());
    for (size_t t = 0; t < mesh->triangles.size(); ++t) {
      const glm::uvec3& tri = mesh->triangles[t];
      if (tri.x >= mesh->vertices.size() || tri.y >= mesh->vertices.size() || tri.z >= mesh->vertices.size()) {
        *error = "host_scene objects: mesh " + std::to_string(m) + ": triangle " + std::to_string(t) +
                 " indexes a vertex past its " + std::to_string(mesh->vertices.size());
        meshes_.clear();
        return false;
      }
      const glm::dvec3 a = mesh->vertices[tri.x], b = mesh->vertices[tri.y], c = mesh->vertices[tri.z];
      const glm::dvec3 cross = glm::cross(b - a, c - a);
      const double len = glm::length(cross);
      if (!(len > 0.0)) continue;  // a degenerate triangle covers no pixel
      const glm::dvec3 n = cross / len;
      for (const glm::dvec3& p : {a, b, c}) {
        Vertex v{};
        for (int k = 0; k < 3; ++k) {
          v.position[k] = static_cast<float>(p[k]);
          v.normal[k] = static_cast<float>(n[k]);
        }
        vertices.push_back(v);
      }
    }
    range.count = static_cast<int>(vertices.size()) - range.first;
    meshes_.push_back(range);
  }

  // The host SDK's sky occlusion include, pasted after the defines (as a host without #include does).
  std::string include;
  {
    std::ifstream in(ATMO_HOST_SDK_INCLUDE_DIR "/atmo/atmo_sky_occlusion.glsl");
    if (!in) {
      *error = "cannot read " ATMO_HOST_SDK_INCLUDE_DIR "/atmo/atmo_sky_occlusion.glsl";
      meshes_.clear();
      return false;
    }
    include.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  // [depth][shading]: shading 0 the open sky (SH9), 1 the include, 2 the include with its bounce compiled out
  // (ATMO_OCC_NO_BOUNCE: for occluders set with ATMO_OCCLUSION_NO_BOUNCE, about half the cost).
  static const char* const kShading[3] = {"", "#define SKY_OCCLUSION 1\n", "#define SKY_OCCLUSION 1\n#define ATMO_OCC_NO_BOUNCE 1\n"};
  for (int depth = 0; depth < 2; ++depth)
    for (int shading = 0; shading < 3; ++shading) {
      const std::string defines = std::string(depth == 1 ? "#define LOG_DEPTH 1\n" : "") + kShading[shading] +
                                  (shading > 0 ? include : std::string());
      program_[depth][shading] = build_program(kVertex, kFragment, defines,
                                               shading ? "host_scene objects with sky occlusion" : "host_scene objects",
                                               error);
      if (!program_[depth][shading]) {
        gl_shutdown();
        return false;
      }
    }
  GLint old_vao = 0, old_array = 0;
  glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &old_vao);
  glGetIntegerv(GL_ARRAY_BUFFER_BINDING, &old_array);
  glGenVertexArrays(1, &vao_);
  glGenBuffers(1, &vbo_);
  glBindVertexArray(vao_);
  glBindBuffer(GL_ARRAY_BUFFER, vbo_);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices.size() * sizeof(Vertex)), vertices.data(),
               GL_STATIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(Vertex), reinterpret_cast<const void*>(offsetof(Vertex, position)));
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(Vertex), reinterpret_cast<const void*>(offsetof(Vertex, normal)));
  glBindVertexArray(static_cast<GLuint>(old_vao));
  glBindBuffer(GL_ARRAY_BUFFER, static_cast<GLuint>(old_array));
  const GLenum gl_error = glGetError();
  if (gl_error != GL_NO_ERROR) {
    *error = "host_scene objects: GL error " + std::to_string(gl_error) + " uploading " +
             std::to_string(vertices.size()) + " vertices";
    gl_shutdown();
    return false;
  }
  gl_ready_ = true;
  return true;
}

void ObjectMeshes::gl_shutdown() {
  for (auto& variants : program_)
    for (unsigned& p : variants) {
      if (p) glDeleteProgram(p);
      p = 0;
    }
  if (vao_) glDeleteVertexArrays(1, &vao_);
  if (vbo_) glDeleteBuffers(1, &vbo_);
  vao_ = vbo_ = 0;
  gl_ready_ = false;
}

void ObjectMeshes::draw(const ViewSetup& view, const ObjectLighting& lighting, const std::vector<ObjectInstance>& instances,
                        const AtmoSkyOcclusion* occlusion, int first_unit) const {
  if (!gl_ready_ || instances.empty()) return;
  const SavedState saved;
  const glm::dmat4 rotation(glm::dmat3(view_from_enu(view)));
  const glm::mat4 clip_from_rel(clip_from_view(view) * rotation);
  const int variant = view.depth_convention == DepthConvention::Logarithmic ? 1 : 0;
  const bool occluded = occlusion && occlusion->object_count > 0;
  // AtmoSkyOcclusion.grid[3]: flags, 1 the bounce (atmo_occ_grid.w).
  const bool bounce = occluded && (static_cast<int>(occlusion->grid[3] + 0.5) & 1) != 0;
  const GLuint program = program_[variant][occluded ? (bounce ? 1 : 2) : 0];
  glUseProgram(program);
  std::optional<SkyOcclusionBinding> binding;  // atmo_sky_occlusion.glsl's inputs, as its header says
  if (occluded) binding.emplace(program, *occlusion, first_unit);
  glUniformMatrix4fv(glGetUniformLocation(program, "u_clip_from_rel"), 1, GL_FALSE, &clip_from_rel[0][0]);
  if (variant == 1) {
    const double c = kLogDepthCoefficient;
    glUniform1f(glGetUniformLocation(program, "u_log_c"), static_cast<float>(c));
    glUniform1f(glGetUniformLocation(program, "u_log_inv"), static_cast<float>(1.0 / std::log2(c * view.far_m + 1.0)));
  }
  float sh9[27];
  for (int k = 0; k < 9; ++k)
    for (int c = 0; c < 3; ++c) sh9[k * 3 + c] = static_cast<float>(lighting.sky_irradiance_sh9[k][c]);
  glUniform3fv(glGetUniformLocation(program, "u_sky_sh9"), 9, sh9);
  const glm::vec3 sun_dir(lighting.sun_direction_enu), sun_lux(lighting.sun_illuminance_lux);
  glUniform3fv(glGetUniformLocation(program, "u_sun_dir"), 1, &sun_dir[0]);
  glUniform3fv(glGetUniformLocation(program, "u_sun_lux"), 1, &sun_lux[0]);
  glUniform1f(glGetUniformLocation(program, "u_exposure"), static_cast<float>(view.exposure_scale));
  const GLint rel_from_object = glGetUniformLocation(program, "u_rel_from_object");
  const GLint albedo = glGetUniformLocation(program, "u_albedo");

  glDisable(GL_BLEND);
  glDepthMask(GL_TRUE);
  glEnable(GL_CULL_FACE);
  glCullFace(GL_BACK);
  glFrontFace(GL_CCW);
  glBindVertexArray(vao_);
  for (const ObjectInstance& instance : instances) {
    if (instance.mesh >= meshes_.size()) continue;
    // Eye-relative in double, then float: the translation is the object's offset from the eye.
    glm::dmat4 rel = instance.enu_from_object;
    rel[3] = glm::dvec4(glm::dvec3(rel[3]) - view.pose.position_enu_m, 1.0);
    const glm::mat4 rel_f(rel);
    const glm::vec3 a(instance.albedo);
    glUniformMatrix4fv(rel_from_object, 1, GL_FALSE, &rel_f[0][0]);
    glUniform3fv(albedo, 1, &a[0]);
    glDrawArrays(GL_TRIANGLES, meshes_[instance.mesh].first, meshes_[instance.mesh].count);
  }
}

std::vector<AtmoOccluderSphere> occluder_spheres(const spheres::SphereSet& set) {
  std::vector<AtmoOccluderSphere> list;
  for (const spheres::Sphere& sp : set.spheres) {
    AtmoOccluderSphere a{};
    for (int k = 0; k < 3; ++k) a.centre_m[k] = sp.centre_m[k];
    a.radius_m = sp.radius_m;
    list.push_back(a);
  }
  return list;
}

}  // namespace atmo::host_scene
