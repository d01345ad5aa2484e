// cloud_optics.h — the parameters the cloud lighting model
// (shaders/clouds/cloud_functions.glsl) takes, from physical inputs.
#pragma once

#include <array>
#include <cstddef>

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

// CloudOctaves' float members by their GLSL names, so the GL layer sets each
// uniform of the struct from one list (count and up_grid are set apart; a GL
// test checks every name resolves in the linked programs).
struct OctaveFloat {
  const char* name;
  float twin::CloudOctaves::*field;
};
inline constexpr std::array<OctaveFloat, 13> kOctaveFloats{{
    {"extinction_scale", &twin::CloudOctaves::extinction_scale},
    {"scattering_scale", &twin::CloudOctaves::scattering_scale},
    {"eccentricity_scale", &twin::CloudOctaves::eccentricity_scale},
    {"ambient_extinction", &twin::CloudOctaves::ambient_extinction},
    {"ambient_loss", &twin::CloudOctaves::ambient_loss},
    {"diffusion_strength", &twin::CloudOctaves::diffusion_strength},
    {"diffusion_extinction", &twin::CloudOctaves::diffusion_extinction},
    {"diffusion_side_escape", &twin::CloudOctaves::diffusion_side_escape},
    {"diffusion_anisotropy", &twin::CloudOctaves::diffusion_anisotropy},
    {"diffusion_buildup_extinction", &twin::CloudOctaves::diffusion_buildup_extinction},
    {"diffusion_lookahead", &twin::CloudOctaves::diffusion_lookahead},
    {"thin_extinction", &twin::CloudOctaves::thin_extinction},
    {"ambient_view_extinction", &twin::CloudOctaves::ambient_view_extinction},
}};
inline constexpr size_t kOctaveFloatCount = kOctaveFloats.size();
// Every member is listed: count, 13 floats, up_grid.
static_assert(sizeof(twin::CloudOctaves) == sizeof(int) + kOctaveFloatCount * sizeof(float) + sizeof(glm::vec3));

}  // namespace atmo::clouds
