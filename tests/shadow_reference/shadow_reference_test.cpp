// Tests of the sky-shadow and bounce reference (tools/shadow_reference) against closed forms:
// the unoccluded sky (uniform and linear in z), spheres overhead (form factor sin^2 theta) and tilted
// (sin^2 theta cos beta), the standard error's convergence, the Sun's disc behind spheres and the
// ground, one bounce off a sphere under a uniform sky (a L pi sin^2 theta), a sun-lit sphere against an
// independent surface-area quadrature, the ground's bounce, a box mesh against the parallel-rectangle
// form factor, the BVH against a brute-force loop over triangles, and degenerate inputs.
// Every test prints what it measured ("[ measured ]" lines).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <vector>

#include <atmo_monte_carlo/sampling.h>

#include "mesh.h"
#include "shadow_reference.h"

namespace sr = atmo::shadow_reference;
using atmo::spheres::TriangleMesh;
using glm::dvec3;

namespace {

constexpr double kPi = 3.14159265358979323846;
double deg(double d) { return d * kPi / 180.0; }

// A rotated, translated frame so that no test geometry is axis aligned (except where the ground is).
struct Frame {
  dvec3 origin{3.25, -1.5, 7.0};
  dvec3 ex, ey, ez;
  Frame() {
    const dvec3 axis = glm::normalize(dvec3(0.3, -0.8, 0.52));
    const double a = 0.9;  // Rodrigues rotation by a about axis
    auto rot = [&](const dvec3& v) {
      return v * std::cos(a) + glm::cross(axis, v) * std::sin(a) + axis * glm::dot(axis, v) * (1 - std::cos(a));
    };
    ex = rot(dvec3(1, 0, 0));
    ey = rot(dvec3(0, 1, 0));
    ez = rot(dvec3(0, 0, 1));
  }
};

const dvec3 kSkyL{1.0, 2.0, 0.5};  // a uniform sky's radiance, distinct per channel

sr::Scene uniform_sky_scene(const dvec3& L = kSkyL) {
  sr::Scene scene;
  scene.sky_radiance = [L](const dvec3&) { return L; };
  return scene;
}

double max_abs(const dvec3& v) { return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}); }
// The largest |got - want| over the channels in units of the channel's standard error.
double worst_sigmas(const sr::Estimate& e, const dvec3& want) {
  double worst = 0;
  for (int c = 0; c < 3; ++c) {
    const double err = std::abs(e.value[c] - want[c]);
    worst = std::max(worst, e.standard_error[c] > 0 ? err / e.standard_error[c] : (err > 0 ? 1e300 : 0.0));
  }
  return worst;
}
double worst_rel(const dvec3& got, const dvec3& want, const dvec3& scale) {
  double worst = 0;
  for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(got[c] - want[c]) / std::abs(scale[c]));
  return worst;
}
bool finite(const dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Asserts e against `want` to `rel_tol` of `scale` (per channel), and within `sigmas` standard errors unless
// the error is below `abs_slack` of `scale` (zero-variance cases); prints both.
void expect_close(const char* what, const sr::Estimate& e, const dvec3& want, const dvec3& scale, double rel_tol,
                  double sigmas = 4.0, double abs_slack = 1e-12) {
  const double rel = worst_rel(e.value, want, scale);
  const double sig = worst_sigmas(e, want);
  if (rel > abs_slack) {
    std::printf("[ measured ] %-44s |err| / scale %.3e = %.2f SE, SE / scale %.2e, %ld samples\n", what, rel, sig,
                max_abs(e.standard_error / scale), e.samples);
  } else {  // a zero-variance case: only rounding is left, and the standard error is rounding too
    std::printf("[ measured ] %-44s |err| / scale %.3e (exact to rounding), %ld samples\n", what, rel, e.samples);
  }
  EXPECT_LT(rel, rel_tol) << what;
  if (rel > abs_slack) {
    EXPECT_LT(sig, sigmas) << what;
  }
}

// ---- meshes made here (TriangleMesh is a plain struct: no functions of tools/spheres are used) ----

// Orients every triangle counter-clockwise seen from outside a convex shape around `inside`.
void orient_outward(TriangleMesh& m, const dvec3& inside) {
  for (glm::uvec3& t : m.triangles) {
    const dvec3 a = m.vertices[t.x], b = m.vertices[t.y], c = m.vertices[t.z];
    if (glm::dot(glm::cross(b - a, c - a), (a + b + c) / 3.0 - inside) < 0) std::swap(t.y, t.z);
  }
}

TriangleMesh box_mesh(const dvec3& lo, const dvec3& hi) {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i) m.vertices.push_back(dvec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z));
  // Each face: the four corners with one coordinate bit fixed, split into two triangles.
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      std::vector<unsigned> c;
      for (unsigned i = 0; i < 8; ++i)
        if (((i >> axis) & 1u) == static_cast<unsigned>(side)) c.push_back(i);
      // c is in bit order: c[0], c[1], c[3], c[2] go around the face.
      m.triangles.push_back({c[0], c[1], c[3]});
      m.triangles.push_back({c[0], c[3], c[2]});
    }
  orient_outward(m, (lo + hi) * 0.5);
  return m;
}

