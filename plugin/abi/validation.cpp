#include "abi/validation.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <sstream>

#include "core/astro/observer.h"
#include "core/astro/time_scales.h"

namespace atmo::abi {

std::string number(double v) {
  if (std::isfinite(v) && std::floor(v) == v && std::fabs(v) < 1e15) {
    std::ostringstream s;
    s << std::fixed << std::setprecision(0) << v;
    return s.str();
  }
  std::string text;
  for (int digits = 10; digits <= 17; ++digits) {
    std::ostringstream s;
    s.precision(digits);
    s << v;
    text = s.str();
    if (std::strtod(text.c_str(), nullptr) == v) break;
  }
  return text;
}

namespace {

// Each check returns false and fills the verdict on failure.
bool finite(Verdict* v, const char* field, double value) {
  if (std::isfinite(value)) return true;
  *v = {ATMO_ERROR_NON_FINITE_VALUE, std::string(field) + " is " + number(value) + ", must be finite"};
  return false;
}

bool finite_array(Verdict* v, const char* field, const double* values, int n) {
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(values[i])) {
      *v = {ATMO_ERROR_NON_FINITE_VALUE,
            std::string(field) + "[" + std::to_string(i) + "] is " + number(values[i]) + ", must be finite"};
      return false;
    }
  }
  return true;
}

bool in_range(Verdict* v, const char* field, double value, double lo, double hi, const char* unit) {
  if (!finite(v, field, value)) return false;
  if (value >= lo && value <= hi) return true;
  *v = {ATMO_ERROR_OUT_OF_RANGE, std::string(field) + " = " + number(value) + " is outside [" + number(lo) + ", " +
                                     number(hi) + "] " + unit};
  return false;
}

bool enum_value(Verdict* v, const char* field, uint32_t value, uint32_t count) {
  if (value < count) return true;
  *v = {ATMO_ERROR_INVALID_ARGUMENT,
        std::string(field) + " = " + std::to_string(value) + " is not a valid value (0.." + std::to_string(count - 1) + ")"};
  return false;
}

// 0 (the default) or within [lo, hi].
bool table_size(Verdict* v, const char* field, uint32_t value, uint32_t lo, uint32_t hi) {
  if (value == 0 || (value >= lo && value <= hi)) return true;
  *v = {ATMO_ERROR_INVALID_ARGUMENT, std::string(field) + " = " + std::to_string(value) + " is outside [" +
                                         std::to_string(lo) + ", " + std::to_string(hi) + "] (0 takes the default)"};
  return false;
}

// view_from_world must be a rigid transform (docs/ABI.md): its upper 3x3 a
// rotation, R R^T = I and det R = +1, each to kRotationTolerance (float
// round-off of a host's matrices is ~1e-6), and its bottom row (0, 0, 0, 1).
// The translation is not used (the eye is given); it need only be finite.
constexpr double kRotationTolerance = 1e-3;
// clip_from_view must be invertible and well conditioned: its condition number
// in the infinity norm, |P| |P^-1|, at most kMaxProjectionCondition (a
// perspective with near 1e-4 m, far 1e7 m has ~1e4; an infinite reversed-Z one
// with near 0.01 m ~1e2).
constexpr double kMaxProjectionCondition = 1e10;

// NaN when any entry is NaN (the inverse of a singular matrix).
double infinity_norm(const glm::dmat4& m) {
  double norm = 0.0;
  for (int r = 0; r < 4; ++r) {
    const double row = std::abs(m[0][r]) + std::abs(m[1][r]) + std::abs(m[2][r]) + std::abs(m[3][r]);
    if (std::isnan(row)) return row;
    norm = std::max(norm, row);
  }
  return norm;
}

}  // namespace

glm::dmat4 matrix(const double m[16]) {
  glm::dmat4 out;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) out[c][r] = m[c * 4 + r];
  return out;
}

bool rigid_transform(Verdict* v, const glm::dmat4& m, const std::string& name) {
  const glm::dmat3 rot(m);
  double worst = 0.0;
  const glm::dmat3 gram = rot * glm::transpose(rot);
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) {
      const double e = std::abs(gram[c][r] - (c == r ? 1.0 : 0.0));
      if (std::isnan(e) || e > worst) worst = e;  // a NaN stays
    }
  if (!(worst <= kRotationTolerance)) {
    *v = {ATMO_ERROR_OUT_OF_RANGE, name + ": the upper 3x3 is not a rotation (max |R R^T - I| = " +
                                       number(worst) + ", tolerance " + number(kRotationTolerance) + ")"};
    return false;
  }
  if (!(glm::determinant(rot) > 0.0)) {
    *v = {ATMO_ERROR_OUT_OF_RANGE, name + ": the upper 3x3 is a reflection (det " +
                                       number(glm::determinant(rot)) + "), not a rotation"};
    return false;
  }
  const double bottom[4] = {m[0][3], m[1][3], m[2][3], m[3][3] - 1.0};
  for (int c = 0; c < 4; ++c) {
    if (!(std::abs(bottom[c]) <= kRotationTolerance)) {
      *v = {ATMO_ERROR_OUT_OF_RANGE, name + "[" + std::to_string(c * 4 + 3) + "] = " +
                                         number(c == 3 ? m[3][3] : bottom[c]) +
                                         ": the bottom row must be (0, 0, 0, 1)"};
      return false;
    }
  }
  return true;
}

