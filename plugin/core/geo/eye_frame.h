// eye_frame.h — where the eye is and how the host's camera is oriented, in the
// frames the passes use. Everything here is double precision; the passes get
// eye-relative float quantities only, so ECEF coordinates of 6 400 km lose
// nothing.
#pragma once

#include <glm/glm.hpp>
#include <string>

#include "core/geo/geodesy.h"

namespace atmo::core {

enum class WorldFrame { Ecef, Enu };

struct CameraInput {
  bool eye_is_geodetic = false;
  glm::dvec3 eye_ecef_m{0.0};
  Geodetic eye_geodetic;
  WorldFrame world_frame = WorldFrame::Ecef;
  Geodetic world_origin;           // ENU world frame only
  glm::dmat4 view_from_world{1.0};
  glm::dmat4 clip_from_view{1.0};
};

struct EyeFrame {
  glm::dvec3 eye_ecef_m{0.0};
  Geodetic eye;                    // geodetic position of the eye
  glm::dmat3 ecef_from_enu{1.0};   // ENU axes at the eye
  glm::dmat3 enu_from_view{1.0};   // camera orientation (view axes -> ENU at the eye)
  glm::dmat4 view_from_clip{1.0};  // inverse projection
};

// Builds the eye frame. Fails (returns false, *error says why) when the view
// rotation is singular or the projection cannot be inverted.
bool make_eye_frame(const CameraInput& in, EyeFrame* out, std::string* error);

// Direction (ENU at the eye) of a unit ECEF vector.
inline glm::dvec3 enu_from_ecef_direction(const EyeFrame& f, const glm::dvec3& d) {
  return glm::transpose(f.ecef_from_enu) * d;
}

}  // namespace atmo::core