// The octahedron subdivided `levels` times, vertices pushed onto the unit sphere (8 * 4^levels triangles).
TriangleMesh octasphere_mesh(int levels) {
  std::vector<std::array<dvec3, 3>> tris;
  const dvec3 X(1, 0, 0), Y(0, 1, 0), Z(0, 0, 1);
  for (double sx : {-1.0, 1.0})
    for (double sy : {-1.0, 1.0})
      for (double sz : {-1.0, 1.0}) tris.push_back({sx * X, sy * Y, sz * Z});
  for (int l = 0; l < levels; ++l) {
    std::vector<std::array<dvec3, 3>> next;
    for (const auto& t : tris) {
      const dvec3 a = glm::normalize(t[0] + t[1]), b = glm::normalize(t[1] + t[2]), c = glm::normalize(t[2] + t[0]);
      next.push_back({t[0], a, c});
      next.push_back({a, t[1], b});
      next.push_back({c, b, t[2]});
      next.push_back({a, b, c});
    }
    tris.swap(next);
  }
  TriangleMesh m;
  for (const auto& t : tris) {
    const unsigned base = static_cast<unsigned>(m.vertices.size());
    for (const dvec3& v : t) m.vertices.push_back(v);
    m.triangles.push_back({base, base + 1, base + 2});
  }
  orient_outward(m, dvec3(0.0));
  return m;
}

glm::dmat4 translate(const dvec3& t) {
  glm::dmat4 m(1.0);
  m[3] = glm::dvec4(t, 1.0);
  return m;
}
glm::dmat4 rotate_z(double a) {
  glm::dmat4 m(1.0);
  m[0] = glm::dvec4(std::cos(a), std::sin(a), 0, 0);
  m[1] = glm::dvec4(-std::sin(a), std::cos(a), 0, 0);
  return m;
}
glm::dmat4 scale(const dvec3& s) {
  glm::dmat4 m(1.0);
  m[0][0] = s.x;
  m[1][1] = s.y;
  m[2][2] = s.z;
  return m;
}
// A general rotation: the Frame's axes as columns.
glm::dmat4 rotate_frame(const Frame& f) {
  glm::dmat4 m(1.0);
  m[0] = glm::dvec4(f.ex, 0);
  m[1] = glm::dvec4(f.ey, 0);
  m[2] = glm::dvec4(f.ez, 0);
  return m;
}

// The form factor from a differential area to a parallel rectangle x by y at height h over one corner.
double corner_form_factor(double x, double y, double h) {
  const double X = x / h, Y = y / h;
  const double sx = std::sqrt(1 + X * X), sy = std::sqrt(1 + Y * Y);
  return (X / sx * std::atan(Y / sx) + Y / sy * std::atan(X / sy)) / (2 * kPi);
}

}  // namespace

// 1. No occluders: a uniform sky L gives E = pi L for any normal, occluded or not; a sky linear in z,
//    L = A + B w_z, gives E = pi A + (2 pi / 3) B n_z (the hemisphere's first moment is (2 pi / 3) n).
TEST(ShadowReference, UnoccludedSky) {
  const Frame f;
  const sr::Scene scene = uniform_sky_scene();
  for (const dvec3& n : {f.ez, -f.ex, glm::normalize(f.ex + 2.0 * f.ey - f.ez)}) {
    for (bool occluded : {false, true}) {
      const sr::Estimate e = sr::sky_irradiance(scene, f.origin, n, occluded, 10000);
      expect_close(occluded ? "uniform sky, occluded, empty scene" : "uniform sky, unoccluded", e, kPi * kSkyL,
                   kPi * kSkyL, 1e-3);
    }
  }
  const dvec3 A(2.0, 1.0, 3.0), B(1.0, 0.5, -2.0);
  sr::Scene linear;
  linear.sky_radiance = [A, B](const dvec3& w) { return A + B * w.z; };
  for (const dvec3& n : {dvec3(0, 0, 1), glm::normalize(dvec3(0.4, -0.3, 0.6)), glm::normalize(dvec3(0.2, 0.5, -0.9))}) {
    const sr::Estimate e = sr::sky_irradiance(linear, f.origin, n, false, 100000, 7);
    expect_close("linear sky A + B w_z", e, kPi * A + (2 * kPi / 3) * B * n.z, kPi * A, 1e-3);
  }
}

// 2. A sphere of angular radius theta centred on the normal: the cosine-weighted cap it covers is
//    sin^2 theta of the hemisphere, so E = pi L (1 - sin^2 theta).
TEST(ShadowReference, SphereOverhead) {
  const Frame f;
  for (double theta_deg : {10.0, 30.0, 60.0, 85.0}) {
    sr::Scene scene = uniform_sky_scene();
    const double d = 20.0, s = std::sin(deg(theta_deg));
    scene.spheres.push_back({f.origin + d * f.ez, d * s, 0});
    const sr::Estimate e = sr::sky_irradiance(scene, f.origin, f.ez, true, 1000000, 3);
    char what[64];
    std::snprintf(what, sizeof what, "sphere overhead, theta %.0f deg", theta_deg);
    expect_close(what, e, kPi * kSkyL * (1 - s * s), kPi * kSkyL, 1e-3);
  }
}

// 3. The sphere's centre at beta from the normal, the cap wholly above the horizon (beta + theta < 90 deg):
//    blocked = pi L sin^2 theta cos beta.
TEST(ShadowReference, SphereTilted) {
  const Frame f;
  const struct {
    double theta, beta;
  } cases[] = {{20, 0}, {20, 30}, {20, 65}, {40, 45}, {10, 79}};
  for (const auto& c : cases) {
    sr::Scene scene = uniform_sky_scene();
    const double d = 7.5, s = std::sin(deg(c.theta));
    const dvec3 dir = std::cos(deg(c.beta)) * f.ez + std::sin(deg(c.beta)) * f.ey;
    scene.spheres.push_back({f.origin + d * dir, d * s, 0});
    const sr::Estimate e = sr::sky_irradiance(scene, f.origin, f.ez, true, 1000000, 5);
    char what[64];
    std::snprintf(what, sizeof what, "sphere tilted, theta %.0f beta %.0f deg", c.theta, c.beta);
    expect_close(what, e, kPi * kSkyL * (1 - s * s * std::cos(deg(c.beta))), kPi * kSkyL, 1e-3);
  }
}

