// cloud_functions.glsl — the cloud lighting model, ONE source for the GLSL
// cloud passes and the C++ twin (plugin/core/clouds/cloud_twin.h), with the
// rules of atmosphere/functions.glsl (ATMO_FN, IN(), f-suffixed literals).
//
// Model (docs/CLOUDS.md): radiance along a view ray through a cloud is
//   L = integral of T_eye(s) * sigma_s(s) * [E_light * J_light(s) + L_ambient(s)] ds
// with
//   J_light = sum_n b^n * exp(-a^n * tau_light) * p(cos, g * c^n) + J_diffusion
// The sum is the multiple-scattering octaves of Wrenninge et al. 2013 (n = 0
// is single scattering; a, b, c < 1 lengthen the light's reach, weaken and
// widen each octave) for light scattered a few times; p is the droplet phase
// function of Jendersie & d'Eon 2023 (HG + Draine, fitted to Mie). J_diffusion
// is the light deep inside: the diffusion approximation's fluence (Ishimaru
// 1978, the Eddington slab solution) as the probability that a photon
// diffusing from the point leaves through the lit side rather than the far
// side, the top or the bottom (a gambler's ruin over escape conductances
// 1 / (1 + k tau) to Marshak's extrapolated boundaries), less the build-up
// below the lit surface. Orders >= 2 weigh 1 - exp(-theta tau_around): a thin
// cloud scatters little twice. L_ambient is the sky above and the ground below,
// split by where the light came from: along the view ray through the phase
// function after few scatterings, by the same escape conductances upwards and
// downwards after many; a non-absorbing cloud in a uniform surrounding returns
// it (white furnace). The march takes the diffusion and ambient terms from a
// few optical depths further along the view ray (cloud_lookahead_share).
// tau_light, tau_up and tau_down (hemispherical) come from the light grid
// (core/clouds/cloud_lighting.h); the march adds tau_back, the optical depth
// behind the point away from the light (cloud_march.glsl). Units: 1/m, 1/sr,
// lux, cd/m^2.

const float CLOUD_PI = 3.14159265358979f;

// Where the march stops: once the background's transmittance is below this,
// the rest of the ray is dropped and the transmittance set to 0. What that
// drops is < 1e-6 of the background (the Sun's disc included: issue 19 asks
// < 1e-6 of its clear value behind a deck) plus < 1e-6 of the light the cloud
// scatters from beyond the stop. A transmittance above it is kept as marched,
// so a thin cloud is not darkened. Stored as 1 - T in the half-float image,
// T = 0 is exact (alpha 1), where the residual kept across a deck's tiles
// (up to 1e-3) read as 4.9e-4 (the half float's step below 1) and let
// ~1e6 cd/m^2 of the disc through.
const float CLOUD_OPAQUE_TRANSMITTANCE = 1e-6f;

// Phase-function parameters, from the droplet diameter (cloud_phase_for_droplet on the CPU).
struct CloudPhase {
  float g_hg;          // Henyey-Greenstein asymmetry (the diffraction peak)
  float g_draine;      // Draine asymmetry
  float alpha_draine;  // Draine's alpha
  float w_draine;      // weight of the Draine lobe
};

