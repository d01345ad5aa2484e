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
  vec4 continuing_sides;   // 1 where the grid's side face goes on into another grid (a deck's tiles): west (-x), east (+x), south (-y), north (+y)
};

struct CloudSample {
  vec3 radiance;         // cd/m^2 scattered towards the eye by the cloud (background excluded)
  float transmittance;   // of the background through the cloud
  float depth_m;         // distance from the ray origin to the opacity-weighted mean of the cloud (far end if none)
};

// origin_index: the eye in index space; dir_grid: unit view direction in grid
// axes; t_max_m: where the ray stops (the host's surface, or far away).
// Where a ray from the point away from the light leaves the grid through a
// side face that goes on into another grid (a deck's next tile), the cloud
// behind does not end there: the depth behind is then at least that of a
// slab whose optical depth to its bottom (or top) is the point's tau_down
// (tau_up), crossed at the light's slant (at most 20 times the vertical:
// ~3 degrees). The march takes the larger of it and the own grid's chord;
// at a tile border the chord jumps (short on the near side, the whole next
// tile on the far side) but the slab's depth, which is the larger whenever
// the ray leaves through the side, does not. 0 elsewhere.
ATMO_FN float cloud_depth_beyond_side(IN(CloudMarch) m, IN(vec3) exit_point, float tau_up, float tau_down) {
  float e = 1e-3f * max(m.grid_size.x, m.grid_size.y);
  float through = 0.0f;
  if (exit_point.x <= e) through = max(through, m.continuing_sides.x);
  if (exit_point.x >= m.grid_size.x - e) through = max(through, m.continuing_sides.y);
  if (exit_point.y <= e) through = max(through, m.continuing_sides.z);
  if (exit_point.y >= m.grid_size.y - e) through = max(through, m.continuing_sides.w);
  if (through <= 0.0f) return 0.0f;
  float slant = max(abs(m.light_dir_grid.z), 0.05f);
  return (m.light_dir_grid.z >= 0.0f ? tau_down : tau_up) / slant;
}

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
  float mu = dot(dir_grid, oc.up_grid);  // > 0: looking up
  CloudRay r = cloud_ray_start();
  for (int i = 0; i < steps; ++i) {
    float t = hit.x + (float(i) + 0.5f) * dt;
    vec3 point = origin_index + dir_grid * t;
    vec4 v = cloud_fetch(vol, point);
    float sigma_t = v.x * m.extinction_per_m;
    if (sigma_t > 0.0f) {
      // Optical depth behind the point, away from the light: the light grid's
      // tau_light where the light's line through the point leaves the grid on
      // the far side is the whole chord, so the difference is what lies behind
      // (one more fetch; not for single scattering).
      float tau_back = 0.0f;
      if (oc.count > 1 && oc.diffusion_strength > 0.0f) {
        vec2 back = cloud_box_hit(point, -m.light_dir_grid, m.grid_size);
        vec3 far_point = clamp(point - m.light_dir_grid * back.y, vec3(0.5f), m.grid_size - vec3(0.5f));
        tau_back = max(max(cloud_fetch(vol, far_point).y - v.y, 0.0f),
                       cloud_depth_beyond_side(m, point - m.light_dir_grid * back.y, v.z, v.w));
      }
      r = cloud_ray_step(r, ph, oc, m.light_illuminance, m.sky_radiance, m.ground_radiance, m.albedo, cos_theta, mu,
                         sigma_t, dt_m, t * m.voxel_size_m, v.y, tau_back, v.z, v.w);
      if (r.transmittance < CLOUD_OPAQUE_TRANSMITTANCE) {
        r.transmittance = 0.0f;
        break;
      }
    }
  }
  s.radiance = r.radiance + r.owed * r.diffuse;
  s.transmittance = r.transmittance;
  s.depth_m = r.weight_sum > 0.0f ? r.depth_sum / r.weight_sum : t_end * m.voxel_size_m;
  return s;
}
