// functions.glsl — the atmosphere model's functions, ONE source for two
// compilers: the GLSL passes #include it, and plugin/core/atmosphere/shader_twin.h
// compiles it as C++ over GLM (the CPU twin), so tests compare the GPU image
// with the very same formulas evaluated on the CPU.
//
// Rules that keep it valid in both languages: functions start with ATMO_FN
// (`inline` in C++, nothing in GLSL); float literals carry an `f`
// suffix (GLSL >= 1.30 accepts it); parameters are declared IN(type) /
// OUT(type); textures are sampled only through the helpers below.
//
// Frame and units: every position is relative to the EYE, in metres, in the
// east-north-up (ENU) axes at the eye. The planet is a sphere of radius
// bottom_radius_m whose centre is at (0, 0, -(bottom_radius_m + eye_altitude_m)),
// so the sphere is tangent to the WGS84 ellipsoid below the eye. Radiance is
// in cd/m^2 (photometric, linear Rec.709 primaries): the sun is given by its
// illuminance in lux, and scattering coefficients are per metre.

struct AtmosphereParameters {
  float bottom_radius_m;        // planet radius at the eye (WGS84 mean radius of curvature)
  float top_radius_m;           // top of the atmosphere
  vec3 rayleigh_scattering;     // sea-level Rayleigh scattering, 1/m, per channel
  float rayleigh_scale_height_m;
  vec3 mie_scattering;          // sea-level aerosol scattering, 1/m
  vec3 mie_extinction;          // sea-level aerosol extinction, 1/m
  float mie_scale_height_m;
  float mie_g;                  // Cornette-Shanks asymmetry
  vec3 ozone_absorption;        // peak ozone absorption, 1/m
  float ozone_center_m;         // altitude of the ozone peak
  float ozone_half_width_m;     // tent profile half width
  vec3 sun_illuminance_lux;     // at the top of the atmosphere, per channel
  float sun_angular_radius;     // radians
  vec3 ground_albedo;           // Lambertian
};

const float ATMO_PI = 3.14159265358979f;

// --- Geometry --------------------------------------------------------------

// Distance along a unit ray from p to the sphere of `radius` around the origin
// (far hit); negative if the ray misses it.
ATMO_FN float ray_sphere_far(IN(vec3) p, IN(vec3) dir, float radius) {
  float b = dot(p, dir);
  float c = dot(p, p) - radius * radius;
  float disc = b * b - c;
  if (disc < 0.0f) return -1.0f;
  return -b + sqrt(disc);
}

// Distance to the near hit of the sphere, negative if missed or behind.
ATMO_FN float ray_sphere_near(IN(vec3) p, IN(vec3) dir, float radius) {
  float b = dot(p, dir);
  float c = dot(p, p) - radius * radius;
  float disc = b * b - c;
  if (disc < 0.0f) return -1.0f;
  float t = -b - sqrt(disc);
  return t;
}

// --- Media -------------------------------------------------------------------

ATMO_FN float rayleigh_density(IN(AtmosphereParameters) atm, float altitude_m) {
  return exp(-max(altitude_m, 0.0f) / atm.rayleigh_scale_height_m);
}

ATMO_FN float mie_density(IN(AtmosphereParameters) atm, float altitude_m) {
  return exp(-max(altitude_m, 0.0f) / atm.mie_scale_height_m);
}

ATMO_FN float ozone_density(IN(AtmosphereParameters) atm, float altitude_m) {
  return max(0.0f, 1.0f - abs(altitude_m - atm.ozone_center_m) / atm.ozone_half_width_m);
}

ATMO_FN vec3 extinction_at(IN(AtmosphereParameters) atm, float altitude_m) {
  return atm.rayleigh_scattering * rayleigh_density(atm, altitude_m) +
         atm.mie_extinction * mie_density(atm, altitude_m) +
         atm.ozone_absorption * ozone_density(atm, altitude_m);
}

// --- Phase functions (1/sr) --------------------------------------------------

ATMO_FN float rayleigh_phase(float cos_theta) {
  return 3.0f / (16.0f * ATMO_PI) * (1.0f + cos_theta * cos_theta);
}

// Cornette-Shanks: Henyey-Greenstein improved to have the Rayleigh limit at g = 0.
ATMO_FN float mie_phase(float g, float cos_theta) {
  float g2 = g * g;
  float k = 3.0f / (8.0f * ATMO_PI) * (1.0f - g2) / (2.0f + g2);
  float denom = max(1.0f + g2 - 2.0f * g * cos_theta, 1e-6f);
  return k * (1.0f + cos_theta * cos_theta) / (denom * sqrt(denom));
}