// 4. Convergence: at N = 1e3, 1e4, 1e5 the error stays within 3 standard errors, the standard error falls
//    at least as 1/sqrt(N) (stratification does better) and so does the RMS error over 8 seeds.
TEST(ShadowReference, Convergence) {
  const Frame f;
  sr::Scene scene = uniform_sky_scene(dvec3(1.0));
  const double d = 3.0, s = std::sin(deg(30.0));
  const dvec3 dir = std::cos(deg(25.0)) * f.ez + std::sin(deg(25.0)) * f.ex;
  scene.spheres.push_back({f.origin + d * dir, d * s, 0});
  const double want = kPi * (1 - s * s * std::cos(deg(25.0)));
  double prev_se = 0, prev_rms = 0;
  for (long n : {1000L, 10000L, 100000L}) {
    const sr::Estimate e = sr::sky_irradiance(scene, f.origin, f.ez, true, n, 11);
    const double err = std::abs(e.value.x - want), se = e.standard_error.x;
    double sq = 0;
    for (uint64_t seed = 100; seed < 108; ++seed) {
      const double r = sr::sky_irradiance(scene, f.origin, f.ez, true, n, seed).value.x - want;
      sq += r * r;
    }
    const double rms = std::sqrt(sq / 8);
    std::printf("[ measured ] convergence N %6ld (%6ld used): err %.3e = %.2f SE, SE %.3e, RMS err (8 seeds) %.3e", n,
                e.samples, err, err / se, se, rms);
    if (prev_se > 0) std::printf(", SE ratio %.3f, RMS ratio %.3f (1/sqrt(10) = 0.316)", se / prev_se, rms / prev_rms);
    std::printf("\n");
    EXPECT_LT(err, 3 * se) << n;
    EXPECT_GT(e.samples, n * 8 / 10);
    EXPECT_LE(e.samples, n);
    if (prev_se > 0) {
      EXPECT_LT(se / prev_se, 0.45) << n;  // 1/sqrt(10) = 0.316 for plain Monte Carlo
      EXPECT_LT(rms / prev_rms, 0.5) << n;
    }
    prev_se = se;
    prev_rms = rms;
  }
}

// 5. The Sun's disc: clear, fully behind a big sphere, a sphere's limb through the disc's centre (checked
//    against an angle test over the disc, ~0.5), a small sphere partly over it (lens area), below the ground.
TEST(ShadowReference, SunVisibility) {
  const Frame f;
  sr::Scene scene;
  const dvec3 sun = glm::normalize(0.8 * f.ex + 0.6 * f.ez);
  scene.sun_direction = sun;
  const double r_sun = scene.sun_angular_radius_rad;
  scene.spheres.push_back({f.origin - 10.0 * sun, 3.0, 0});  // behind the receiver: no effect
  const double clear = sr::sun_visibility(scene, f.origin);
  std::printf("[ measured ] sun clear: %.6f\n", clear);
  EXPECT_EQ(clear, 1.0);

  sr::Scene blocked = scene;
  blocked.spheres.push_back({f.origin + 50.0 * sun, 5.0, 0});
  const double behind = sr::sun_visibility(blocked, f.origin);
  std::printf("[ measured ] sun behind a sphere: %.6f\n", behind);
  EXPECT_EQ(behind, 0.0);

  // The limb through the centre: the sphere's centre at its own angular radius alpha from the Sun.
  const double alpha = deg(30.0), dist = 100.0;
  const dvec3 perp = f.ey;  // orthogonal to sun (sun is in the ex-ez plane)
  const dvec3 c_dir = std::cos(alpha) * sun + std::sin(alpha) * perp;
  sr::Scene half = scene;
  half.spheres.push_back({f.origin + dist * c_dir, dist * std::sin(alpha), 0});
  // Independent expectation: the fraction of the cap (uniform in solid angle) within alpha of c_dir.
  auto covered_fraction = [&](const dvec3& centre_dir, double ang_radius) {
    dvec3 b1, b2;
    atmo::monte_carlo::basis(sun, b1, b2);
    const int nt = 1500, np = 1500;
    double covered = 0, total = 0;
    for (int i = 0; i < nt; ++i) {
      const double t = (i + 0.5) / nt * r_sun, w = std::sin(t);
      for (int j = 0; j < np; ++j) {
        const double p = (j + 0.5) / np * 2 * kPi;
        const dvec3 dir = std::cos(t) * sun + std::sin(t) * (std::cos(p) * b1 + std::sin(p) * b2);
        total += w;
        if (glm::dot(dir, centre_dir) > std::cos(ang_radius)) covered += w;
      }
    }
    return covered / total;
  };
  const double v_half = sr::sun_visibility(half, f.origin, 16384);
  const double want_half = 1 - covered_fraction(c_dir, alpha);
  std::printf("[ measured ] sun half behind a limb: %.6f (angle-test quadrature %.6f, err %.2e)\n", v_half, want_half,
              std::abs(v_half - want_half));
  EXPECT_NEAR(v_half, 0.5, 0.01);
  EXPECT_NEAR(v_half, want_half, 1e-3);

  // A small sphere (angular radius 1.3 r_sun) whose centre is 1.5 r_sun from the Sun's: the lens area of two
  // circles (planar; the disc is 0.0047 rad, so curvature errors are ~1e-5).
  const double a2 = 1.3 * r_sun, off = 1.5 * r_sun, far = 1000.0;
  const dvec3 c2 = std::cos(off) * sun + std::sin(off) * perp;
  sr::Scene lens = scene;
  lens.spheres.push_back({f.origin + far * c2, far * std::sin(a2), 0});
  const double r1 = r_sun, r2 = a2, dd = off;
  const double area = r1 * r1 * std::acos((dd * dd + r1 * r1 - r2 * r2) / (2 * dd * r1)) +
                      r2 * r2 * std::acos((dd * dd + r2 * r2 - r1 * r1) / (2 * dd * r2)) -
                      0.5 * std::sqrt((-dd + r1 + r2) * (dd + r1 - r2) * (dd - r1 + r2) * (dd + r1 + r2));
  const double want_lens = 1 - area / (kPi * r1 * r1);
  for (long n : {4096L, 65536L}) {
    const double v = sr::sun_visibility(lens, f.origin, n);
    std::printf("[ measured ] sun partly behind a small sphere, %ld samples: %.6f (lens area %.6f, err %.2e)\n", n, v,
                want_lens, std::abs(v - want_lens));
    EXPECT_NEAR(v, want_lens, n < 10000 ? 3e-3 : 1e-3);
  }

  // The ground: a Sun below the horizon is hidden, one above is not; a Sun whose centre is on the horizon is half.
  sr::Scene ground;
  ground.ground = true;
  ground.ground_height_m = -2.0;
  const dvec3 p(1.0, 2.0, 0.0);
  ground.sun_direction = dvec3(0.6, 0.0, -0.8);
  EXPECT_EQ(sr::sun_visibility(ground, p), 0.0);
  ground.sun_direction = dvec3(0.6, 0.0, 0.8);
  EXPECT_EQ(sr::sun_visibility(ground, p), 1.0);
  ground.sun_direction = dvec3(1.0, 0.0, 0.0);
  const double on_ground = sr::sun_visibility(ground, dvec3(0.0, 0.0, -2.0), 16384);
  std::printf("[ measured ] sun centred on the horizon, receiver on the ground: %.6f\n", on_ground);
  EXPECT_NEAR(on_ground, 0.5, 0.01);
}