// Multiple-scattering octaves, the diffusion term and the ambient term
// (defaults and how they were fitted: core/clouds/cloud_optics.cpp).
struct CloudOctaves {
  int count;                 // octaves summed, >= 1 (1 = single scattering only)
  float extinction_scale;    // a: optical depth to the light scales by a^n
  float scattering_scale;    // b: octave n is weighted b^n
  float eccentricity_scale;  // c: asymmetries scale by c^n
  float ambient_extinction;  // k: optical depth to the sky and ground scales by k in their escape probabilities
  float ambient_loss;                  // the ambient reaches the point scaled by 1 - this (0: white furnace)
  float diffusion_strength;            // K: diffuse fluence / (E_light) where the lit side owns all escape; 0 = no diffusion term
  float diffusion_extinction;          // k_d: optical depths scale by k_d in the diffusion's escape probabilities
  float diffusion_side_escape;         // lambda: weight of escape through the top and bottom besides the light's axis
  float diffusion_anisotropy;          // g_d: diffuse light grows by (1 + g_d cos) towards the light's travel direction
  float diffusion_buildup_extinction;  // s: the diffuse light builds up as 1 - exp(-s tau_light) below the lit surface
  float diffusion_lookahead;           // Lambda: diffuse and ambient light come from ~Lambda optical depths further along the view ray (0: the point itself)
  float thin_extinction;               // theta: orders >= 2 scale by 1 - exp(-theta tau_around) (a thin cloud scatters little twice)
  float ambient_view_extinction;       // beta: the ambient's sky/ground split follows the view's elevation with weight exp(-beta tau_around)
  vec3 up_grid;                        // the zenith in the grids' axes: (0, 0, 1) while clouds turn only about the vertical
};

ATMO_FN float cloud_hg(float g, float cos_theta) {
  float g2 = g * g;
  float denom = max(1.0f + g2 - 2.0f * g * cos_theta, 1e-7f);
  return (1.0f - g2) / (4.0f * CLOUD_PI * denom * sqrt(denom));
}

// Draine 2003: HG times (1 + alpha cos^2) / (1 + alpha (1 + 2 g^2) / 3); integrates to 1.
ATMO_FN float cloud_draine(float g, float alpha, float cos_theta) {
  return cloud_hg(g, cos_theta) * (1.0f + alpha * cos_theta * cos_theta) /
         (1.0f + alpha * (1.0f + 2.0f * g * g) / 3.0f);
}

// 1/sr; cos_theta between the light's travel direction and the direction to the eye
// (1 = looking into the light through the cloud). g_scale = c^n for octave n.
ATMO_FN float cloud_phase(IN(CloudPhase) ph, float cos_theta, float g_scale) {
  return (1.0f - ph.w_draine) * cloud_hg(ph.g_hg * g_scale, cos_theta) +
         ph.w_draine * cloud_draine(ph.g_draine * g_scale, ph.alpha_draine, cos_theta);
}

// The octaves' part of J_light: the light scattered towards the eye per unit
// scattering coefficient and unit illuminance, 1/sr; orders n >= 1 weighted
// by `multiple` (cloud_multiple_share).
ATMO_FN float cloud_light_octaves(IN(CloudPhase) ph, IN(CloudOctaves) oc, float tau_light, float cos_theta,
                                  float multiple) {
  float sum = 0.0f;
  float weight = 1.0f;
  float reach = 1.0f;
  float g_scale = 1.0f;
  for (int n = 0; n < oc.count; ++n) {
    sum += weight * exp(-reach * tau_light) * cloud_phase(ph, cos_theta, g_scale);
    weight *= (n == 0 ? multiple : 1.0f) * oc.scattering_scale;
    reach *= oc.extinction_scale;
    g_scale *= oc.eccentricity_scale;
  }
  return sum;
}

// How readily a diffusing photon leaves through a boundary at optical depth
// tau: 1 / (1 + k tau), the diffusion approximation's flux to an extrapolated
// boundary (1D: the gambler's ruin is linear in distance, so the probability
// of leaving through one side is its conductance over the sum).
ATMO_FN float cloud_escape(float k, float tau) {
  return 1.0f / (1.0f + k * max(tau, 0.0f));
}

// The optical size of the cloud around a point: the mean of its chords along
// the light (tau_light + tau_back) and the vertical (tau_up + tau_down).
ATMO_FN float cloud_tau_around(float tau_light, float tau_back, float tau_up, float tau_down) {
  return 0.5f * (tau_light + tau_back + tau_up + tau_down);
}

// The weight of scattering orders >= 2 at a point: light scattered once
// around it is scattered again there only as far as the surroundings are
// optically thick, 1 - exp(-theta tau_around) (1 inside thick clouds; theta 0:
// always 1).
ATMO_FN float cloud_multiple_share(IN(CloudOctaves) oc, float tau_around) {
  return oc.thin_extinction > 0.0f ? 1.0f - exp(-oc.thin_extinction * tau_around) : 1.0f;
}