// --- Transmittance lookup table ----------------------------------------------
// T(r, mu) from a point at radius r, direction cosine mu with the zenith, to
// the top of the atmosphere. Parametrisation: x_r = rho / H, x_mu = (d - d_min)
// / (d_max - d_min), with H the horizon distance at the ground, rho at r, and d
// the distance to the top; it spends texels where the table varies fast.

ATMO_FN float clamp_cosine(float mu) { return clamp(mu, -1.0f, 1.0f); }

ATMO_FN float distance_to_top(IN(AtmosphereParameters) atm, float r, float mu) {
  float disc = r * r * (mu * mu - 1.0f) + atm.top_radius_m * atm.top_radius_m;
  return max(-r * mu + sqrt(max(disc, 0.0f)), 0.0f);
}

ATMO_FN vec2 transmittance_uv_from_r_mu(IN(AtmosphereParameters) atm, float r, float mu, IN(vec2) lut_size) {
  float H = sqrt(atm.top_radius_m * atm.top_radius_m - atm.bottom_radius_m * atm.bottom_radius_m);
  float rho = sqrt(max(r * r - atm.bottom_radius_m * atm.bottom_radius_m, 0.0f));
  rho = min(rho, H);
  float d = distance_to_top(atm, r, mu);
  float d_min = atm.top_radius_m - r;
  float d_max = rho + H;
  float x_mu = clamp((d - d_min) / max(d_max - d_min, 1e-3f), 0.0f, 1.0f);
  float x_r = rho / H;
  // Texel centres at the table's edges.
  return vec2(0.5f / lut_size.x + x_mu * (1.0f - 1.0f / lut_size.x),
              0.5f / lut_size.y + x_r * (1.0f - 1.0f / lut_size.y));
}

// Inverse of the mapping above, used to fill the table (x in [0,1]^2, texel centres removed).
ATMO_FN vec2 transmittance_r_mu_from_unit(IN(AtmosphereParameters) atm, IN(vec2) x) {
  float H = sqrt(atm.top_radius_m * atm.top_radius_m - atm.bottom_radius_m * atm.bottom_radius_m);
  float rho = H * x.y;
  float r = sqrt(rho * rho + atm.bottom_radius_m * atm.bottom_radius_m);
  float d_min = atm.top_radius_m - r;
  float d_max = rho + H;
  float d = d_min + x.x * (d_max - d_min);
  float mu = d == 0.0f ? 1.0f : (H * H - rho * rho - d * d) / (2.0f * r * d);
  return vec2(r, clamp_cosine(mu));
}

// Transmittance from a point at radius r towards the sun (direction cosine
// mu_s), including the Earth's shadow smoothed over the sun's disc.
ATMO_FN vec3 transmittance_to_sun(IN(AtmosphereParameters) atm, LUT2D lut, IN(vec2) lut_size,
                          float r, float mu_s) {
  float sin_h = atm.bottom_radius_m / r;
  float cos_h = -sqrt(max(1.0f - sin_h * sin_h, 0.0f));
  float visible = smoothstep(-sin_h * atm.sun_angular_radius, sin_h * atm.sun_angular_radius, mu_s - cos_h);
  return sample_lut(lut, transmittance_uv_from_r_mu(atm, r, mu_s, lut_size)) * visible;
}

// --- Multiple scattering (Hillaire 2020, isotropic approximation) ------------
// Psi_ms(r, mu_s): radiance of all orders >= 2 reaching a point, per unit sun
// illuminance and per unit scattering coefficient, assuming the light
// scattered twice or more is isotropic. The table is indexed by
// u = mu_s * 0.5 + 0.5 and v = altitude / thickness (texel centres at the edges).

ATMO_FN vec2 multiple_scattering_uv(IN(AtmosphereParameters) atm, float r, float mu_s, IN(vec2) lut_size) {
  float x_mu = clamp(mu_s * 0.5f + 0.5f, 0.0f, 1.0f);
  float x_r = clamp((r - atm.bottom_radius_m) / (atm.top_radius_m - atm.bottom_radius_m), 0.0f, 1.0f);
  return vec2(0.5f / lut_size.x + x_mu * (1.0f - 1.0f / lut_size.x),
              0.5f / lut_size.y + x_r * (1.0f - 1.0f / lut_size.y));
}

// Direction i of n, evenly spread over the sphere (Fibonacci lattice).
ATMO_FN vec3 sphere_direction(int i, int n) {
  float z = 1.0f - 2.0f * (float(i) + 0.5f) / float(n);
  float radius = sqrt(max(1.0f - z * z, 0.0f));
  float phi = 2.39996323f * float(i);  // golden angle
  return vec3(radius * cos(phi), radius * sin(phi), z);
}

