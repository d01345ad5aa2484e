#include "atmo_support/example_view.h"

#include <glad/gl.h>

#include <cmath>
#include <cstring>
#include <vector>

namespace atmo::support {

AtmoViewState example_view_state(int width, int height, unsigned depth_texture, double height_m) {
  AtmoViewState v;
  std::memset(static_cast<void*>(&v), 0, sizeof(v));
  v.header.type = ATMO_TYPE_VIEW_STATE;
  v.header.struct_size = sizeof(v);
  v.eye_kind = ATMO_POSITION_GEODETIC;
  v.eye_geodetic[0] = 47.26;
  v.eye_geodetic[1] = 11.35;
  v.eye_geodetic[2] = height_m;
  v.world_frame = ATMO_WORLD_ENU;
  v.world_origin_geodetic[0] = 47.26;
  v.world_origin_geodetic[1] = 11.35;
  // Looking north, level: view x = east, y = up, z = south (column-major).
  const double looking_north[16] = {1, 0, 0, 0, 0, 0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1};
  std::memcpy(v.view_from_world, looking_north, sizeof(looking_north));
  const double f = 1.0 / std::tan(M_PI / 6.0), aspect = double(width) / height, n = 1.0, fa = 1e5;
  const double projection[16] = {f / aspect, 0, 0, 0, 0, f, 0, 0, 0, 0, (fa + n) / (n - fa), -1,
                                 0, 0, 2.0 * fa * n / (n - fa), 0};
  std::memcpy(v.clip_from_view, projection, sizeof(projection));
  v.viewport[2] = width;
  v.viewport[3] = height;
  v.depth_texture = depth_texture;
  v.exposure_scale = 1e-4;
  return v;
}

unsigned make_split_depth_texture(int width, int height, float geometry_depth) {
  std::vector<float> depth(static_cast<size_t>(width) * height, 1.0f);
  for (int y = 0; y < height / 2; ++y)
    for (int x = 0; x < width; ++x) depth[static_cast<size_t>(y) * width + x] = geometry_depth;
  return make_depth_texture(width, height, depth);
}

unsigned make_depth_texture(int width, int height, const std::vector<float>& depth) {
  GLint previous = 0;
  glGetIntegerv(GL_TEXTURE_BINDING_2D, &previous);
  GLuint t = 0;
  glGenTextures(1, &t);
  glBindTexture(GL_TEXTURE_2D, t);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT32F, width, height, 0, GL_DEPTH_COMPONENT, GL_FLOAT, depth.data());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glBindTexture(GL_TEXTURE_2D, static_cast<GLuint>(previous));
  return t;
}

}  // namespace atmo::support
