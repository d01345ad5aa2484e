// camera.h — the host's camera in a local east-north-up (ENU) world frame whose
// origin is a geodetic point, the three depth conventions Atmo understands, and
// the one place that fills an AtmoViewState, so every host does it the same way.
#ifndef ATMO_HOST_SCENE_CAMERA_H
#define ATMO_HOST_SCENE_CAMERA_H

#include <array>
#include <cstdint>

#include <glm/glm.hpp>

#include "atmo/atmo.h"

namespace atmo::host_scene {

enum class DepthConvention {
  Standard,     // classic GL perspective, NDC z in [-1,1], near -> 0, far -> 1
  Reversed,     // reverse-Z, infinite far plane, glClipControl ZERO_TO_ONE: near -> 1, infinity -> 0
  Logarithmic,  // standard matrix; the fragment shader writes log2(C*w + 1) / log2(C*far + 1)
};

AtmoDepthConvention to_atmo(DepthConvention convention);
const char* to_string(DepthConvention convention);
// Parses "standard", "reversed" or "log"/"logarithmic"; false if unknown.
bool parse_depth_convention(const char* text, DepthConvention* out);

// The C of ATMO_DEPTH_LOGARITHMIC used by every host-scene shader.
constexpr double kLogDepthCoefficient = 1.0;

// Logarithmic depth of a view-space distance w (along -z), as the shaders write it.
double logarithmic_depth(double w, double far_m, double coefficient = kLogDepthCoefficient);

struct Geodetic {
  double latitude_deg = 0.0;
  double longitude_deg = 0.0;
  double height_m = 0.0;  // above the WGS84 ellipsoid
};

// heading 0 = north, clockwise (90 = east); pitch positive up; roll positive
// right side down (the camera's up tilts to the right).
struct CameraPose {
  glm::dvec3 position_enu_m{0.0};
  double heading_deg = 0.0;
  double pitch_deg = 0.0;
  double roll_deg = 0.0;
};

// Rotation from camera axes (x right, y up, z back; the camera looks down -z)
// to ENU axes.
glm::dmat3 enu_from_camera_rotation(const CameraPose& pose);
// Unit viewing direction in ENU.
glm::dvec3 forward_enu(const CameraPose& pose);
// OpenGL view matrix: ENU world -> camera (looks down -z, +y up).
glm::dmat4 view_from_enu(const CameraPose& pose);

// Perspective projection for a convention. Reversed ignores far_m (infinite).
// Logarithmic is the Standard matrix: depth comes from the fragment shader.
glm::dmat4 projection(double vfov_rad, double aspect, double near_m, double far_m,
                      DepthConvention convention);

// Geodetic position of a point given in the ENU frame at `origin` (WGS84,
// GeographicLib::LocalCartesian), and the inverse.
Geodetic geodetic_from_enu(const Geodetic& origin, const glm::dvec3& enu_m);
glm::dvec3 enu_from_geodetic(const Geodetic& origin, const Geodetic& point);

// Everything a host needs to draw one view with Atmo.
struct ViewSetup {
  Geodetic world_origin;                   // origin of the ENU world frame
  CameraPose pose;                         // camera in that frame
  double vfov_rad = glm::radians(60.0);
  double near_m = 1.0;
  double far_m = 200000.0;                 // Standard / Logarithmic far plane
  DepthConvention depth_convention = DepthConvention::Reversed;
  std::array<int32_t, 4> viewport{0, 0, 1, 1};  // x, y, width, height (pixels)
  uint32_t depth_texture = 0;              // host depth texture, 0: none
  AtmoOutputEncoding output_encoding = ATMO_OUTPUT_LINEAR_HDR;
  double exposure_scale = 1.0 / (1.2 * 32768.0);  // EV100 = 15
  AtmoCloudQuality cloud_quality = ATMO_CLOUD_QUALITY_DEFAULT;  // the layer march's cost knob
};

double aspect(const ViewSetup& setup);
glm::dmat4 view_from_enu(const ViewSetup& setup);
glm::dmat4 clip_from_view(const ViewSetup& setup);
Geodetic eye_geodetic(const ViewSetup& setup);

// Fills an AtmoViewState (header included): geodetic eye, ENU world frame with
// its origin, view and projection matrices, viewport, depth texture and
// convention (far and C for logarithmic), output encoding, exposure, cloud quality.
AtmoViewState make_view_state(const ViewSetup& setup);

// Photographic exposure: cd/m^2 -> output units, 1 / (1.2 * 2^EV100).
double exposure_scale_from_ev100(double ev100);

}  // namespace atmo::host_scene

#endif  // ATMO_HOST_SCENE_CAMERA_H