// One texel of the table: from a point at radius r with the sun at cosine
// mu_s (ENU at that point, so the planet centre is straight below), march
// `directions` rays. Second-order light L2 (single scattering seen from the
// point, isotropic phase, plus the lit ground) and the transfer f_ms (how much
// of an isotropic unit radiance field scatters back) give the geometric series
// of all higher orders: Psi_ms = L2 / (1 - f_ms).
ATMO_FN vec3 multiple_scattering_texel(IN(AtmosphereParameters) atm, LUT2D transmittance, IN(vec2) lut_size,
                                       float r, float mu_s, int directions, int steps) {
  vec3 origin = vec3(0.0f, 0.0f, r);  // planet-centred, point on the +z axis
  vec3 sun_dir = vec3(sqrt(max(1.0f - mu_s * mu_s, 0.0f)), 0.0f, mu_s);
  const float isotropic = 1.0f / (4.0f * ATMO_PI);
  vec3 l2 = vec3(0.0f);
  vec3 f_ms = vec3(0.0f);
  for (int d = 0; d < directions; ++d) {
    vec3 dir = sphere_direction(d, directions);
    float t_top = ray_sphere_far(origin, dir, atm.top_radius_m);
    float t_ground = ray_sphere_near(origin, dir, atm.bottom_radius_m);
    bool hits_ground = t_ground > 0.0f;
    float t_end = hits_ground ? t_ground : max(t_top, 0.0f);
    float dt = t_end / float(steps);
    vec3 tau = vec3(0.0f);
    vec3 light = vec3(0.0f);
    vec3 transfer = vec3(0.0f);
    for (int i = 0; i < steps; ++i) {
      float t = (float(i) + 0.5f) * dt;
      vec3 p = origin + dir * t;
      float rp = length(p);
      float altitude = rp - atm.bottom_radius_m;
      float rd = rayleigh_density(atm, altitude);
      float md = mie_density(atm, altitude);
      vec3 sigma_s = atm.rayleigh_scattering * rd + atm.mie_scattering * md;
      vec3 sigma_t = atm.rayleigh_scattering * rd + atm.mie_extinction * md +
                     atm.ozone_absorption * ozone_density(atm, altitude);
      vec3 t_view = exp(-(tau + sigma_t * (0.5f * dt)));
      vec3 t_sun = transmittance_to_sun(atm, transmittance, lut_size, rp, dot(p, sun_dir) / rp);
      light += t_view * sigma_s * t_sun * (isotropic * dt);
      transfer += t_view * sigma_s * dt;
      tau += sigma_t * dt;
    }
    if (hits_ground) {
      vec3 g = origin + dir * t_ground;
      float mu_g = dot(normalize(g), sun_dir);
      vec3 t_sun = transmittance_to_sun(atm, transmittance, lut_size, atm.bottom_radius_m, mu_g);
      light += exp(-tau) * t_sun * max(mu_g, 0.0f) * atm.ground_albedo / ATMO_PI;
    }
    l2 += light;
    f_ms += transfer * isotropic;
  }
  l2 *= 1.0f / float(directions);
  f_ms *= 4.0f * ATMO_PI / float(directions);  // integral over the sphere with the isotropic phase
  return l2 / max(vec3(1.0f) - f_ms, vec3(1e-3f));
}

// --- Single scattering along a view ray -------------------------------------

struct ScatteringResult {
  vec3 inscattered;    // cd/m^2 reaching the eye from the segment
  vec3 transmittance;  // along the segment
  vec3 shadowed_away;  // cd/m^2 the clouds' shadow took from `inscattered` (0 without clouds)
};

// The integral of exp(-sigma_t s) over one step of length dt, with sigma_t
// constant across the step: (1 - exp(-sigma_t dt)) / sigma_t (Hillaire 2015),
// given step_transmittance = exp(-sigma_t dt) (the caller needs it anyway, so
// a step costs one exp as the midpoint rule did). A midpoint rule (source x
// midpoint transmittance x dt) overshoots where a step is optically thick, as
// the long grazing steps near the horizon are: the sky just above the horizon
// came out brighter than the ground just below (a 1.1/255 seam at 10 km).
// Under x = 1e-3 a series keeps float precision.
ATMO_FN vec3 step_transmittance_integral(IN(vec3) sigma_t, float dt, IN(vec3) step_transmittance) {
  vec3 x = sigma_t * dt;
  vec3 series = vec3(1.0f) - x * (0.5f - x * (1.0f / 6.0f));
  vec3 exact = (vec3(1.0f) - step_transmittance) / max(x, vec3(1e-30f));
  return dt * mix(exact, series, lessThan(x, vec3(1e-3f)));
}

