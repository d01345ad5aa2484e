#include "atmo_host_scene/camera.h"

#include <cmath>
#include <cstring>

#include <GeographicLib/LocalCartesian.hpp>

namespace atmo::host_scene {

AtmoDepthConvention to_atmo(DepthConvention convention) {
  switch (convention) {
    case DepthConvention::Standard: return ATMO_DEPTH_STANDARD;
    case DepthConvention::Reversed: return ATMO_DEPTH_REVERSED_ZERO_TO_ONE;
    case DepthConvention::Logarithmic: return ATMO_DEPTH_LOGARITHMIC;
  }
  return ATMO_DEPTH_STANDARD;
}

const char* to_string(DepthConvention convention) {
  switch (convention) {
    case DepthConvention::Standard: return "standard";
    case DepthConvention::Reversed: return "reversed";
    case DepthConvention::Logarithmic: return "logarithmic";
  }
  return "?";
}

bool parse_depth_convention(const char* text, DepthConvention* out) {
  if (!text || !out) return false;
  if (std::strcmp(text, "standard") == 0) {
    *out = DepthConvention::Standard;
  } else if (std::strcmp(text, "reversed") == 0 || std::strcmp(text, "reversed-z") == 0) {
    *out = DepthConvention::Reversed;
  } else if (std::strcmp(text, "log") == 0 || std::strcmp(text, "logarithmic") == 0) {
    *out = DepthConvention::Logarithmic;
  } else {
    return false;
  }
  return true;
}

double logarithmic_depth(double w, double far_m, double coefficient) {
  return std::log2(coefficient * w + 1.0) / std::log2(coefficient * far_m + 1.0);
}

glm::dmat3 enu_from_camera_rotation(const CameraPose& pose) {
  const double h = glm::radians(pose.heading_deg);
  const double p = glm::radians(pose.pitch_deg);
  const double r = glm::radians(pose.roll_deg);
  // Level camera looking north: right = east, up = up, back = south.
  const glm::dmat3 level(glm::dvec3(1, 0, 0), glm::dvec3(0, 0, 1), glm::dvec3(0, -1, 0));
  // Heading turns clockwise seen from above: a rotation about +z by -h.
  const double ch = std::cos(h), sh = std::sin(h);
  const glm::dmat3 yaw(glm::dvec3(ch, -sh, 0), glm::dvec3(sh, ch, 0), glm::dvec3(0, 0, 1));
  // Pitch up turns north towards up: a rotation about +x (east) by +p.
  const double cp = std::cos(p), sp = std::sin(p);
  const glm::dmat3 pitch(glm::dvec3(1, 0, 0), glm::dvec3(0, cp, sp), glm::dvec3(0, -sp, cp));
  // Roll about the camera's back axis by -r tilts up towards the right.
  const double cr = std::cos(r), sr = std::sin(r);
  const glm::dmat3 roll(glm::dvec3(cr, -sr, 0), glm::dvec3(sr, cr, 0), glm::dvec3(0, 0, 1));
  return yaw * pitch * level * roll;
}

glm::dvec3 forward_enu(const CameraPose& pose) { return -enu_from_camera_rotation(pose)[2]; }

glm::dmat4 view_from_enu(const CameraPose& pose) {
  const glm::dmat3 camera_from_enu = glm::transpose(enu_from_camera_rotation(pose));
  glm::dmat4 m(camera_from_enu);
  m[3] = glm::dvec4(-(camera_from_enu * pose.position_enu_m), 1.0);
  return m;
}

glm::dmat4 projection(double vfov_rad, double aspect, double near_m, double far_m,
                      DepthConvention convention) {
  const double f = 1.0 / std::tan(0.5 * vfov_rad);
  glm::dmat4 m(0.0);
  m[0][0] = f / aspect;
  m[1][1] = f;
  m[2][3] = -1.0;  // w_clip = -z_view
  if (convention == DepthConvention::Reversed) {
    // z_clip = near, so depth = near / w: 1 at the near plane, 0 at infinity.
    m[3][2] = near_m;
  } else {
    m[2][2] = -(far_m + near_m) / (far_m - near_m);
    m[3][2] = -2.0 * far_m * near_m / (far_m - near_m);
  }
  return m;
}

Geodetic geodetic_from_enu(const Geodetic& origin, const glm::dvec3& enu_m) {
  const GeographicLib::LocalCartesian frame(origin.latitude_deg, origin.longitude_deg, origin.height_m);
  Geodetic g;
  frame.Reverse(enu_m.x, enu_m.y, enu_m.z, g.latitude_deg, g.longitude_deg, g.height_m);
  return g;
}

glm::dvec3 enu_from_geodetic(const Geodetic& origin, const Geodetic& point) {
  const GeographicLib::LocalCartesian frame(origin.latitude_deg, origin.longitude_deg, origin.height_m);
  glm::dvec3 enu;
  frame.Forward(point.latitude_deg, point.longitude_deg, point.height_m, enu.x, enu.y, enu.z);
  return enu;
}

double aspect(const ViewSetup& setup) {
  const double h = setup.viewport[3] > 0 ? setup.viewport[3] : 1;
  return static_cast<double>(setup.viewport[2]) / h;
}

glm::dmat4 view_from_enu(const ViewSetup& setup) { return view_from_enu(setup.pose); }

glm::dmat4 clip_from_view(const ViewSetup& setup) {
  return projection(setup.vfov_rad, aspect(setup), setup.near_m, setup.far_m, setup.depth_convention);
}

Geodetic eye_geodetic(const ViewSetup& setup) {
  return geodetic_from_enu(setup.world_origin, setup.pose.position_enu_m);
}

AtmoViewState make_view_state(const ViewSetup& setup) {
  AtmoViewState s;
  std::memset(&s, 0, sizeof s);
  s.header.type = ATMO_TYPE_VIEW_STATE;
  s.header.struct_size = sizeof(AtmoViewState);
  s.header.next = nullptr;

  const Geodetic eye = eye_geodetic(setup);
  s.eye_kind = ATMO_POSITION_GEODETIC;
  s.world_frame = ATMO_WORLD_ENU;
  s.eye_geodetic[0] = eye.latitude_deg;
  s.eye_geodetic[1] = eye.longitude_deg;
  s.eye_geodetic[2] = eye.height_m;
  s.world_origin_geodetic[0] = setup.world_origin.latitude_deg;
  s.world_origin_geodetic[1] = setup.world_origin.longitude_deg;
  s.world_origin_geodetic[2] = setup.world_origin.height_m;

  const glm::dmat4 view = view_from_enu(setup);
  const glm::dmat4 proj = clip_from_view(setup);
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      s.view_from_world[c * 4 + r] = view[c][r];
      s.clip_from_view[c * 4 + r] = proj[c][r];
    }
  }
  for (int i = 0; i < 4; ++i) s.viewport[i] = setup.viewport[i];

  s.depth_texture = setup.depth_texture;
  s.depth_convention = static_cast<uint32_t>(to_atmo(setup.depth_convention));
  if (setup.depth_convention == DepthConvention::Logarithmic) {
    s.far_plane_m = setup.far_m;
    s.log_depth_coefficient = kLogDepthCoefficient;
  }
  s.output_encoding = static_cast<uint32_t>(setup.output_encoding);
  s.exposure_scale = setup.exposure_scale;
  s.cloud_quality = setup.cloud_quality;
  return s;
}

double exposure_scale_from_ev100(double ev100) { return 1.0 / (1.2 * std::exp2(ev100)); }

}  // namespace atmo::host_scene