// The diffuse (all orders, diffusion-approximation) part of J_light, 1/sr:
// K times the probability that a photon diffusing from the point leaves
// through the lit side (towards the light, tau_light) rather than the far
// side (tau_back, away from the light) or, weighted by lambda, through the
// top and bottom beyond what the light's axis already counts; less the
// build-up exp(-s tau_light) just below the lit surface; times the diffuse
// flux's forward bias (1 + g_d cos) (cos: as in cloud_phase). Isotropic part
// of the radiance = fluence / 4 pi. The caller weighs it by
// cloud_multiple_share.
ATMO_FN float cloud_light_diffusion(IN(CloudOctaves) oc, float tau_light, float tau_back, float tau_up,
                                    float tau_down, float cos_theta) {
  if (oc.count < 2 || oc.diffusion_strength <= 0.0f) return 0.0f;  // count 1: single scattering only
  float k = oc.diffusion_extinction;
  float to_light = cloud_escape(k, tau_light);
  float to_back = cloud_escape(k, tau_back);
  float to_sides = max(cloud_escape(k, tau_up) + cloud_escape(k, tau_down) - to_light - to_back, 0.0f);
  float lit = to_light / (to_light + to_back + oc.diffusion_side_escape * to_sides);
  float fluence = lit * (1.0f + oc.diffusion_anisotropy * cos_theta) -
                  exp(-oc.diffusion_buildup_extinction * tau_light);
  return oc.diffusion_strength * max(fluence, 0.0f) / (4.0f * CLOUD_PI);
}

// The share of the diffuse light still owed to the points behind that a step
// of optical thickness step_tau settles: the diffuse radiance leaving a point
// towards the eye was carried there from upstream (the diffusion
// approximation's radiance, U - 3 F.w, is the fluence about one transport
// mean free path upstream; Jensen et al. 2001 place the dipole's source that
// deep for the same reason), so each point's diffuse source is the mean of the
// diffusion and ambient terms over the optical depths beyond it along the
// view ray with weight exp(-delta tau / Lambda) / Lambda, the remainder at the
// ray's last sample.
ATMO_FN float cloud_lookahead_share(IN(CloudOctaves) oc, float step_tau) {
  return oc.diffusion_lookahead > 0.0f ? 1.0f - exp(-step_tau / oc.diffusion_lookahead) : 1.0f;
}

// The share of the ambient light at a point that came from the sky (the rest
// from the ground). Light that reaches the point after few scatterings came
// along the view ray through the phase function: its diffraction peak (weight
// 1 - w_draine) from straight behind the point (the sky when the eye looks up,
// mu = view . zenith > 0), its Draine lobe tilted by ~1.5 g_draine mu; light
// that diffused there escaped upwards or downwards as the conductances through
// tau_up and tau_down say (cloud_escape). The first weighs exp(-beta
// tau_around).
ATMO_FN float cloud_sky_share(IN(CloudPhase) ph, IN(CloudOctaves) oc, float tau_up, float tau_down,
                              float tau_around, float mu) {
  float up = cloud_escape(oc.ambient_extinction, tau_up);
  float down = cloud_escape(oc.ambient_extinction, tau_down);
  float diffused = up / (up + down);
  float peak = clamp(0.5f + 25.0f * mu, 0.0f, 1.0f);
  float lobe = clamp(0.5f + 0.75f * ph.g_draine * mu, 0.0f, 1.0f);
  float along_view = (1.0f - ph.w_draine) * peak + ph.w_draine * lobe;
  float t = exp(-oc.ambient_view_extinction * tau_around);
  return t * along_view + (1.0f - t) * diffused;
}

