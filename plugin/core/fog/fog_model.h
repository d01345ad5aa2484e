// fog_model.h — homogeneous fog lit by point lights: the medium's optics and
// the lookup tables of host_sdk/include/atmo/atmo_fog_lights.glsl (Sun,
// Ramamoorthi, Narasimhan & Nayar 2005, in the stable form of docs/FOG.md).
// Pure CPU, double precision where tables are made; no GL.
#pragma once

#include <cmath>
#include <memory>
#include <vector>

namespace atmo::fog {

// Defaults for radiation fog's droplets (docs/FOG.md): Henyey-Greenstein
// asymmetry of ~10 um water droplets at 550 nm, and the albedo of water.
constexpr double kFogPhaseG = 0.85;
constexpr double kFogAlbedo = 0.999;
// The multiple-scattering handover rate: with t the optical thickness light ->
// point, the diffusion fluence is scaled by 1 - exp(-rate t) and its flux by
// (1 - exp(-0.4 rate t))^2 (atmo_fog_diffusion_light). Fitted to the all-orders
// Monte Carlo (tools/fog_reference/fog_handover_fit: g = 0.85, unbounded fog,
// T 0.25..16, view angles 2..150 deg, minimum RMS of ln(model / MC): 0.541 at
// 0.599 for albedo 0.99, 0.572 at 0.634 for albedo 0.999, T <= 8;
// docs/measurements/fog_multiple_scattering.md).
constexpr double kHandoverRate = 0.6;
// Heights and distances at or beyond this mean "none" (no fog top, no surface on the ray): ATMO_FOG_FAR.
constexpr float kNoTop = 1.0e30f;

// Extinction (1/m) of a fog of meteorological optical range `mor_m`: the
// 5 % contrast threshold, ln(20) / MOR, as the aerial perspective uses.
double extinction_from_visibility(double mor_m);

// Henyey-Greenstein phase function, 1/sr, of the cosine of the scattering angle
// (0 = forward).
double henyey_greenstein(double cos_angle, double g);

struct FogOptics {
  double extinction_per_m = 0.0;  // beta; 0: no fog
  double albedo = kFogAlbedo;     // scattering / extinction
  double phase_g = kFogPhaseG;    // Henyey-Greenstein asymmetry
  double top_height_m = INFINITY; // the layer's top, height above the ellipsoid; inf: no top
  bool multiple_scattering = true;
  // Transport coefficient sigma_a + sigma_s (1 - g) = beta (1 - albedo g).
  double transport_per_m() const;
  // Decay of the diffusion term: sqrt(3 sigma_tr sigma_a + (pi / H_eff)^2), the
  // second part the escape through the top of a layer `depth_m` deep (inf: none)
  // with the extrapolated boundary 2 / (3 sigma_tr) beyond each face.
  double diffusion_decay_per_m(double depth_m) const;
};

// A table for the GL layer (GL_R32F, GL_LINEAR, clamped) and its CPU twin:
// `width` columns fastest, `height` rows.
struct FogTable {
  int width = 0;
  int height = 0;
  std::vector<float> texels;
  float at(int x, int y) const { return texels[static_cast<size_t>(y) * width + x]; }
};

// The special function of the stable form, by adaptive quadrature:
//   Ghat(u, v) = integral_v^{pi/2} 4 pi p(2 xi) exp(-u (tan xi - tan v)) d xi,
// p the Henyey-Greenstein phase (g = 0: isotropic, Ghat(0, v) = pi/2 - v).
// u in [0, inf] (inf: the limit 0), v in [0, pi/2]. rel_tol relative.
double ghat(double u, double v, double g, double rel_tol = 1e-10);
// lim_{u->inf} u Ghat(u, v) = 4 pi p(2v) cos^2 v: the table's last column.
double ghat_u_limit(double v, double g);

// The airlight table: size x size texels of Ghat(u, v) / atmo_fog_ghat_scale(u, pi/2 - v)
// (atmo_fog_lights.glsl) on the grid x = sqrt(u / (1 + u)), y = v / (pi/2), both ends included.
FogTable build_airlight_table(int size, double g);

// The surface table: G_n(T, theta) (the paper's eq. 16 for a cos^n lobe, with
// the phase function), for n = 2^k, k = 0..8 (layer 0: the Lambertian G_0),
// stacked in rows: layer k holds rows [k * theta_size, (k + 1) * theta_size),
// theta in [0, pi]; columns the thickness coordinate of T (the last, T = inf,
// holds T = 100). Texels hold e^T G_n(T, theta).
constexpr int kSurfaceLayers = 9;
FogTable build_surface_table(int thickness_size, int theta_size, double g);
// A phase's tables (the airlight table of airlight_size, the surface table of
// surface_size x surface_size angles), made once per process and kept (the
// last few phases): ~40 ms on 2 cores the first time, ~30 ms of it the
// surface table's lobes, which no phase changes. A context makes the default
// phase's on a worker when it is created, so that its first set_fog need not
// wait; a call for tables being made waits for them.
struct FogTables {
  FogTable airlight, surface;
};
std::shared_ptr<const FogTables> fog_tables(double g, int airlight_size, int surface_size);
// G_n(T, theta) by quadrature (the table's reference), n >= 1.
double surface_g(double thickness, double theta, double exponent, double g);

// The glow's cull bound: La <= albedo * I * exp(-beta D) * beta Ghat(0, gamma/2) / (2 pi D sin gamma)
// (Ghat falls with u; the subtracted far term is >= 0). The angle (rad) beyond
// which the glow of a light of intensity `intensity_cd` at `distance_m` stays
// below `threshold_cd_m2`: 0 when even the core is below it, pi when no angle is.
class GlowBound {
 public:
  explicit GlowBound(double g);
  double radius_rad(double beta, double albedo, double distance_m, double intensity_cd, double threshold_cd_m2) const;

 private:
  std::vector<double> ghat0_;  // Ghat(0, gamma/2) at gamma_i = pi i / (n - 1)
  // For i in [1, n - 2]: the largest over j >= i of the bound's shape at sample j, max(Ghat_j, Ghat_j-1) /
  // sin gamma_j (not increasing in i: the first sample from the back above the threshold by bisection).
  std::vector<double> shape_max_;
};

}  // namespace atmo::fog