// 6. One bounce. A uniform sky L over the whole sphere lights every point of a sphere with E_hit = pi L, so
//    its radiance is a L and a receiver facing it (angular radius theta) gets a L pi sin^2 theta. A single
//    convex sphere never shadows itself: traced == unshadowed_hit. With the ground, traced < unshadowed.
TEST(ShadowReference, BounceUniformSky) {
  const Frame f;
  const dvec3 albedo(0.3, 0.5, 0.7);
  for (double theta_deg : {10.0, 30.0, 60.0}) {
    sr::Scene scene = uniform_sky_scene();
    scene.object_albedo = {dvec3(0.0), albedo};
    const double d = 12.0, s = std::sin(deg(theta_deg));
    scene.spheres.push_back({f.origin + d * f.ex, d * s, 1});
    const dvec3 want = albedo * kSkyL * kPi * s * s;
    const sr::Estimate un = sr::bounce_irradiance(scene, f.origin, f.ex, sr::BounceMode::unshadowed_hit, 400000, 4, 9);
    char what[64];
    std::snprintf(what, sizeof what, "bounce off a sphere, theta %.0f deg", theta_deg);
    expect_close(what, un, want, kPi * kSkyL, 1e-3);
    const sr::Estimate tr = sr::bounce_irradiance(scene, f.origin, f.ex, sr::BounceMode::traced, 400000, 4, 9);
    std::printf("[ measured ] %-44s traced - unshadowed %.3e\n", what, max_abs(tr.value - un.value));
    EXPECT_LT(max_abs(tr.value - un.value), 1e-12 * max_abs(un.value));
  }
  // The same sphere resting over the ground, with the Sun: the ground hides the sphere's underside from the sky
  // and the sphere shades the ground.
  sr::Scene scene = uniform_sky_scene();
  scene.object_albedo = {albedo};
  scene.ground = true;
  scene.ground_height_m = 0.0;
  scene.sun_direction = glm::normalize(dvec3(0.3, 0.2, 0.9));
  scene.sun_illuminance = dvec3(50000.0);
  scene.spheres.push_back({dvec3(5.0, 0.0, 3.0), 2.5, 0});
  const dvec3 p(0.0, 0.0, 1.0), n = glm::normalize(dvec3(1.0, 0.0, -0.3));
  const sr::Estimate un = sr::bounce_irradiance(scene, p, n, sr::BounceMode::unshadowed_hit, 20000, 64, 4);
  const sr::Estimate tr = sr::bounce_irradiance(scene, p, n, sr::BounceMode::traced, 20000, 64, 4);
  std::printf("[ measured ] sphere over the ground, sun: unshadowed %.1f (SE %.2f), traced %.1f (SE %.2f) lux (red)\n",
              un.value.x, un.standard_error.x, tr.value.x, tr.standard_error.x);
  for (int c = 0; c < 3; ++c) {
    EXPECT_LT(tr.value[c], un.value[c]);
    EXPECT_GT(tr.value[c], 0.0);
  }
}

