// cloud_layer_march.glsl — one view ray through every cloud of the scene at
// once, over the clipmap of core/clouds/cloud_clipmap.h: ONE source for the
// GLSL layer pass (clouds_layer.frag) and the C++ twin (cloud_twin.h). Its
// cost is its steps (at most max_steps), not the number of clouds. Needs
// cloud_functions.glsl and, from the includer:
//   CLOUD_LAYER, the clipmap's storage (a sampler3D in GLSL, the levels on the CPU);
//   vec4 cloud_layer_fetch_a(IN(CLOUD_LAYER) v, int level, IN(vec3) q) and
//   vec2 cloud_layer_fetch_b(IN(CLOUD_LAYER) v, int level, IN(vec3) q):
//     the level's terms trilinearly at level index point q (voxel centres at
//     integer + 0.5): a = (sigma_t, tau_light, tau_up, tau_down),
//     b = (tau_back, sigma_t droplet_um);
//   float cloud_layer_fetch_clear(IN(CLOUD_LAYER) v, int level, IN(ivec3) brick):
//     the level's clear distance at a brick of 2x2x2 voxels (clamped into
//     the level; core/clouds/cloud_clipmap.h);
//   void cloud_layer_air(float depth_m, OUT(vec3) inscatter, OUT(vec3) transmittance):
//     the air between the eye and a cloud at that distance (the aerial
//     perspective; none on the CPU).
// Positions are metres from the eye in the clouds' ENU axes.

#define CLOUD_LAYER_MAX_LEVELS 10
#define CLOUD_LAYER_PHASES 8

struct CloudLayerMarch {
  int level_count;
  vec4 level_origin[CLOUD_LAYER_MAX_LEVELS];  // xyz: corner of the level's voxel (0, 0, 0), m from the eye; w: voxel m
  vec4 level_dims[CLOUD_LAYER_MAX_LEVELS];    // voxels along x, y, z; w: the level's first slice in the GL texture
  vec4 level_bricks[CLOUD_LAYER_MAX_LEVELS];  // clear bricks along x, y, z; w: the level's first slice in theirs
  vec4 phases[CLOUD_LAYER_PHASES];            // CloudPhase (g_hg, g_draine, alpha_draine, w_draine) at ...
  float phase_um[CLOUD_LAYER_PHASES];         // ... these droplet diameters (um, ascending): the field's own
  int phase_count;                            // >= 1
  float bottom_m;                             // the field's lowest and highest height, m relative to the eye
  float top_m;
  float step_voxels;                          // dense step, voxels of the level at the point
  int max_steps;                              // the budget: steps lengthen so the ray ends within it
  float albedo;
  vec3 light_illuminance;                     // lux on a surface facing the light
  vec3 light_dir;                             // unit, towards the light
  vec3 sky_radiance;                          // cd/m^2
  vec3 ground_radiance;                       // cd/m^2
};

struct CloudLayerSample {
  vec3 radiance;        // cd/m^2 towards the eye, through the air (background excluded)
  float transmittance;  // of the background
  float depth_m;        // opacity-weighted mean distance of the clouds (t_max when none)
  int steps;            // steps taken (cost)
};

// The finest level holding point p (2 voxels in from its sides), -1 when none.
ATMO_FN int cloud_layer_level_at(IN(CloudLayerMarch) m, IN(vec3) p) {
  for (int l = 0; l < m.level_count; ++l) {
    vec2 q = (vec2(p.x, p.y) - vec2(m.level_origin[l].x, m.level_origin[l].y)) / m.level_origin[l].w;
    if (q.x >= 2.0f && q.y >= 2.0f && q.x <= m.level_dims[l].x - 2.0f && q.y <= m.level_dims[l].y - 2.0f) return l;
  }
  return -1;
}

// Level l's index point at p; heights clamped into the level's slab (its
// empty first and last slices), so a fetch never reads a neighbouring level.
ATMO_FN vec3 cloud_layer_index(IN(CloudLayerMarch) m, int l, IN(vec3) p) {
  vec3 q = (p - vec3(m.level_origin[l].x, m.level_origin[l].y, m.level_origin[l].z)) / m.level_origin[l].w;
  q.z = clamp(q.z, 0.5f, m.level_dims[l].z - 0.5f);
  return q;
}

// The droplets' phase at a diameter: exact at the field's own diameters,
// linear between them (where clouds of two kinds overlap).
ATMO_FN CloudPhase cloud_layer_phase(IN(CloudLayerMarch) m, float droplet_um) {
  vec4 p = m.phases[0];
  for (int i = 1; i < m.phase_count; ++i) {
    if (droplet_um <= m.phase_um[i - 1]) break;
    float f = clamp((droplet_um - m.phase_um[i - 1]) / max(m.phase_um[i] - m.phase_um[i - 1], 1e-6f), 0.0f, 1.0f);
    p = m.phases[i - 1] * (1.0f - f) + m.phases[i] * f;
  }
  CloudPhase ph;
  ph.g_hg = p.x;
  ph.g_draine = p.y;
  ph.alpha_draine = p.z;
  ph.w_draine = p.w;
  return ph;
}