namespace {

bool well_conditioned_projection(Verdict* v, const glm::dmat4& p) {
  const glm::dmat4 inverse = glm::inverse(p);
  const double condition = infinity_norm(p) * infinity_norm(inverse);
  if (condition <= kMaxProjectionCondition) return true;  // false for NaN and Inf (a singular matrix)
  *v = {ATMO_ERROR_OUT_OF_RANGE, "AtmoViewState.clip_from_view is singular or ill-conditioned (condition number " +
                                     number(condition) + ", at most " + number(kMaxProjectionCondition) + ")"};
  return false;
}

}  // namespace

Verdict validate_atmosphere(const AtmoAtmosphereState& s, core::AtmosphereSettings* out) {
  Verdict v;
  core::AtmosphereSettings r;
  if (s.visibility_m != 0.0 &&
      !in_range(&v, "AtmoAtmosphereState.visibility_m", s.visibility_m, 50.0, 500000.0, "m"))
    return v;
  if (s.aerosol_scale_height_m != 0.0 &&
      !in_range(&v, "AtmoAtmosphereState.aerosol_scale_height_m", s.aerosol_scale_height_m, 100.0, 20000.0, "m"))
    return v;
  if (s.ground_albedo != 0.0 && !in_range(&v, "AtmoAtmosphereState.ground_albedo", s.ground_albedo, 0.0, 1.0, ""))
    return v;
  if (s.visibility_m != 0.0) r.visibility_m = s.visibility_m;
  if (s.aerosol_scale_height_m != 0.0) r.aerosol_scale_height_m = s.aerosol_scale_height_m;
  if (s.ground_albedo != 0.0) r.ground_albedo = s.ground_albedo;
  *out = r;
  return v;
}

Verdict validate_frame(const AtmoFrameState& s) {
  Verdict v;
  // The ephemeris's own ranges (core/astro/time_scales.h): years 0001-9999, |DUT1| <= 0.9 s.
  if (!in_range(&v, "AtmoFrameState.utc_posix_s", s.utc_posix_s, core::astro::kMinPosixUtcS,
                core::astro::kMaxPosixUtcS, "s (0001-01-01T00:00:00Z to 9999-12-31T23:59:59Z)"))
    return v;
  if (!in_range(&v, "AtmoFrameState.dut1_s", s.dut1_s, -core::astro::kMaxAbsDut1S, core::astro::kMaxAbsDut1S, "s"))
    return v;
  if (s.deferred_frames > 100000u)
    return {ATMO_ERROR_OUT_OF_RANGE,
            "AtmoFrameState.deferred_frames = " + std::to_string(s.deferred_frames) + " is above 100000"};
  return v;
}