// 6b. Sun light only: a Lambertian sphere lit by the Sun (E_hit = E_s max(0, m.s)) seen by a receiver facing it,
//     against an independent quadrature over the sphere's visible surface (E = integral of L cos_p cos_x / d^2 dA).
//     And the ground alone under a receiver facing down: E_b = a_g (pi L + E_s cos zenith), either mode.
TEST(ShadowReference, BounceSunLitSphereAndGround) {
  const Frame f;
  const dvec3 albedo(0.5, 0.4, 0.3);
  const double e_sun = 1000.0, d = 10.0, radius = 5.0;
  sr::Scene scene;
  scene.object_albedo = {albedo};
  scene.sun_illuminance = dvec3(e_sun);
  const dvec3 c_dir = f.ex;
  scene.sun_direction = std::cos(deg(110.0)) * c_dir + std::sin(deg(110.0)) * f.ey;  // lights the far side mostly
  const dvec3 centre = f.origin + d * c_dir;
  scene.spheres.push_back({centre, radius, 0});

  // Quadrature over the sphere's cap visible from p: polar angle t about the axis towards p, cos t > R / d.
  const dvec3 axis = -c_dir, s = scene.sun_direction;
  dvec3 b1, b2;
  atmo::monte_carlo::basis(axis, b1, b2);
  const double t_max = std::acos(radius / d);
  const int nt = 1200, np = 2400;
  double sum = 0;
  for (int i = 0; i < nt; ++i) {
    const double t = (i + 0.5) / nt * t_max;
    for (int j = 0; j < np; ++j) {
      const double ph = (j + 0.5) / np * 2 * kPi;
      const dvec3 m = std::cos(t) * axis + std::sin(t) * (std::cos(ph) * b1 + std::sin(ph) * b2);
      const dvec3 x = centre + radius * m;
      const dvec3 v = f.origin - x;  // hit point to receiver
      const double dist2 = glm::dot(v, v), dist = std::sqrt(dist2);
      const double radiance = e_sun / kPi * std::max(0.0, glm::dot(m, s));  // per unit albedo
      sum += radiance * glm::dot(c_dir, -v / dist) * glm::dot(m, v / dist) / dist2 * radius * radius * std::sin(t);
    }
  }
  const double want = sum * (t_max / nt) * (2 * kPi / np);
  for (sr::BounceMode mode : {sr::BounceMode::unshadowed_hit, sr::BounceMode::traced}) {
    const sr::Estimate e = sr::bounce_irradiance(scene, f.origin, c_dir, mode, 100000, 4, 21);
    expect_close(mode == sr::BounceMode::traced ? "sun-lit sphere, traced (quadrature)" : "sun-lit sphere, unshadowed (quadrature)",
                 e, albedo * want, albedo * want, 1e-2);
  }

  sr::Scene ground = uniform_sky_scene();
  ground.ground = true;
  ground.ground_height_m = 1.5;
  ground.ground_albedo = dvec3(0.2, 0.25, 0.3);
  ground.sun_illuminance = dvec3(e_sun);
  ground.sun_direction = glm::normalize(dvec3(0.5, 0.2, 0.7));
  const dvec3 want_g = ground.ground_albedo * (kPi * kSkyL + e_sun * ground.sun_direction.z);
  for (sr::BounceMode mode : {sr::BounceMode::unshadowed_hit, sr::BounceMode::traced}) {
    const sr::Estimate e = sr::bounce_irradiance(ground, dvec3(3.0, -2.0, 4.0), dvec3(0, 0, -1), mode, 10000, 16, 2);
    expect_close(mode == sr::BounceMode::traced ? "ground below, traced" : "ground below, unshadowed", e, want_g,
                 want_g, 1e-3);
  }
}

// 7a. A thin box overhead (a mesh, placed by a rotation about z and a translation): the receiver sees only its
//     bottom face, a 2a x 2b rectangle at height h: blocked = pi L F, F four corner form factors. Also the same
//     box mirrored (negative determinant), and an unprepared scene (a BVH built per call) giving the same numbers.
TEST(ShadowReference, MeshPlateOverhead) {
  const double a = 3.0, b = 1.5, h = 2.0, thick = 0.2;
  // Object frame: the box is 2b x 2a (x, y) — a quarter turn about z brings it to 2a x 2b in the world.
  const TriangleMesh box = box_mesh(dvec3(-b, -a, 0.0), dvec3(b, a, thick));
  const dvec3 p(10.0, -4.0, 1.0);
  sr::Scene scene = uniform_sky_scene();
  scene.object_albedo = {dvec3(0.5)};
  scene.meshes.push_back({&box, translate(p + dvec3(0, 0, h)) * rotate_z(deg(90.0)), 0});
  scene.prepare();
  const double F = 4 * corner_form_factor(a, b, h);
  const dvec3 want = kPi * kSkyL * (1 - F);
  const sr::Estimate e = sr::sky_irradiance(scene, p, dvec3(0, 0, 1), true, 200000, 13);
  char what[80];
  std::snprintf(what, sizeof what, "box plate overhead (F = %.4f)", F);
  expect_close(what, e, want, kPi * kSkyL, 1e-3);

  sr::Scene unprepared = scene;
  unprepared.mesh_bvh.reset();
  const sr::Estimate e2 = sr::sky_irradiance(unprepared, p, dvec3(0, 0, 1), true, 200000, 13);
  EXPECT_EQ(e.value, e2.value);
  EXPECT_THROW(sr::intersect(unprepared, p, dvec3(0, 0, 1), nullptr), std::logic_error);

  sr::Scene mirrored = scene;
  mirrored.meshes[0].world_from_object = translate(p + dvec3(0, 0, h)) * rotate_z(deg(90.0)) * scale(dvec3(-1, 1, 1));
  mirrored.prepare();
  sr::Hit hit;
  ASSERT_TRUE(sr::intersect(mirrored, p, dvec3(0, 0, 1), &hit));
  EXPECT_NEAR(hit.distance_m, h, 1e-12);
  EXPECT_FALSE(hit.from_inside);
  EXPECT_NEAR(hit.normal.z, -1.0, 1e-12);
  const sr::Estimate e3 = sr::sky_irradiance(mirrored, p, dvec3(0, 0, 1), true, 200000, 13);
  expect_close("box plate overhead, mirrored transform", e3, want, kPi * kSkyL, 1e-3);

  // A box enclosing the receiver: everything blocked, from inside.
  const TriangleMesh room = box_mesh(dvec3(-1.0), dvec3(1.0));
  sr::Scene inside = uniform_sky_scene();
  inside.meshes.push_back({&room, translate(p), 0});
  inside.prepare();
  ASSERT_TRUE(sr::intersect(inside, p, dvec3(0.3, 0.1, 0.2), &hit));
  EXPECT_TRUE(hit.from_inside);
  EXPECT_EQ(sr::sky_irradiance(inside, p, dvec3(0, 0, 1), true, 1000).value, dvec3(0.0));
}

