#include "abi/fog_inputs.h"

#include <cmath>
#include <cstring>
#include <string>

#include "abi/struct_io.h"
#include "abi/validation.h"

namespace atmo::abi {

namespace {

Verdict bad(AtmoResult code, const std::string& message) { return {code, message}; }

}  // namespace

Verdict set_fog_state(const AtmoFogState& s, fog::FogMedium* fog) {
  const double fields[] = {s.visibility_m, s.extinction_per_m, s.top_height_m, s.phase_asymmetry,
                           s.single_scattering_albedo};
  const char* names[] = {"visibility_m", "extinction_per_m", "top_height_m", "phase_asymmetry",
                         "single_scattering_albedo"};
  for (int i = 0; i < 5; ++i)
    if (!std::isfinite(fields[i]))
      return bad(ATMO_ERROR_NON_FINITE_VALUE, std::string("AtmoFogState.") + names[i] + " is " + number(fields[i]));
  if (s.visibility_m != 0.0 && (s.visibility_m < 10.0 || s.visibility_m > 100000.0))
    return bad(ATMO_ERROR_OUT_OF_RANGE, "AtmoFogState.visibility_m = " + number(s.visibility_m) + " is outside [10, 100000] m");
  if (s.extinction_per_m < 0.0 || s.extinction_per_m > 1.0)
    return bad(ATMO_ERROR_OUT_OF_RANGE,
               "AtmoFogState.extinction_per_m = " + number(s.extinction_per_m) + " is outside [0, 1] 1/m");
  if (s.top_height_m < -500.0 || s.top_height_m > 20000.0)
    return bad(ATMO_ERROR_OUT_OF_RANGE, "AtmoFogState.top_height_m = " + number(s.top_height_m) + " is outside [-500, 20000] m");
  if (std::abs(s.phase_asymmetry) > 0.95)
    return bad(ATMO_ERROR_OUT_OF_RANGE, "AtmoFogState.phase_asymmetry = " + number(s.phase_asymmetry) + " is outside [-0.95, 0.95]");
  if (s.single_scattering_albedo < 0.0 || s.single_scattering_albedo > 1.0)
    return bad(ATMO_ERROR_OUT_OF_RANGE,
               "AtmoFogState.single_scattering_albedo = " + number(s.single_scattering_albedo) + " is outside (0, 1]");
  if (s.scattering >= ATMO_FOG_SCATTERING_COUNT)
    return bad(ATMO_ERROR_INVALID_ARGUMENT, "AtmoFogState.scattering = " + std::to_string(s.scattering) +
                                                " is not an AtmoFogScattering");
  if (s.airlight_table_size != 0 && (s.airlight_table_size < 8 || s.airlight_table_size > 512))
    return bad(ATMO_ERROR_OUT_OF_RANGE, "AtmoFogState.airlight_table_size = " + std::to_string(s.airlight_table_size) +
                                            " is outside [8, 512]");
  fog::FogOptics o;
  o.extinction_per_m = s.visibility_m > 0.0 ? fog::extinction_from_visibility(s.visibility_m) : s.extinction_per_m;
  o.albedo = s.single_scattering_albedo > 0.0 ? s.single_scattering_albedo : fog::kFogAlbedo;
  o.phase_g = s.phase_asymmetry != 0.0 ? s.phase_asymmetry : fog::kFogPhaseG;
  o.top_height_m = s.top_height_m != 0.0 ? s.top_height_m : INFINITY;
  o.multiple_scattering = s.scattering == ATMO_FOG_SCATTERING_AUTO;
  const int size = s.airlight_table_size ? static_cast<int>(s.airlight_table_size) : 64;
  fog->apply(o, size);
  return {};
}

}  // namespace atmo::abi
