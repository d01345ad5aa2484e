// validation.h — checks every field of a state struct against its documented
// range before anything changes, so a bad frame is refused whole with a
// message that names the struct, the field and the value.
#pragma once

#include <string>

#include "atmo/atmo.h"
#include "core/atmosphere/atmosphere_model.h"
#include "core/geo/eye_frame.h"

namespace atmo::abi {

struct Verdict {
  AtmoResult code = ATMO_SUCCESS;
  std::string message;
  bool ok() const { return code == ATMO_SUCCESS; }
};

// A value for an error message: whole numbers below 1e15 in full (POSIX
// seconds), else the shortest form (10 to 17 significant digits) that reads
// back as v, so a value just outside a range never prints as the bound itself.
std::string number(double v);

Verdict validate_atmosphere(const AtmoAtmosphereState& s, core::AtmosphereSettings* out);
Verdict validate_frame(const AtmoFrameState& s);
// Fills the eye frame (double precision) from a valid view state.
Verdict validate_view(const AtmoViewState& s, core::EyeFrame* out);

// A column-major 4x4 of the ABI (element [col * 4 + row]).
glm::dmat4 matrix(const double m[16]);
// True when m is rigid (docs/ABI.md: the upper 3x3 a rotation to 1e-3, det > 0, the bottom row (0, 0, 0, 1));
// else fills *v with an error naming `name`.
bool rigid_transform(Verdict* v, const glm::dmat4& m, const std::string& name);

// Default exposure when exposure_scale is 0: EV100 = 15.
constexpr double kDefaultExposureScale = 1.0 / (1.2 * 32768.0);

}  // namespace atmo::abi