// 7b. The BVH against a brute-force loop over the world-space triangles, on random rays (origins inside and
//     outside), for a subdivided octahedron under a general transform and a box; and the meshed sphere's sky
//     shadow against the analytic sphere's (the inscribed polyhedron blocks slightly less).
TEST(ShadowReference, MeshBvhMatchesBruteForce) {
  const Frame f;
  const TriangleMesh ball = octasphere_mesh(4);  // 2048 triangles
  const TriangleMesh box = box_mesh(dvec3(-0.5, -0.5, 0.0), dvec3(0.5, 0.5, 1.0));
  sr::Scene scene;
  scene.meshes.push_back({&ball, translate(dvec3(0.5, 0.2, 0.1)) * rotate_frame(f) * scale(dvec3(1.5, 1.0, 0.7)), 3});
  scene.meshes.push_back({&box, translate(dvec3(-1.5, 0.5, -0.5)) * rotate_z(0.4), 5});
  scene.prepare();

  struct WorldTri {
    dvec3 a, b, c;
    int object;
  };
  std::vector<WorldTri> tris;
  for (const sr::MeshOccluder& m : scene.meshes)
    for (const glm::uvec3& t : m.mesh->triangles) {
      auto w = [&](unsigned i) { return dvec3(m.world_from_object * glm::dvec4(m.mesh->vertices[i], 1.0)); };
      tris.push_back({w(t.x), w(t.y), w(t.z), m.object});
    }
  atmo::monte_carlo::Xoshiro256 rng(42);
  int rays = 0, hits = 0, inside_hits = 0, mismatches = 0;
  double worst_dist = 0, worst_normal = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (; rays < 20000; ++rays) {
    // Origins in a 6 m cube about the meshes; every other ray aimed at a point among them (more hits).
    const dvec3 o(6 * rng.uniform() - 3, 6 * rng.uniform() - 3, 6 * rng.uniform() - 3);
    const double z = 2 * rng.uniform() - 1, phi = 2 * kPi * rng.uniform(), sxy = std::sqrt(1 - z * z);
    const dvec3 aim(3 * rng.uniform() - 1.5, 3 * rng.uniform() - 1.5, 3 * rng.uniform() - 1.5);
    const dvec3 d = rays % 2 || aim == o ? dvec3(sxy * std::cos(phi), sxy * std::sin(phi), z) : glm::normalize(aim - o);
    // Brute force: every triangle, Moller-Trumbore written out independently.
    double best = std::numeric_limits<double>::infinity();
    const WorldTri* best_tri = nullptr;
    for (const WorldTri& t : tris) {
      const dvec3 e1 = t.b - t.a, e2 = t.c - t.a, pv = glm::cross(d, e2);
      const double det = glm::dot(e1, pv);
      if (det == 0) continue;
      const dvec3 tv = o - t.a;
      const double u = glm::dot(tv, pv) / det;
      if (u < 0 || u > 1) continue;
      const dvec3 qv = glm::cross(tv, e1);
      const double v = glm::dot(d, qv) / det;
      if (v < 0 || u + v > 1) continue;
      const double dist = glm::dot(e2, qv) / det;
      if (dist > 0 && dist < best) {
        best = dist;
        best_tri = &t;
      }
    }
    sr::Hit hit;
    const bool got = sr::intersect(scene, o, d, &hit);
    if (got != (best_tri != nullptr)) {
      ++mismatches;
      continue;
    }
    if (!got) continue;
    ++hits;
    if (hit.from_inside) ++inside_hits;
    worst_dist = std::max(worst_dist, std::abs(hit.distance_m - best) / best);
    const dvec3 nrm = glm::normalize(glm::cross(best_tri->b - best_tri->a, best_tri->c - best_tri->a));
    worst_normal = std::max(worst_normal, 1 - glm::dot(nrm, hit.normal));
    if (hit.object != best_tri->object) ++mismatches;
  }
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  std::printf("[ measured ] BVH vs brute force: %d rays, %d hits (%d from inside), %d mismatches, worst relative "
              "distance %.2e, worst 1 - n.n' %.2e (%.0f ms with the brute force)\n",
              rays, hits, inside_hits, mismatches, worst_dist, worst_normal, ms);
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(hits, rays / 4);
  EXPECT_GT(inside_hits, 0);
  EXPECT_LT(worst_dist, 1e-12);
  EXPECT_LT(worst_normal, 1e-12);

  // The meshed unit sphere (level 5: 8192 triangles) against the analytic sphere, 30 degrees overhead.
  const TriangleMesh fine_ball = octasphere_mesh(5);
  const double d = 4.0, rr = d * std::sin(deg(30.0));
  sr::Scene meshed = uniform_sky_scene(), analytic = uniform_sky_scene();
  meshed.meshes.push_back({&fine_ball, translate(f.origin + d * f.ez) * scale(dvec3(rr)), 0});
  meshed.prepare();
  analytic.spheres.push_back({f.origin + d * f.ez, rr, 0});
  const sr::Estimate em = sr::sky_irradiance(meshed, f.origin, f.ez, true, 100000, 17);
  const sr::Estimate ea = sr::sky_irradiance(analytic, f.origin, f.ez, true, 100000, 17);
  const double blocked_m = kPi * kSkyL.x - em.value.x, blocked_a = kPi * kSkyL.x - ea.value.x;
  std::printf("[ measured ] meshed sphere (8192 triangles) blocks %.5f, analytic %.5f (ratio %.5f)\n", blocked_m,
              blocked_a, blocked_m / blocked_a);
  EXPECT_LT(blocked_m, blocked_a);
  EXPECT_GT(blocked_m / blocked_a, 0.99);
}

