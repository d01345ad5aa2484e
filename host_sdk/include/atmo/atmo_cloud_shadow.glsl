// atmo_cloud_shadow.glsl — the clouds' shadow for a host's surface shader.
// Get the map with api.get_cloud_shadows(view, &shadows) each frame (its
// texture and matrix change when the clouds are relit), bind
// shadows.texture to a sampler2D and pass shadows.uv_from_world as a mat4
// (column-major, as GL takes it); then multiply the direct Sun (or Moon)
// light of a surface by atmo_cloud_shadow(map, matrix, world_position).
// world_position is in the view's world frame (AtmoViewState.world_frame).
// In an ECEF world, float positions carry ~0.5 m of rounding, well under a
// texel (docs/CLOUDS.md).
#ifndef ATMO_CLOUD_SHADOW_GLSL
#define ATMO_CLOUD_SHADOW_GLSL

// Direct transmittance of the clouds between the point and the light, in
// [0, 1]; 1 off the map (no clouds there).
float atmo_cloud_shadow(sampler2D shadow_map, mat4 uv_from_world, vec3 world_position) {
  vec2 uv = (uv_from_world * vec4(world_position, 1.0)).xy;
  if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return 1.0;
  return texture(shadow_map, uv).r;
}

#endif  // ATMO_CLOUD_SHADOW_GLSL