Verdict validate_view(const AtmoViewState& s, core::EyeFrame* out) {
  Verdict v;
  if (!enum_value(&v, "AtmoViewState.eye_kind", s.eye_kind, 2)) return v;
  if (!enum_value(&v, "AtmoViewState.world_frame", s.world_frame, 2)) return v;
  if (!enum_value(&v, "AtmoViewState.depth_convention", s.depth_convention, 3)) return v;
  if (!enum_value(&v, "AtmoViewState.output_encoding", s.output_encoding, 2)) return v;
  if (!enum_value(&v, "AtmoViewState.sky_method", s.sky_method, ATMO_SKY_METHOD_COUNT)) return v;
  if (!enum_value(&v, "AtmoViewState.depth_origin", s.depth_origin, 2)) return v;
  if (!enum_value(&v, "AtmoViewState.cloud_quality", s.cloud_quality, ATMO_CLOUD_QUALITY_COUNT)) return v;
  if (s.aerial_range_m != 0.0 && !in_range(&v, "AtmoViewState.aerial_range_m", s.aerial_range_m, 100.0, 1e7, "m"))
    return v;
  if (!table_size(&v, "AtmoViewState.sky_view_table_size[0]", s.sky_view_table_size[0], 16, 1024)) return v;
  if (!table_size(&v, "AtmoViewState.sky_view_table_size[1]", s.sky_view_table_size[1], 16, 1024)) return v;
  if (s.sky_view_table_size[1] % 2 != 0) {
    return {ATMO_ERROR_INVALID_ARGUMENT, "AtmoViewState.sky_view_table_size[1] = " +
                                             std::to_string(s.sky_view_table_size[1]) +
                                             " must be even (the horizon lies on a row boundary)"};
  }
  for (int i = 0; i < 3; ++i) {
    const std::string field = "AtmoViewState.aerial_volume_size[" + std::to_string(i) + "]";
    if (!table_size(&v, field.c_str(), s.aerial_volume_size[i], 4, 256)) return v;
  }

  core::CameraInput cam;
  cam.eye_is_geodetic = s.eye_kind == ATMO_POSITION_GEODETIC;
  if (cam.eye_is_geodetic) {
    if (!in_range(&v, "AtmoViewState.eye_geodetic[0] (latitude)", s.eye_geodetic[0], -90.0, 90.0, "degrees") ||
        !in_range(&v, "AtmoViewState.eye_geodetic[1] (longitude)", s.eye_geodetic[1], -1e4, 1e4, "degrees") ||
        !finite(&v, "AtmoViewState.eye_geodetic[2] (height)", s.eye_geodetic[2]))
      return v;
    cam.eye_geodetic = {s.eye_geodetic[0], s.eye_geodetic[1], s.eye_geodetic[2]};
  } else {
    if (!finite_array(&v, "AtmoViewState.eye_ecef_m", s.eye_ecef_m, 3)) return v;
    cam.eye_ecef_m = glm::dvec3(s.eye_ecef_m[0], s.eye_ecef_m[1], s.eye_ecef_m[2]);
    if (glm::length(cam.eye_ecef_m) < 1000.0) {
      v = {ATMO_ERROR_OUT_OF_RANGE, "AtmoViewState.eye_ecef_m is within 1 km of the Earth's centre"};
      return v;
    }
  }
  cam.world_frame = s.world_frame == ATMO_WORLD_ENU ? core::WorldFrame::Enu : core::WorldFrame::Ecef;
  if (cam.world_frame == core::WorldFrame::Enu) {
    if (!in_range(&v, "AtmoViewState.world_origin_geodetic[0] (latitude)", s.world_origin_geodetic[0], -90.0, 90.0,
                  "degrees") ||
        !finite_array(&v, "AtmoViewState.world_origin_geodetic", s.world_origin_geodetic, 3))
      return v;
    cam.world_origin = {s.world_origin_geodetic[0], s.world_origin_geodetic[1], s.world_origin_geodetic[2]};
  }
  if (!finite_array(&v, "AtmoViewState.view_from_world", s.view_from_world, 16) ||
      !finite_array(&v, "AtmoViewState.clip_from_view", s.clip_from_view, 16))
    return v;
  cam.view_from_world = matrix(s.view_from_world);
  cam.clip_from_view = matrix(s.clip_from_view);
  if (!rigid_transform(&v, cam.view_from_world, "AtmoViewState.view_from_world") || !well_conditioned_projection(&v, cam.clip_from_view)) return v;

  if (s.viewport[2] <= 0 || s.viewport[3] <= 0 || s.viewport[2] > 32768 || s.viewport[3] > 32768 ||
      s.viewport[0] < 0 || s.viewport[1] < 0) {
    v = {ATMO_ERROR_OUT_OF_RANGE, "AtmoViewState.viewport = {" + std::to_string(s.viewport[0]) + ", " +
                                      std::to_string(s.viewport[1]) + ", " + std::to_string(s.viewport[2]) + ", " +
                                      std::to_string(s.viewport[3]) +
                                      "}: x, y must be >= 0 and width, height in [1, 32768]"};
    return v;
  }
  if (s.depth_convention == ATMO_DEPTH_LOGARITHMIC) {
    if (!in_range(&v, "AtmoViewState.far_plane_m", s.far_plane_m, 1e-3, 1e12, "m")) return v;
    if (s.log_depth_coefficient != 0.0 &&
        !in_range(&v, "AtmoViewState.log_depth_coefficient", s.log_depth_coefficient, 1e-9, 1e9, ""))
      return v;
  }
  if (!in_range(&v, "AtmoViewState.exposure_scale", s.exposure_scale, 0.0, 1e12, "")) return v;

  core::EyeFrame frame;
  std::string why;
  if (!core::make_eye_frame(cam, &frame, &why)) {
    v = {ATMO_ERROR_OUT_OF_RANGE, "AtmoViewState." + why};
    return v;
  }
  // The ephemeris's observer range (core/astro/observer.h), which every pass serves.
  const char* height_field = cam.eye_is_geodetic ? "AtmoViewState.eye_geodetic[2] (height)"
                                                 : "AtmoViewState.eye_ecef_m (height above the WGS84 ellipsoid)";
  if (!in_range(&v, height_field, frame.eye.height_m, core::astro::kMinObserverHeightM,
                core::astro::kMaxObserverHeightM, "m"))
    return v;
  *out = frame;
  return v;
}

}  // namespace atmo::abi