// 8. Degenerate inputs: no NaN, no crash, and the right limits.
TEST(ShadowReference, DegenerateInputs) {
  const Frame f;
  const dvec3 full = kPi * kSkyL;
  {  // zero, negative and NaN radii: nothing there
    sr::Scene scene = uniform_sky_scene();
    scene.object_albedo = {dvec3(0.5)};
    for (double r : {0.0, -1.0, std::nan("")}) scene.spheres.push_back({f.origin + 2.0 * f.ez, r, 0});
    scene.spheres.push_back({f.origin, 0.0, 0});  // a zero-radius sphere at the receiver itself
    const sr::Estimate e = sr::sky_irradiance(scene, f.origin, f.ez, true, 1000);
    std::printf("[ measured ] zero/negative/NaN radius: |E / (pi L) - 1| = %.2e\n", worst_rel(e.value, full, full));
    EXPECT_LT(worst_rel(e.value, full, full), 1e-14);
    EXPECT_EQ(sr::sun_visibility(scene, f.origin), 1.0);
    EXPECT_EQ(sr::bounce_irradiance(scene, f.origin, f.ez, sr::BounceMode::traced, 100, 4).value, dvec3(0.0));
  }
  {  // inside a sphere: everything blocked, the Sun hidden, no bounce (the inside of a solid is dark)
    sr::Scene scene = uniform_sky_scene();
    scene.object_albedo = {dvec3(0.5)};
    scene.sun_illuminance = dvec3(1000.0);
    scene.spheres.push_back({f.origin + 0.3 * f.ex, 1.0, 0});
    for (const dvec3& n : {f.ez, f.ex, -f.ex}) {
      EXPECT_EQ(sr::sky_irradiance(scene, f.origin, n, true, 1000).value, dvec3(0.0));
      EXPECT_EQ(sr::bounce_irradiance(scene, f.origin, n, sr::BounceMode::unshadowed_hit, 1000, 4).value, dvec3(0.0));
    }
    EXPECT_EQ(sr::sun_visibility(scene, f.origin), 0.0);
    EXPECT_LT(worst_rel(sr::sky_irradiance(scene, f.origin, f.ez, false, 1000).value, full, full), 1e-14);  // unoccluded ignores it
    // At the centre exactly as well.
    EXPECT_EQ(sr::sky_irradiance(scene, f.origin + 0.3 * f.ex, f.ez, true, 1000).value, dvec3(0.0));
  }
  {  // on a sphere's surface, n outward: nothing blocks (no self-hits), for R = 1 m and R = 1e7 m
    for (double radius : {1.0, 1e7}) {
      sr::Scene scene = uniform_sky_scene();
      const dvec3 centre = f.origin - 3.0 * f.ey;
      scene.spheres.push_back({centre, radius, 0});
      atmo::monte_carlo::Xoshiro256 rng(5);
      double worst = 0;
      for (int k = 0; k < 20; ++k) {
        const double z = 2 * rng.uniform() - 1, phi = 2 * kPi * rng.uniform(), sxy = std::sqrt(1 - z * z);
        const dvec3 m(sxy * std::cos(phi), sxy * std::sin(phi), z);
        const sr::Estimate e = sr::sky_irradiance(scene, centre + radius * m, m, true, 1000, k + 1);
        worst = std::max(worst, worst_rel(e.value, full, full));
      }
      std::printf("[ measured ] receiver on a sphere of radius %.0e m, n outward: worst |E / (pi L) - 1| %.2e\n",
                  radius, worst);
      EXPECT_LT(worst, 1e-14);  // nothing blocked: only the sum's rounding
    }
  }
  {  // grazing normals: on the ground (n horizontal) half the cosine lobe meets the ground: E = pi L / 2; the
     // same on top of a sphere (its tangent plane); along the normal of a receiver exactly on the surface.
    sr::Scene scene = uniform_sky_scene();
    scene.ground = true;
    scene.ground_height_m = -1.0;
    const sr::Estimate e = sr::sky_irradiance(scene, dvec3(2.0, 3.0, -1.0), glm::normalize(dvec3(1, 1, 0)), true, 100000);
    expect_close("grazing normal on the ground", e, full / 2.0, full, 1e-3);
    sr::Scene ball = uniform_sky_scene();
    ball.spheres.push_back({f.origin, 2.0, 0});
    const sr::Estimate eb = sr::sky_irradiance(ball, f.origin + 2.0 * f.ez, f.ex, true, 100000);
    expect_close("grazing normal on top of a sphere", eb, full / 2.0, full, 1e-3);
    EXPECT_TRUE(finite(sr::bounce_irradiance(scene, dvec3(2.0, 3.0, -1.0), dvec3(1, 0, 0), sr::BounceMode::traced, 1000, 4).value));
  }
  {  // a 1e7 m sphere as the Earth, the receiver 1 m above it: n up sees the whole sky; n tilted by tau loses
     // the part of the lobe below the horizon, (1 - cos tau) / 2 (a plane; the horizon's 4.5e-4 rad dip is
     // below the tolerance). Sun visibility and the bounce stay finite.
    const double R = 1e7;
    sr::Scene scene = uniform_sky_scene();
    scene.object_albedo = {dvec3(0.3)};
    scene.sun_illuminance = dvec3(1e5);
    scene.sun_direction = glm::normalize(dvec3(0.0, 1.0, 1.0));
    scene.spheres.push_back({dvec3(0.0, 0.0, -R), R, 0});
    const dvec3 p(0.0, 0.0, 1.0);
    const sr::Estimate up = sr::sky_irradiance(scene, p, dvec3(0, 0, 1), true, 10000);
    EXPECT_LT(worst_rel(up.value, full, full), 1e-14);  // nothing blocked: only the sum's rounding
    const double tau = deg(40.0);
    const sr::Estimate tilted = sr::sky_irradiance(scene, p, dvec3(std::sin(tau), 0, std::cos(tau)), true, 100000);
    expect_close("1e7 m sphere below, n tilted 40 deg", tilted, full * (1 + std::cos(tau)) / 2.0, full, 1e-3);
    EXPECT_EQ(sr::sun_visibility(scene, p), 1.0);
    EXPECT_EQ(sr::sun_visibility(scene, dvec3(0.0, 0.0, 0.0)), 1.0);  // on the surface itself
    const sr::Estimate b = sr::bounce_irradiance(scene, p, dvec3(0, 0, -1), sr::BounceMode::traced, 10000, 4);
    // Facing down over a (nearly) flat ground of albedo 0.3: 0.3 (pi L + E_s cos 45 deg).
    const dvec3 want_b = dvec3(0.3) * (full + 1e5 * std::sqrt(0.5));
    expect_close("1e7 m sphere below, bounce facing down", b, want_b, want_b, 1e-3);
  }
}

