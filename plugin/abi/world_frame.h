// world_frame.h — the host's world axes (AtmoWorldFrame) as a transform to
// ECEF: the identity for ATMO_WORLD_ECEF, the ENU frame at the geodetic origin
// (degrees, degrees, metres) for ATMO_WORLD_ENU. The origin is validated by the caller.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "atmo/atmo.h"
#include "core/geo/geodesy.h"

namespace atmo::abi {

inline glm::dmat4 ecef_from_world_frame(uint32_t world_frame, const double origin_geodetic[3]) {
  if (world_frame != ATMO_WORLD_ENU) return glm::dmat4(1.0);
  return core::ecef_from_enu_at({origin_geodetic[0], origin_geodetic[1], origin_geodetic[2]});
}

}  // namespace atmo::abi