// --- The clouds' shadow on the air -----------------------------------------
// The clouds' shadow map (core/clouds/cloud_shadow.h: the direct
// transmittance of every cloud between a point of the clouds' ground plane
// and the Sun, looked up by sliding a point along the light onto that plane)
// darkens the sunlit air below the clouds: haze under an overcast, shafts
// between cumulus. The map is made for points below the clouds; within the
// layer the shadow fades out linearly from the lowest base to the highest
// top, above it there is none.
struct CloudShadowing {
  mat4 uv_from_eye_enu;  // a point (m, the eye's ENU: dir * t) -> (u, v, height in the clouds' frame m, 1)
  float base_m;          // the clouds' lowest base, that height
  float top_m;           // their highest top
  int enabled;           // 0: no clouds, or the map is not of the Sun
};

ATMO_FN CloudShadowing no_cloud_shadowing() {
  CloudShadowing cs;
  cs.uv_from_eye_enu = mat4(1.0f);
  cs.base_m = 0.0f;
  cs.top_m = 0.0f;
  cs.enabled = 0;
  return cs;
}

// The Sun's direct light at `p` relative to the eye (ENU m) passed by the
// clouds, [0, 1]: 1 off the map, above the clouds or when disabled.
ATMO_FN float cloud_shadowing_at(IN(CloudShadowing) cs, LUT2D map, IN(vec3) p) {
  if (cs.enabled == 0) return 1.0f;
  vec4 q = cs.uv_from_eye_enu * vec4(p, 1.0f);
  if (q.z >= cs.top_m || q.x < 0.0f || q.y < 0.0f || q.x > 1.0f || q.y > 1.0f) return 1.0f;
  float t = sample_lut(map, vec2(q.x, q.y)).r;
  float within = clamp((q.z - cs.base_m) / max(cs.top_m - cs.base_m, 1.0f), 0.0f, 1.0f);
  return mix(t, 1.0f, within);
}

// How far along `dir` from the eye the clouds' shadow can reach: to where the
// ray leaves the map's square or rises above the clouds' highest top (0 when
// it never passes under the clouds within the map, or when disabled). The
// part of a sky-dome ray it covers is what the sky pass takes the shadowed
// light from.
ATMO_FN float cloud_shadow_reach(IN(CloudShadowing) cs, IN(vec3) dir) {
  if (cs.enabled == 0) return 0.0f;
  vec4 q0 = cs.uv_from_eye_enu * vec4(0.0f, 0.0f, 0.0f, 1.0f);
  vec4 dq = cs.uv_from_eye_enu * vec4(dir, 0.0f);
  float t_in = 0.0f, t_out = 1e30f;
  // The slab 0 <= u, v <= 1 and height <= top.
  for (int a = 0; a < 2; ++a) {
    float o = a == 0 ? q0.x : q0.y, d = a == 0 ? dq.x : dq.y;
    if (abs(d) < 1e-12f) {
      if (o < 0.0f || o > 1.0f) return 0.0f;
      continue;
    }
    float ta = -o / d, tb = (1.0f - o) / d;
    t_in = max(t_in, min(ta, tb));
    t_out = min(t_out, max(ta, tb));
  }
  if (dq.z > 0.0f) {
    if (q0.z >= cs.top_m) return 0.0f;
    t_out = min(t_out, (cs.top_m - q0.z) / dq.z);
  } else if (dq.z < 0.0f) {
    if (q0.z > cs.top_m) t_in = max(t_in, (cs.top_m - q0.z) / dq.z);
  } else if (q0.z >= cs.top_m) {
    return 0.0f;
  }
  return t_out > t_in ? t_out : 0.0f;
}

// The sky's loss to the clouds' shadow is tabulated per view direction
// (sky_cloud_loss_lut.frag): u the azimuth in the eye's ENU (east = 0.5,
// wrapping at west), v the elevation, sqrt-spaced from the horizon (v = 0.5)
// to the zenith (1) and the nadir (0), where the loss changes fastest. x in
// [0, 1]^2 runs over texel centres, from the first to the last.
ATMO_FN vec3 sky_cloud_loss_direction(IN(vec2) x) {
  float azimuth = (2.0f * x.x - 1.0f) * ATMO_PI;
  float s = 2.0f * x.y - 1.0f;
  float elevation = s * abs(s) * (0.5f * ATMO_PI);
  return vec3(cos(elevation) * cos(azimuth), cos(elevation) * sin(azimuth), sin(elevation));
}

ATMO_FN vec2 sky_cloud_loss_uv(IN(vec3) dir, IN(vec2) table_size) {
  float azimuth = atan(dir.y, dir.x);
  float elevation = asin(clamp(dir.z, -1.0f, 1.0f));
  float s = elevation / (0.5f * ATMO_PI);
  vec2 x = vec2(0.5f + 0.5f * azimuth / ATMO_PI, 0.5f + 0.5f * sign(s) * sqrt(abs(s)));
  return (x * (table_size - 1.0f) + 0.5f) / table_size;
}

