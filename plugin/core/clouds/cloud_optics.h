// cloud_optics.h — the parameters the cloud lighting model
// (shaders/clouds/cloud_functions.glsl) takes, from physical inputs.
#pragma once

#include "core/clouds/cloud_twin.h"

namespace atmo::clouds {

// Jendersie & d'Eon 2023's fit of HG + Draine to Mie scattering by water
// droplets of effective diameter d, micrometres; the fit holds for d in
// [5, 50] and d is clamped to it.
twin::CloudPhase phase_for_droplet(float droplet_diameter_um);

// The octave parameters the plugin draws with by default (docs/CLOUDS.md
// shows how they were chosen against the path tracer).
twin::CloudOctaves default_octaves();

// Single scattering only (the "no multiple scattering" tier, and the
// path tracer's first bounce).
twin::CloudOctaves single_scattering_octaves();

}  // namespace atmo::clouds