// Determinism: the same seed gives the same numbers whatever the thread count; another seed differs;
// bad arguments throw.
TEST(ShadowReference, DeterministicAndValidated) {
  const Frame f;
  sr::Scene scene = uniform_sky_scene();
  scene.object_albedo = {dvec3(0.4)};
  scene.sun_illuminance = dvec3(1000.0);
  scene.spheres.push_back({f.origin + 3.0 * f.ez, 1.5, 0});
  scene.ground = true;
  scene.ground_height_m = f.origin.z - 1.0;
  scene.threads = 1;
  const sr::Estimate a = sr::sky_irradiance(scene, f.origin, f.ez, true, 5000, 3);
  const sr::Estimate ba = sr::bounce_irradiance(scene, f.origin, f.ez, sr::BounceMode::traced, 2000, 16, 3);
  scene.threads = 3;
  const sr::Estimate b = sr::sky_irradiance(scene, f.origin, f.ez, true, 5000, 3);
  const sr::Estimate bb = sr::bounce_irradiance(scene, f.origin, f.ez, sr::BounceMode::traced, 2000, 16, 3);
  EXPECT_EQ(a.value, b.value);
  EXPECT_EQ(a.standard_error, b.standard_error);
  EXPECT_EQ(ba.value, bb.value);
  EXPECT_EQ(ba.standard_error, bb.standard_error);
  EXPECT_NE(sr::sky_irradiance(scene, f.origin, f.ez, true, 5000, 4).value, a.value);

  EXPECT_THROW(sr::sky_irradiance(scene, f.origin, dvec3(0.0), true, 100), std::invalid_argument);
  EXPECT_THROW(sr::sky_irradiance(scene, f.origin, f.ez, true, 1), std::invalid_argument);
  EXPECT_THROW(sr::bounce_irradiance(scene, f.origin, f.ez, sr::BounceMode::traced, 100, 0), std::invalid_argument);
  scene.spheres[0].object = 2;  // no albedo for object 2
  EXPECT_THROW(sr::bounce_irradiance(scene, f.origin, f.ez, sr::BounceMode::traced, 100, 4), std::invalid_argument);
  scene.sky_radiance = [](const dvec3&) -> dvec3 { throw std::runtime_error("sky failed"); };
  EXPECT_THROW(sr::sky_irradiance(scene, f.origin, f.ez, false, 1000), std::runtime_error);  // from a worker thread
}