// The share of the light a cloud passes diffusely, given its direct
// transmittance: a conservative two-stream slab of optical depth tau =
// -ln(direct) and droplet asymmetry 0.85 lets 1 / (1 + 0.75 (1 - 0.85) tau)
// through (Bohren 1987). The map's half floats stop at 4.9e-4 (tau 7.6), so a
// deck thicker than that reads as 0.54.
ATMO_FN float cloud_diffuse_transmission(float direct) {
  return 1.0f / (1.0f + 0.1125f * -log(max(direct, 1e-6f)));
}

// Integrates scattered light (single scattering of Rayleigh + Mie with their
// phase functions, plus the isotropic multiple-scattering term sigma_s * Psi_ms)
// from the eye along `dir` over [0, max_distance] clipped to the atmosphere,
// with `steps` samples placed denser near the eye. Eye altitude in metres.
// The clouds' shadow at each sample (cs, map) scales the Sun's single
// scattering by the clouds' direct transmittance, and the air's multiple
// scattering by their diffuse transmission (cloud_diffuse_transmission): the
// diffuse light under a deck, which its base sends down, stands in for the
// sky's.
ATMO_FN ScatteringResult integrate_scattering_shadowed(IN(AtmosphereParameters) atm, LUT2D lut, IN(vec2) lut_size,
                                                       LUT2D ms_lut, IN(vec2) ms_size, float eye_altitude_m,
                                                       IN(vec3) dir, IN(vec3) sun_dir, float max_distance, int steps,
                                                       IN(CloudShadowing) cs, LUT2D map) {
  ScatteringResult result;
  result.inscattered = vec3(0.0f);
  result.transmittance = vec3(1.0f);
  result.shadowed_away = vec3(0.0f);
  vec3 center = vec3(0.0f, 0.0f, -(atm.bottom_radius_m + eye_altitude_m));
  vec3 eye_from_center = -center;

  // Enter the atmosphere if the eye is above it.
  float t_start = 0.0f;
  float r_eye = length(eye_from_center);
  if (r_eye > atm.top_radius_m) {
    t_start = ray_sphere_near(eye_from_center, dir, atm.top_radius_m);
    if (t_start < 0.0f) return result;  // looks past the atmosphere
  }
  float t_top = ray_sphere_far(eye_from_center, dir, atm.top_radius_m);
  float t_ground = ray_sphere_near(eye_from_center, dir, atm.bottom_radius_m);
  float t_end = t_top;
  if (t_ground > 0.0f) t_end = min(t_end, t_ground);
  t_end = min(t_end, max_distance);
  if (t_end <= t_start) return result;

  float cos_theta = dot(dir, sun_dir);
  float phase_r = rayleigh_phase(cos_theta);
  float phase_m = mie_phase(atm.mie_g, cos_theta);

  vec3 transmittance = vec3(1.0f);  // eye to the start of the current step
  float t_prev = t_start;
  float span = t_end - t_start;
  for (int i = 0; i < steps; ++i) {
    // Quadratic spacing: fine near the eye where density changes fastest.
    float s1 = (float(i) + 1.0f) / float(steps);
    float s0 = float(i) / float(steps);
    float sm = 0.5f * (s0 + s1);
    float t = t_start + span * sm * sm;
    float t_next = t_start + span * s1 * s1;
    float dt = t_next - t_prev;
    t_prev = t_next;

    vec3 p = eye_from_center + dir * t;
    float r = length(p);
    float altitude = r - atm.bottom_radius_m;
    float rd = rayleigh_density(atm, altitude);
    float md = mie_density(atm, altitude);
    vec3 sigma_t = atm.rayleigh_scattering * rd + atm.mie_extinction * md +
                   atm.ozone_absorption * ozone_density(atm, altitude);

    vec3 step_transmittance = exp(-sigma_t * dt);
    float mu_s = dot(p, sun_dir) / r;
    vec3 t_sun = transmittance_to_sun(atm, lut, lut_size, r, mu_s);
    vec3 scatter = atm.rayleigh_scattering * (rd * phase_r) + atm.mie_scattering * (md * phase_m);
    vec3 sigma_s = atm.rayleigh_scattering * rd + atm.mie_scattering * md;
    vec3 psi_ms = sample_lut(ms_lut, multiple_scattering_uv(atm, r, mu_s, ms_size));
    float direct = cloud_shadowing_at(cs, map, dir * t);
    float diffuse = cloud_diffuse_transmission(direct);
    vec3 weight = transmittance * step_transmittance_integral(sigma_t, dt, step_transmittance);
    result.inscattered += weight * (direct * t_sun * scatter + diffuse * sigma_s * psi_ms);
    result.shadowed_away += weight * ((1.0f - direct) * t_sun * scatter + (1.0f - diffuse) * sigma_s * psi_ms);
    transmittance *= step_transmittance;
  }
  result.transmittance = transmittance;
  result.inscattered *= atm.sun_illuminance_lux;
  result.shadowed_away *= atm.sun_illuminance_lux;
  return result;
}

