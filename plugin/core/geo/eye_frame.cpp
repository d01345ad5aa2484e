#include "core/geo/eye_frame.h"

#include <cmath>

namespace atmo::core {

bool make_eye_frame(const CameraInput& in, EyeFrame* out, std::string* error) {
  EyeFrame f;
  if (in.eye_is_geodetic) {
    f.eye = in.eye_geodetic;
    f.eye_ecef_m = ecef_from_geodetic(in.eye_geodetic);
  } else {
    f.eye_ecef_m = in.eye_ecef_m;
    f.eye = geodetic_from_ecef(in.eye_ecef_m);
  }
  f.ecef_from_enu = ecef_from_enu(f.eye.latitude_deg, f.eye.longitude_deg);

  // Rotation part of the view matrix, orthonormalised against float round-off
  // (the ABI refuses scale, shear and mirrors: abi/validation.cpp); the
  // translation is ignored because the eye is given.
  glm::dmat3 view_rot(in.view_from_world);
  glm::dvec3 r0 = glm::dvec3(view_rot[0][0], view_rot[1][0], view_rot[2][0]);  // view x in world
  glm::dvec3 r1 = glm::dvec3(view_rot[0][1], view_rot[1][1], view_rot[2][1]);  // view y in world
  double l0 = glm::length(r0), l1 = glm::length(r1);
  if (!(l0 > 1e-12) || !(l1 > 1e-12)) {
    if (error) *error = "view_from_world: rotation part is singular (zero row)";
    return false;
  }
  glm::dvec3 x = r0 / l0;
  glm::dvec3 y = r1 - x * glm::dot(x, r1);
  double ly = glm::length(y);
  if (!(ly > 1e-9)) {
    if (error) *error = "view_from_world: rotation part is singular (parallel rows)";
    return false;
  }
  y /= ly;
  glm::dvec3 z = glm::cross(x, y);
  glm::dmat3 world_from_view(x, y, z);  // columns: view axes in world

  glm::dmat3 ecef_from_world(1.0);
  if (in.world_frame == WorldFrame::Enu) {
    ecef_from_world = ecef_from_enu(in.world_origin.latitude_deg, in.world_origin.longitude_deg);
  }
  f.enu_from_view = glm::transpose(f.ecef_from_enu) * ecef_from_world * world_from_view;

  double det = glm::determinant(in.clip_from_view);
  if (!std::isfinite(det) || std::abs(det) < 1e-300) {
    if (error) *error = "clip_from_view: matrix is singular";
    return false;
  }
  f.view_from_clip = glm::inverse(in.clip_from_view);
  *out = f;
  return true;
}

}  // namespace atmo::core