// The ray from the eye along unit dir, to t_max_m (the host's surface or far).
// The same lighting as cloud_march (cloud_functions.glsl), its depths read
// from the clipmap; a cloud's diffuse light still owed is paid where the ray
// leaves it (a clear step), and each cloud (a run of cloudy steps) takes the
// air in front of it at its own opacity-weighted depth, as the per-cloud
// passes do.
ATMO_FN CloudLayerSample cloud_layer_march(IN(CLOUD_LAYER) vol, IN(CloudLayerMarch) m, IN(CloudOctaves) oc,
                                           IN(vec3) dir, float t_max_m) {
  CloudLayerSample s;
  s.radiance = vec3(0.0f);
  s.transmittance = 1.0f;
  s.depth_m = t_max_m;
  s.steps = 0;
  if (m.level_count <= 0) return s;
  // The slab between the field's bottom and top, inside the outermost level.
  float t0 = 0.0f;
  float t1 = t_max_m;
  if (abs(dir.z) > 1e-9f) {
    float ta = m.bottom_m / dir.z;
    float tb = m.top_m / dir.z;
    t0 = max(t0, min(ta, tb));
    t1 = min(t1, max(ta, tb));
  } else if (m.bottom_m > 0.0f || m.top_m < 0.0f) {
    return s;
  }
  // Sideways: 2 voxels in from the outermost level's sides; heights: the slab.
  int outer = m.level_count - 1;
  float margin = 2.0f * m.level_origin[outer].w;
  vec3 lo = vec3(m.level_origin[outer].x + margin, m.level_origin[outer].y + margin, m.bottom_m);
  vec3 hi = vec3(m.level_origin[outer].x + m.level_dims[outer].x * m.level_origin[outer].w - margin,
                 m.level_origin[outer].y + m.level_dims[outer].y * m.level_origin[outer].w - margin, m.top_m);
  vec2 box = cloud_box_hit(-lo, dir, hi - lo);
  t0 = max(t0, box.x);
  t1 = min(t1, box.y);
  if (!(t0 < t1)) return s;

  float cos_theta = dot(m.light_dir, dir);
  float mu = dot(dir, oc.up_grid);
  float transmittance = 1.0f;
  vec3 radiance = vec3(0.0f);
  float depth_sum = 0.0f;
  float weight_sum = 0.0f;
  // The cloud being crossed, from its front.
  CloudRay seg = cloud_ray_start();
  bool in_cloud = false;
  float t = t0;
  int i = 0;
  while (t < t1 && i < m.max_steps) {
    int left = m.max_steps - i;
    vec3 p = dir * t;
    int l = cloud_layer_level_at(m, p);
    if (l < 0) break;
    float v = m.level_origin[l].w;
    // Whole steps to t1 (the slab's far side, the host's surface): the
    // ray's last sample lies half a step before it, as the per-cloud march's
    // before its box's face. A cloud's remaining diffuse weight is paid at
    // its last sample (cloud_ray_step); where that fell anywhere in the last
    // step, a deck's lit top paid it deep inside instead of at the face,
    // where the build-up leaves none (a tile seen from below was 7.1 % off
    // the path tracer, the per-cloud march 5.0 %).
    float dt = min(max(v * m.step_voxels, (t1 - t) / float(left)), t1 - t);
    dt = (t1 - t) / ceil((t1 - t) / dt);
    // Empty space: the level's clear bricks say how far no cloud reaches
    // around the point (cloud_clipmap.h): skip that far. Not looked for
    // inside a cloud (a fetch a step saved: the brick there is cloudy).
    float clear_reach = 0.0f;
    if (!in_cloud) {
      ivec3 brick = ivec3(floor(cloud_layer_index(m, l, p) * 0.5f));
      clear_reach = max(2.0f * cloud_layer_fetch_clear(vol, l, brick) - 2.5f, 0.0f) * v;
    }
    vec3 mid = dir * (t + 0.5f * dt);
    vec4 a = vec4(0.0f);
    if (clear_reach > dt) {
      dt = min(clear_reach, t1 - t);
    } else {
      a = cloud_layer_fetch_a(vol, l, cloud_layer_index(m, l, mid));
    }
    ++i;
    float sigma_t = a.x;
    if (sigma_t > 1e-7f) {
      vec2 b = cloud_layer_fetch_b(vol, l, cloud_layer_index(m, l, mid));
      float tau_light = a.y;
      float tau_up = a.z;
      float tau_down = a.w;
      float tau_back = b.x;
      CloudPhase ph = cloud_layer_phase(m, b.y / sigma_t);
      if (!in_cloud) {
        in_cloud = true;
        seg = cloud_ray_start();
      }
      seg = cloud_ray_step(seg, ph, oc, m.light_illuminance, m.sky_radiance, m.ground_radiance, m.albedo, cos_theta,
                           mu, sigma_t, dt, t + 0.5f * dt, tau_light, tau_back, tau_up, tau_down);
    }
    t += dt;
    bool ends = in_cloud && (sigma_t <= 1e-7f || t >= t1 || i >= m.max_steps ||
                             transmittance * seg.transmittance < CLOUD_OPAQUE_TRANSMITTANCE);
    if (ends) {
      // The cloud ends: pay what it owes, put it behind the air in front of it.
      in_cloud = false;
      vec3 seg_radiance = seg.radiance + seg.owed * seg.diffuse;
      float depth = seg.weight_sum > 0.0f ? seg.depth_sum / seg.weight_sum : t;
      vec3 air_inscatter;
      vec3 air_transmittance;
      cloud_layer_air(depth, air_inscatter, air_transmittance);
      radiance += transmittance * (seg_radiance * air_transmittance + (1.0f - seg.transmittance) * air_inscatter);
      depth_sum += transmittance * (1.0f - seg.transmittance) * depth;
      weight_sum += transmittance * (1.0f - seg.transmittance);
      transmittance *= seg.transmittance;
      if (transmittance < CLOUD_OPAQUE_TRANSMITTANCE) {  // nothing behind shows (cloud_functions.glsl)
        transmittance = 0.0f;
        break;
      }
    }
  }
  s.radiance = radiance;
  s.transmittance = transmittance;
  s.depth_m = weight_sum > 0.0f ? depth_sum / weight_sum : t_max_m;
  s.steps = i;
  return s;
}