// integrate_scattering_shadowed without clouds.
ATMO_FN ScatteringResult integrate_scattering(IN(AtmosphereParameters) atm, LUT2D lut, IN(vec2) lut_size,
                                              LUT2D ms_lut, IN(vec2) ms_size, float eye_altitude_m, IN(vec3) dir,
                                              IN(vec3) sun_dir, float max_distance, int steps) {
  return integrate_scattering_shadowed(atm, lut, lut_size, ms_lut, ms_size, eye_altitude_m, dir, sun_dir,
                                       max_distance, steps, no_cloud_shadowing(), lut);
}

// Radiance of the Lambertian ground seen at distance t_ground along dir, lit by
// the transmitted sun (a crude sky term is added by the caller if wanted).
ATMO_FN vec3 ground_radiance(IN(AtmosphereParameters) atm, LUT2D lut, IN(vec2) lut_size,
                     float eye_altitude_m, IN(vec3) dir, IN(vec3) sun_dir, float t_ground) {
  vec3 center = vec3(0.0f, 0.0f, -(atm.bottom_radius_m + eye_altitude_m));
  vec3 p = dir * t_ground - center;
  vec3 normal = normalize(p);
  float mu_s = dot(normal, sun_dir);
  vec3 t_sun = transmittance_to_sun(atm, lut, lut_size, atm.bottom_radius_m, mu_s);
  return atm.ground_albedo / ATMO_PI * atm.sun_illuminance_lux * t_sun * max(mu_s, 0.0f);
}

// Radiance of the sun's disc (cd/m^2) along dir, with limb darkening
// (Neckel & Labs polynomial fitted per channel is the next issue; here a
// grey u = 0.6 linear law).
ATMO_FN vec3 sun_disc_radiance(IN(AtmosphereParameters) atm, IN(vec3) dir, IN(vec3) sun_dir) {
  float cos_angle = dot(dir, sun_dir);
  float cos_radius = cos(atm.sun_angular_radius);
  if (cos_angle < cos_radius) return vec3(0.0f);
  float sin_radius = sin(atm.sun_angular_radius);
  float solid_angle = 2.0f * ATMO_PI * (1.0f - cos_radius);
  float s = clamp(sqrt(max(1.0f - cos_angle * cos_angle, 0.0f)) / sin_radius, 0.0f, 1.0f);
  float mu = sqrt(max(1.0f - s * s, 0.0f));
  const float u = 0.6f;
  float limb = (1.0f - u * (1.0f - mu)) / (1.0f - u / 3.0f);  // mean over the disc is 1
  return atm.sun_illuminance_lux / solid_angle * limb;
}

// --- Host depth to distance ---------------------------------------------------
// depth: the window-space value read from the host's depth texture. convention:
// 0 standard, 1 reversed [0,1], 2 logarithmic (see atmo.h). Returns the
// view-space point (camera at origin, looking down -z), or w < 0 for "no
// geometry" (the far plane / cleared depth).
ATMO_FN vec4 view_point_from_depth(IN(mat4) view_from_clip, IN(vec2) ndc_xy, float depth, int convention,
                           float log_far_m, float log_coefficient) {
  if (convention == 1) {
    if (depth <= 0.0f) return vec4(0.0f, 0.0f, 0.0f, -1.0f);
    vec4 p = view_from_clip * vec4(ndc_xy, depth, 1.0f);
    return vec4(vec3(p) / p.w, 1.0f);
  }
  if (depth >= 1.0f) return vec4(0.0f, 0.0f, 0.0f, -1.0f);
  if (convention == 2) {
    float w = (exp2(depth * log2(log_coefficient * log_far_m + 1.0f)) - 1.0f) / log_coefficient;
    vec4 near_point = view_from_clip * vec4(ndc_xy, -1.0f, 1.0f);
    vec3 ray = vec3(near_point) / near_point.w;
    return vec4(ray * (w / max(-ray.z, 1e-6f)), 1.0f);
  }
  vec4 p = view_from_clip * vec4(ndc_xy, depth * 2.0f - 1.0f, 1.0f);
  return vec4(vec3(p) / p.w, 1.0f);
}

// --- Whole pixels: what the passes compute, callable from the CPU twin -------

// View ray through a pixel, view space (camera looks down -z), from the
// inverse projection: the near-plane point (NDC z = -1, or +1 for reversed Z).
ATMO_FN vec3 view_ray_from_ndc(IN(mat4) view_from_clip, IN(vec2) ndc_xy, int convention) {
  float near_z = convention == 1 ? 1.0f : -1.0f;
  vec4 p = view_from_clip * vec4(ndc_xy, near_z, 1.0f);
  return normalize(vec3(p) / p.w);
}

