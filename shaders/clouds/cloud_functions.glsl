// cloud_functions.glsl — the cloud lighting model, ONE source for the GLSL
// cloud passes and the C++ twin (plugin/core/clouds/cloud_twin.h), with the
// rules of atmosphere/functions.glsl (ATMO_FN, IN(), f-suffixed literals).
//
// Model (docs/CLOUDS.md): radiance along a view ray through a cloud is
//   L = integral of T_eye(s) * sigma_s(s) * [E_light * J_light(s) + L_ambient(s)] ds
// with
//   J_light = sum_n b^n * exp(-a^n * tau_light) * p(cos, g * c^n)
// the multiple-scattering octaves of Wrenninge et al. 2013 (n = 0 is single
// scattering; a, b, c < 1 lengthen the light's reach, weaken and widen each
// octave), p the droplet phase function of Jendersie & d'Eon 2023 (HG +
// Draine, fitted to Mie for a droplet diameter), and L_ambient the sky above
// and the ground below, each seen through the cloud's optical depth towards
// them (scaled by k_ambient for the diffuse light's shorter paths).
// tau_light, tau_up and tau_down come from the light grid
// (core/clouds/cloud_lighting.h). Units: 1/m, 1/sr, lux, cd/m^2.

const float CLOUD_PI = 3.14159265358979f;

// Phase-function parameters, from the droplet diameter (cloud_phase_for_droplet on the CPU).
struct CloudPhase {
  float g_hg;          // Henyey-Greenstein asymmetry (the diffraction peak)
  float g_draine;      // Draine asymmetry
  float alpha_draine;  // Draine's alpha
  float w_draine;      // weight of the Draine lobe
};

// Multiple-scattering octaves.
struct CloudOctaves {
  int count;                 // octaves summed, >= 1 (1 = single scattering only)
  float extinction_scale;    // a: optical depth to the light scales by a^n
  float scattering_scale;    // b: octave n is weighted b^n
  float eccentricity_scale;  // c: asymmetries scale by c^n
  float ambient_extinction;  // k: optical depth to the sky and ground scales by k
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

// J_light above: the light scattered towards the eye per unit scattering
// coefficient and unit illuminance, 1/sr.
ATMO_FN float cloud_light_octaves(IN(CloudPhase) ph, IN(CloudOctaves) oc, float tau_light, float cos_theta) {
  float sum = 0.0f;
  float weight = 1.0f;
  float reach = 1.0f;
  float g_scale = 1.0f;
  for (int n = 0; n < oc.count; ++n) {
    sum += weight * exp(-reach * tau_light) * cloud_phase(ph, cos_theta, g_scale);
    weight *= oc.scattering_scale;
    reach *= oc.extinction_scale;
    g_scale *= oc.eccentricity_scale;
  }
  return sum;
}

// In-scattered ambient radiance per unit scattering coefficient, cd/m^2: the
// sky's mean radiance over the upper hemisphere through tau_up, the ground's
// (or the deck's below) through tau_down, each covering half the sphere of an
// isotropic-averaged phase function.
ATMO_FN vec3 cloud_ambient(IN(CloudOctaves) oc, IN(vec3) sky_radiance, IN(vec3) ground_radiance, float tau_up,
                           float tau_down) {
  return 0.5f * (sky_radiance * exp(-oc.ambient_extinction * tau_up) +
                 ground_radiance * exp(-oc.ambient_extinction * tau_down));
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
