// fog_reference.h — an independent, double-precision, brute-force reference for
// light from point lights in a homogeneous fog: the single-scattering "airlight"
// of Sun, Ramamoorthi, Narasimhan & Nayar 2005 ("A Practical Analytic Single
// Scattering Model for Real Time Rendering", SIGGRAPH), its surface term
// (eq. 15), and a Monte Carlo path tracer with every scattering order.
//
// It integrates the physical integrals directly (adaptive Gauss-Kronrod in a
// geometric change of variable; no F / G tables, no special-function closed
// forms), so the plugin's fast table-based model can be measured against it.
// Extras over the paper: Henyey-Greenstein phase, absorption (albedo), cone
// lights, and a horizontal slab of fog with vacuum above and below.
//
// Units: SI, metres and radians. World z is up (only the slab uses it).
// Radiance comes out in the unit of the light's intensity per m^2
// (cd/m^2 for an intensity in cd, W/(m^2 sr) for W/sr).
#pragma once

#include <cstdint>
#include <limits>

#include <glm/glm.hpp>

namespace atmo::fog_reference {

struct Medium {
  double extinction_per_m = 0;  // beta = scattering + absorption, 1/m. <= 0: no medium (all radiances 0)
  double albedo = 1;            // single-scattering albedo, scattering / extinction
  double hg_g = 0;              // Henyey-Greenstein asymmetry in (-1, 1); 0 isotropic (clamped to +-0.999999)
  // Optional slab: the medium fills only bottom_m <= z <= top_m (world z up); outside is vacuum.
  // Both infinite by default (unbounded medium).
  double bottom_m = -std::numeric_limits<double>::infinity();
  double top_m = std::numeric_limits<double>::infinity();
};

struct Light {
  glm::dvec3 position_m{0.0};
  double intensity = 1;  // on-axis intensity (cd or W/sr)
  // Cone: intensity * profile(cos angle to axis); profile = 1 when cos_outer <= -1 (omnidirectional);
  // else smoothstep(cos_outer, cos_inner, c) (GLSL smoothstep, cos_inner > cos_outer; a hard edge at
  // cos_outer if cos_inner <= cos_outer).
  glm::dvec3 axis{0, 0, -1};  // unit (normalised internally)
  double cos_inner = -2, cos_outer = -2;
};

// Henyey-Greenstein phase function, 1/sr; integrates to 1 over the sphere. The argument is the cosine
// of the scattering angle (1 = forward, no deflection); g = 0 returns 1/(4 pi) exactly.
double henyey_greenstein(double cos_scattering_angle, double g);

// The cone profile in [0, 1] for a direction leaving the light (need not be unit; a zero vector gives 1).
double light_profile(const Light& light, const glm::dvec3& direction_from_light);

// Optical thickness of the segment a->b through the (slab) medium: beta * length of the part inside.
double optical_thickness(const Medium& medium, const glm::dvec3& a, const glm::dvec3& b);

// Single-scattered radiance arriving at `eye` from direction -view_dir (view_dir: from the eye outward;
// normalised internally), scattered once along the ray segment [0, d_vp] (d_vp may be INFINITY: no
// surface). Eq. (3) of the paper generalised:
//   integral_0^d_vp  beta*albedo * p(alpha) * I0*profile * exp(-tau(light->x)) / d^2 * exp(-tau(eye->x)) dx
// with d the light-to-point distance and alpha the scattering angle. The direct beam (the delta of eq. 2)
// is not included.
// Numerics: global adaptive Gauss-Kronrod (G7/K15) in eta, with x = x* + c tan(eta) centred on the point
// x* of the segment closest to the light (c = that distance); the 1/d^2 peak becomes bounded and an
// infinite d_vp becomes eta = pi/2 (no truncation). Break points at the closest approach, the slab
// boundary crossings and the cone-edge crossings. Stops when the summed |K15 - G7| estimate is below
// rel_tol * |result| (at most 20000 sub-intervals).
// Degenerate input: beta*albedo <= 0, intensity 0, d_vp <= 0 (or NaN) or a zero view_dir give 0.
// A light on (or within 1e-9 * D_sv of) the view line -- gamma = 0 or pi exactly -- is displaced
// perpendicularly to a distance of 1e-9 * D_sv, i.e. gamma is treated as >= 1e-9 rad: the airlight of an
// exactly on-axis point is infinite (the 1/gamma glow core), this gives the finite value just beside it
// (about beta*I0*exp(-T_sv) / (4 * D_sv * 1e-9) for an unbounded isotropic medium). A light exactly at the
// eye (D_sv = 0) has a divergent integral: returns 0. Never NaN.
double single_scattering_radiance(const Medium& medium, const Light& light, const glm::dvec3& eye,
                                  const glm::dvec3& view_dir, double d_vp, double rel_tol = 1e-8);

// The paper's eq. (15): light scattered once in the medium and then reflected by a surface at `point`,
// from one light, for unit BRDF weight (multiply by k_d or k_s):
//   lambert:  integral over the hemisphere about the unit normal n of L_a(incident dir, D_vp = inf) * cos(theta_i) d omega
//   phong(n): integral over the hemisphere about the unit direction r of L_a * cos^n(theta'_i) d omega
// (the surface horizon is ignored for the Phong lobe, as in the paper). With beta = extinction and
// D_sp = |light - point|, for an omni isotropic light in an unbounded medium these equal
// beta^2 * G_0(T_sp, theta_s) / (2 pi T_sp) and beta^2 * G_n(T_sp, theta'_s) / (2 pi T_sp) (times I0, albedo).
// Numerics: 2D adaptive Gauss-Kronrod over (polar, azimuth) about the LIGHT direction (the 1/sin gamma'
// of L_a cancels the solid-angle Jacobian), break points where the integration circle meets the
// horizon; each L_a from single_scattering_radiance at rel_tol / 100. For an omni light in an unbounded
// medium L_a depends on the polar angle only and is evaluated once per polar node; otherwise (cone
// light or slab) the full 2D integral is taken. A light at the point gives 0. phong with exponent 0 is
// the plain hemisphere integral of L_a.
double surface_scattered_lambert(const Medium& medium, const Light& light, const glm::dvec3& point,
                                 const glm::dvec3& normal, double rel_tol = 1e-5);
double surface_scattered_phong(const Medium& medium, const Light& light, const glm::dvec3& point,
                               const glm::dvec3& reflected, double exponent, double rel_tol = 1e-5);

// Monte Carlo with all orders of scattering: backward path tracing from the eye along view_dir,
// free-flight sampling (beta), next-event estimation to the point light for every path segment (HG
// phase, albedo as weight, profile and optical thickness to the light), new direction sampled from HG.
// The first segment ends at d_vp (a black surface; later segments are not blocked by it: a small object,
// as the paper assumes); a path that leaves the slab is lost (vacuum, black).
// Next-event estimation: the light scattered once along each segment is estimated from two samples
// combined by the balance heuristic: the free-flight sample (which is also the next vertex; alone, it
// is plain next-event estimation at that vertex) and an equiangular sample (pdf ~ 1/d^2 along the line,
// Kulla & Fajardo 2012). Plain vertex NEE has an infinite-variance 1/d^2 tail from vertices that land
// near the light; with the equiangular sample the per-segment weight is bounded by ~pi/b (b: the
// segment's distance to the light). Order k is the segment estimate on the k-th segment, so `single`
// is the view ray's.
// Termination: Russian roulette on the weight against a floor of max(0.1, r / R0), r the distance to the
// light, R0 = D_sv + 5 transport mean free paths (the importance of a walker far from the light falls
// like 1/r in the diffusion regime; unbiased), and a hard stop after max_orders vertices. Russian
// roulette leaves the expected weight unchanged, so truncated_weight is the weight the cap really cuts:
// ~0 with absorption or a slab, but ~1 in an unbounded conservative medium, where the order series
// decays only like k^-3/2 (diffusion) and the cap loses roughly 2 T_sv / sqrt(4 pi max_orders / (3 (1-g)))
// of the multiple part (~5 % at T_sv = 8, g = 0.85, max_orders = 2000).
// Variance: in an unbounded, nearly conservative medium the multiple part is dominated by the rare paths
// that pass close to the light (a heavy, log-divergent tail): expect ~10-20 % standard error at 1e4
// paths there, and standard errors that are themselves noisy; the single part is well behaved.
// Paths are split into fixed chunks of 1024, each with its own xoshiro256** stream seeded from
// (seed, chunk index) and reduced in chunk order: the result does not depend on `threads`
// (0: hardware concurrency).
struct MonteCarloResult {
  double total = 0, single = 0, multiple = 0;  // radiance: all orders, order 1, orders >= 2
  double total_std_error = 0, single_std_error = 0, multiple_std_error = 0;
  uint64_t paths = 0;
  double truncated_weight = 0;  // mean weight still alive at max_orders (see above)
  double mean_vertices = 0;     // scattering vertices per path (cost diagnostic)
};
MonteCarloResult monte_carlo_radiance(const Medium& medium, const Light& light, const glm::dvec3& eye,
                                      const glm::dvec3& view_dir, double d_vp, uint64_t paths, uint64_t seed,
                                      int max_orders = 2000, int threads = 0 /*0: hardware*/);

}  // namespace atmo::fog_reference