// Sky radiance (cd/m^2) along an ENU direction, split so ambient lighting can
// leave out the sun (a separate light): `diffuse` is the in-scattered light to
// the top of the atmosphere plus, where the ray meets the Earth, the lit ground
// seen through the air; `sun_visible` says the ray reaches space, where the
// sun's disc (times `transmittance`) is added. eye_altitude_m must be >= 1.
struct SkyRadiance {
  vec3 diffuse;
  vec3 transmittance;
  bool sun_visible;
};

ATMO_FN SkyRadiance sky_radiance_parts(IN(AtmosphereParameters) atm, LUT2D lut, IN(vec2) lut_size, LUT2D ms_lut,
                                       IN(vec2) ms_size, float eye_altitude_m, IN(vec3) dir, IN(vec3) sun_dir,
                                       int steps) {
  ScatteringResult s = integrate_scattering(atm, lut, lut_size, ms_lut, ms_size, eye_altitude_m, dir, sun_dir, 1e12f,
                                            steps);
  vec3 center = vec3(0.0f, 0.0f, -(atm.bottom_radius_m + eye_altitude_m));
  float t_ground = ray_sphere_near(-center, dir, atm.bottom_radius_m);
  SkyRadiance r;
  r.transmittance = s.transmittance;
  r.sun_visible = !(t_ground > 0.0f);
  r.diffuse = s.inscattered;
  if (!r.sun_visible)
    r.diffuse += s.transmittance * ground_radiance(atm, lut, lut_size, eye_altitude_m, dir, sun_dir, t_ground);
  return r;
}

ATMO_FN vec3 sky_radiance(IN(AtmosphereParameters) atm, LUT2D lut, IN(vec2) lut_size, LUT2D ms_lut,
                          IN(vec2) ms_size, float eye_altitude_m, IN(vec3) dir, IN(vec3) sun_dir, int steps) {
  SkyRadiance r = sky_radiance_parts(atm, lut, lut_size, ms_lut, ms_size, eye_altitude_m, dir, sun_dir, steps);
  return r.sun_visible ? r.diffuse + r.transmittance * sun_disc_radiance(atm, dir, sun_dir) : r.diffuse;
}

// --- Sky-view table (Hillaire 2020, section 5.3) ----------------------------
// The diffuse sky of sky_radiance_parts (in-scattering to the top of the
// atmosphere, plus the lit ground where the ray meets the Earth; no sun disc)
// over every direction around the eye, by azimuth from the sun (0..pi: the sky
// is symmetric about the sun's vertical plane) and elevation. The geometric
// horizon, which dips by acos(R / r) with altitude, sits at v = 0.5 (a row
// boundary for an even height, so sky and ground texels never blend across
// it); above and below, v goes as the square root of the angle from the
// horizon, crowding texels where the sky changes fastest. The table depends on
// the eye altitude and the sun's elevation (and the air), not on the camera.

ATMO_FN float horizon_elevation(IN(AtmosphereParameters) atm, float eye_altitude_m) {
  float r = atm.bottom_radius_m + max(eye_altitude_m, 0.0f);
  return -acos(clamp(atm.bottom_radius_m / r, 0.0f, 1.0f));
}

ATMO_FN vec2 sky_view_uv(IN(AtmosphereParameters) atm, float eye_altitude_m, IN(vec3) dir, IN(vec3) sun_dir,
                         IN(vec2) lut_size) {
  float elevation = asin(clamp(dir.z, -1.0f, 1.0f));
  float h = horizon_elevation(atm, eye_altitude_m);
  float v = elevation >= h ? 0.5f + 0.5f * sqrt(clamp((elevation - h) / (0.5f * ATMO_PI - h), 0.0f, 1.0f))
                           : 0.5f - 0.5f * sqrt(clamp((h - elevation) / (h + 0.5f * ATMO_PI), 0.0f, 1.0f));
  float lv = length(vec2(dir.x, dir.y));
  float ls = length(vec2(sun_dir.x, sun_dir.y));
  float cos_phi = lv > 1e-6f && ls > 1e-6f ? clamp((dir.x * sun_dir.x + dir.y * sun_dir.y) / (lv * ls), -1.0f, 1.0f)
                                            : 1.0f;
  float u = acos(cos_phi) / ATMO_PI;
  // Within half a row of the horizon, bilinear filtering would blend the sky
  // and the Earth rows across it (a bright line on the ground): stay on the
  // direction's own side, at the centre of the row next to the horizon.
  float half_row = 0.5f / lut_size.y;
  float v_tex = 0.5f / lut_size.y + v * (1.0f - 1.0f / lut_size.y);
  v_tex = elevation >= h ? max(v_tex, 0.5f + half_row) : min(v_tex, 0.5f - half_row);
  return vec2(0.5f / lut_size.x + u * (1.0f - 1.0f / lut_size.x), v_tex);
}