// In-scattered ambient radiance per unit scattering coefficient, cd/m^2: the
// sky's mean radiance over the upper hemisphere and the ground's (or the
// deck's below) over the lower, split by cloud_sky_share, times 1 -
// ambient_loss (a non-absorbing cloud in a uniform surrounding returns it:
// white furnace).
ATMO_FN vec3 cloud_ambient(IN(CloudPhase) ph, IN(CloudOctaves) oc, IN(vec3) sky_radiance, IN(vec3) ground_radiance,
                           float tau_up, float tau_down, float tau_around, float mu) {
  float sky = cloud_sky_share(ph, oc, tau_up, tau_down, tau_around, mu);
  return (1.0f - oc.ambient_loss) * (sky_radiance * sky + ground_radiance * (1.0f - sky));
}

// One step of the eye-ray integral over a segment of length dt with constant
// extinction sigma_t and source S = sigma_s * (in-scattered radiance): the
// exact integral of T * S over the segment (Hillaire 2016's energy-conserving
// form), so a coarse step neither loses nor invents light. Returns the
// radiance added in front of the segment's far end, relative to T at its start.
ATMO_FN vec3 cloud_step_radiance(IN(vec3) source, float sigma_t, float dt) {
  float step_t = exp(-sigma_t * dt);
  return sigma_t > 1e-9f ? source * (1.0f - step_t) / sigma_t : source * dt;
}

// A view ray's running sums through a cloud (cloud_march.glsl, cloud_layer_march.glsl).
struct CloudRay {
  vec3 radiance;        // scattered towards the eye, relative to the transmittance where the sums started
  float transmittance;  // from there
  float owed;           // scattering weight whose diffuse source is still to come (cloud_lookahead_share)
  vec3 diffuse;         // the last sample's diffuse source (diffusion + ambient) per unit weight
  float depth_sum;      // opacity-weighted distance, m
  float weight_sum;
};

ATMO_FN CloudRay cloud_ray_start() {
  CloudRay r;
  r.radiance = vec3(0.0f);
  r.transmittance = 1.0f;
  r.owed = 0.0f;
  r.diffuse = vec3(0.0f);
  r.depth_sum = 0.0f;
  r.weight_sum = 0.0f;
  return r;
}

// One step of dt_m metres at distance depth_m with constant extinction
// sigma_t (> 0) and the optical depths at its point: the octaves there, the
// diffusion and ambient terms owed to its scattering and paid from the
// samples ahead. cos_theta: light . view (cloud_phase); mu: view . zenith.
ATMO_FN CloudRay cloud_ray_step(IN(CloudRay) r, IN(CloudPhase) ph, IN(CloudOctaves) oc, IN(vec3) light_illuminance,
                                IN(vec3) sky_radiance, IN(vec3) ground_radiance, float albedo, float cos_theta,
                                float mu, float sigma_t, float dt_m, float depth_m, float tau_light, float tau_back,
                                float tau_up, float tau_down) {
  CloudRay s = r;
  float around = cloud_tau_around(tau_light, tau_back, tau_up, tau_down);
  float multiple = cloud_multiple_share(oc, around);
  vec3 in_light = light_illuminance * cloud_light_octaves(ph, oc, tau_light, cos_theta, multiple);
  s.radiance += s.transmittance * cloud_step_radiance((albedo * sigma_t) * in_light, sigma_t, dt_m);
  s.diffuse = (light_illuminance * multiple) * cloud_light_diffusion(oc, tau_light, tau_back, tau_up, tau_down, cos_theta) +
              cloud_ambient(ph, oc, sky_radiance, ground_radiance, tau_up, tau_down, around, mu);
  float step_t = exp(-sigma_t * dt_m);
  s.owed += s.transmittance * albedo * (1.0f - step_t);
  float share = s.owed * cloud_lookahead_share(oc, sigma_t * dt_m);
  s.radiance += share * s.diffuse;
  s.owed -= share;
  float w = s.transmittance * (1.0f - step_t);
  s.depth_sum += w * depth_m;
  s.weight_sum += w;
  s.transmittance *= step_t;
  return s;
}

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
