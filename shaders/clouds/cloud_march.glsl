// cloud_march.glsl — the view ray through one cloud's grid: ONE source for the
// GLSL impostor and direct passes and the C++ reference (cloud_twin.h). Needs
// cloud_functions.glsl and, from the includer, the type CLOUD_VOLUME and
// `vec4 cloud_fetch(IN(CLOUD_VOLUME) v, IN(vec3) index_point)` returning
// (density, tau_light, tau_up, tau_down) trilinearly at an index-space point
// (voxel centres at integer + 0.5, zero outside): a sampler3D in GLSL, the
// dense grids on the CPU.
//
// Index space is the grid's voxels; it differs from metres by voxel_size_m
// only (a cloud's voxels are cubes and its rotation is rigid), so one unit
// direction serves both.

struct CloudMarch {
  vec3 grid_size;          // voxels along x, y, z
  float voxel_size_m;
  float extinction_per_m;  // at density 1
  float albedo;
  float step_voxels;       // march step, voxels (a ray longer than max_steps steps gets longer steps)
  int max_steps;
  vec3 light_illuminance;  // lux on a surface facing the light, at the cloud
  vec3 light_dir_grid;     // unit, towards the light, grid axes
  vec3 sky_radiance;       // cd/m^2, mean over the upper hemisphere
  vec3 ground_radiance;    // cd/m^2, mean over the lower hemisphere
};

struct CloudSample {
  vec3 radiance;         // cd/m^2 scattered towards the eye by the cloud (background excluded)
  float transmittance;   // of the background through the cloud
  float depth_m;         // distance from the ray origin to the opacity-weighted mean of the cloud (far end if none)
};

// Entry and exit of a ray with the box [0, size], as (t_near, t_far); t_near > t_far when it misses.
ATMO_FN vec2 cloud_box_hit(IN(vec3) origin, IN(vec3) dir, IN(vec3) size) {
  vec3 inv = vec3(1.0f) / vec3(abs(dir.x) > 1e-12f ? dir.x : 1e-12f, abs(dir.y) > 1e-12f ? dir.y : 1e-12f,
                              abs(dir.z) > 1e-12f ? dir.z : 1e-12f);
  vec3 a = (vec3(0.0f) - origin) * inv;
  vec3 b = (size - origin) * inv;
  vec3 lo = min(a, b);
  vec3 hi = max(a, b);
  return vec2(max(max(lo.x, lo.y), max(lo.z, 0.0f)), min(min(hi.x, hi.y), hi.z));
}

// origin_index: the eye in index space; dir_grid: unit view direction in grid
// axes; t_max_m: where the ray stops (the host's surface, or far away).
ATMO_FN CloudSample cloud_march(IN(CLOUD_VOLUME) vol, IN(CloudMarch) m, IN(CloudPhase) ph, IN(CloudOctaves) oc,
                                IN(vec3) origin_index, IN(vec3) dir_grid, float t_max_m) {
  CloudSample s;
  s.radiance = vec3(0.0f);
  s.transmittance = 1.0f;
  s.depth_m = t_max_m;
  vec2 hit = cloud_box_hit(origin_index, dir_grid, m.grid_size);
  float t_end = min(hit.y, t_max_m / m.voxel_size_m);
  if (!(hit.x < t_end)) return s;
  float span = t_end - hit.x;
  int steps = int(ceil(span / m.step_voxels));
  steps = clamp(steps, 1, max(m.max_steps, 1));
  float dt = span / float(steps);          // index units
  float dt_m = dt * m.voxel_size_m;
  // Looking into the light through the cloud: cos = 1 (cloud_functions.glsl).
  float cos_theta = dot(m.light_dir_grid, dir_grid);
  float depth_sum = 0.0f;
  float weight_sum = 0.0f;
  float transmittance = 1.0f;
  vec3 radiance = vec3(0.0f);
  for (int i = 0; i < steps; ++i) {
    float t = hit.x + (float(i) + 0.5f) * dt;
    vec4 v = cloud_fetch(vol, origin_index + dir_grid * t);
    float sigma_t = v.x * m.extinction_per_m;
    if (sigma_t > 0.0f) {
      vec3 in_light = m.light_illuminance * cloud_light_octaves(ph, oc, v.y, cos_theta);
      vec3 ambient = cloud_ambient(oc, m.sky_radiance, m.ground_radiance, v.z, v.w);
      vec3 source = (m.albedo * sigma_t) * (in_light + ambient);
      radiance += transmittance * cloud_step_radiance(source, sigma_t, dt_m);
      float step_t = exp(-sigma_t * dt_m);
      float w = transmittance * (1.0f - step_t);
      depth_sum += w * t * m.voxel_size_m;
      weight_sum += w;
      transmittance *= step_t;
      if (transmittance < 1e-4f) break;
    }
  }
  s.radiance = radiance;
  s.transmittance = transmittance;
  s.depth_m = weight_sum > 0.0f ? depth_sum / weight_sum : t_end * m.voxel_size_m;
  return s;
}