// Inverse of sky_view_uv for filling the table: x in [0,1]^2 with texel
// centres removed; the direction is in a frame whose x axis is the sun's
// azimuth (the sun is at (cos e_s, 0, sin e_s)).
ATMO_FN vec3 sky_view_direction(IN(AtmosphereParameters) atm, float eye_altitude_m, IN(vec2) x) {
  float h = horizon_elevation(atm, eye_altitude_m);
  float s = 2.0f * abs(x.y - 0.5f);
  float elevation = x.y >= 0.5f ? h + s * s * (0.5f * ATMO_PI - h) : h - s * s * (h + 0.5f * ATMO_PI);
  float phi = x.x * ATMO_PI;
  return vec3(cos(elevation) * cos(phi), cos(elevation) * sin(phi), sin(elevation));
}

// One texel of the sky-view table: the diffuse sky (cd/m^2) at unit
// coordinates x, for the sun at elevation sine sin_sun_elevation.
ATMO_FN vec3 sky_view_texel(IN(AtmosphereParameters) atm, LUT2D lut, IN(vec2) lut_size, LUT2D ms_lut, IN(vec2) ms_size,
                            float eye_altitude_m, IN(vec2) x, float sin_sun_elevation, int steps) {
  float s = clamp(sin_sun_elevation, -1.0f, 1.0f);
  vec3 sun_local = vec3(sqrt(max(1.0f - s * s, 0.0f)), 0.0f, s);
  vec3 dir = sky_view_direction(atm, eye_altitude_m, x);
  return sky_radiance_parts(atm, lut, lut_size, ms_lut, ms_size, eye_altitude_m, dir, sun_local, steps).diffuse;
}

// Sky radiance (cd/m^2) from the sky-view table's value `diffuse` for the ENU
// direction dir: adds the sun's disc seen through the air where the ray
// reaches space (transmittance from the transmittance table).
ATMO_FN vec3 sky_radiance_with_sun(IN(AtmosphereParameters) atm, LUT2D lut, IN(vec2) lut_size, IN(vec3) diffuse,
                                   float eye_altitude_m, IN(vec3) dir, IN(vec3) sun_dir) {
  float r = atm.bottom_radius_m + max(eye_altitude_m, 0.0f);
  vec3 eye_from_center = vec3(0.0f, 0.0f, r);
  if (ray_sphere_near(eye_from_center, dir, atm.bottom_radius_m) > 0.0f) return diffuse;
  vec3 disc = sun_disc_radiance(atm, dir, sun_dir);
  if (disc.x + disc.y + disc.z <= 0.0f) return diffuse;
  return diffuse + disc * sample_lut(lut, transmittance_uv_from_r_mu(atm, r, dir.z, lut_size));
}

// --- Aerial-perspective volume (Hillaire 2020, section 5.4) ------------------
// Froxels over the screen: (u, v) is the pixel's position in the viewport and
// w the slice; slice k of n holds the in-scattered light and the transmittance
// from the eye to distance range * ((k + 1) / n)^2 along the froxel's centre
// ray. Quadratic slices keep near haze fine while one volume reaches the
// visible horizon from flight altitude (range = where a grazing ray leaves the
// atmosphere, or the host's far plane if nearer). The slice mapping and its
// inverse live in host_sdk/include/atmo/atmo_aerial_perspective.glsl, which
// host shaders use too.

// How far the volume must reach: from the eye to where a ray grazing the
// Earth leaves the atmosphere.
ATMO_FN float aerial_geometric_range(IN(AtmosphereParameters) atm, float eye_altitude_m) {
  float r = atm.bottom_radius_m + max(eye_altitude_m, 0.0f);
  float to_horizon = sqrt(max(r * r - atm.bottom_radius_m * atm.bottom_radius_m, 0.0f));
  float horizon_to_top = sqrt(atm.top_radius_m * atm.top_radius_m - atm.bottom_radius_m * atm.bottom_radius_m);
  return to_horizon + horizon_to_top;
}

// --- Output encoding -----------------------------------------------------------

// Narkowicz 2015 fit of the ACES filmic curve, then the sRGB transfer
// function: the one tone map of host_sdk/include/atmo/atmo_tone_map.glsl.
#define ATMO_TONE_FN ATMO_FN
#include "../host_sdk/include/atmo/atmo_tone_map.glsl"
#undef ATMO_TONE_FN
ATMO_FN vec3 encode_display_srgb(IN(vec3) exposed) { return atmo_display_srgb(exposed); }
