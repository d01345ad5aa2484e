// The host include atmo_sky_occlusion.glsl through its C++ twin: against the
// double-precision study (core/shadows/sphere_occlusion) at order 4, its
// generated squaring against the triple product, the object hierarchy's
// blend, and the inputs where it is known to fail (inside a sphere,
// touching, zero and huge radii, grazing normals, no spheres).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>

#include <glm/gtc/matrix_transform.hpp>
#include <sstream>

#include "core/shadows/occlusion_frame.h"
#include "core/shadows/occlusion_twin.h"
#include "core/shadows/sphere_occlusion.h"

namespace atmo::shadows {
namespace {

// A clear-ish sky: brighter towards the zenith and the Sun's side, a dim ground below (cd/m^2).
std::vector<glm::dvec3> test_sky_sh16() {
  const int nz = 200, nphi = 400;
  std::vector<glm::dvec3> sh(16, glm::dvec3(0.0));
  for (int a = 0; a < nz; ++a) {
    const double z = 1.0 - 2.0 * (a + 0.5) / nz;
    for (int b = 0; b < nphi; ++b) {
      const double phi = 2.0 * M_PI * (b + 0.5) / nphi, s = std::sqrt(1.0 - z * z);
      const glm::dvec3 d(s * std::cos(phi), s * std::sin(phi), z);
      const glm::dvec3 l = z > 0.0 ? glm::dvec3(2000.0, 2600.0, 3800.0) * (0.6 + 0.4 * z + 0.3 * std::max(0.0, d.x))
                                   : glm::dvec3(900.0, 850.0, 800.0);
      const ShVector y = sh_basis(4, d);
      for (int i = 0; i < 16; ++i) sh[i] += l * (y[i] * 4.0 * M_PI / (nz * nphi));
    }
  }
  return sh;
}

// A frame whose one camera (at the ENU origin, looking north, world = ENU) lists every object in every tile.
OcclusionFrame frame_of(const std::vector<OccluderObject>& objects, const OcclusionLimits& limits) {
  std::vector<const OccluderObject*> ptrs;
  std::vector<glm::dmat4> poses;
  for (const OccluderObject& o : objects) {
    ptrs.push_back(&o);
    poses.push_back(glm::dmat4(1.0));
  }
  const glm::dmat4 view = glm::lookAt(glm::dvec3(0.0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1));  // north
  const glm::dmat4 proj = glm::perspective(1.5, 16.0 / 9.0, 0.1, 1e5);
  std::vector<glm::dvec3> sky = test_sky_sh16();
  return make_occlusion_frame(ptrs, poses, proj * view, glm::dmat3(1.0), 640, 360,
                              make_sky_transfer(sky, glm::normalize(glm::dvec3(0.5, 0.3, 0.8)), glm::dvec3(8e4)),
                              glm::normalize(glm::dvec3(0.5, 0.3, 0.8)), glm::dvec3(8e4), limits);
}

TEST(SkyOcclusionInclude, SquaringIsTheTripleProductsGeneratedCode) {
  std::ifstream in(ATMO_HOST_SDK_INCLUDE "/atmo/atmo_sky_occlusion.glsl");
  ASSERT_TRUE(in.good());
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  const std::string head = "ATMO_OCC_FN AtmoOccSh atmo_occ_square(AtmoOccSh g) {\n";
  const size_t at = text.find(head);
  ASSERT_NE(at, std::string::npos);
  const size_t end = text.find("}\n", at + head.size());
  EXPECT_EQ(text.substr(at + head.size(), end - at - head.size()), sh_square_glsl(include_triple_product()))
      << "regenerate the body from core/shadows sh_square_glsl";
  // And it squares: against the sparse product in double.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  ShVector g(16);
  for (double& c : g) c = u(rng);
  const ShVector sq = include_triple_product().product(g, g);
  twin::AtmoOccSh t;
  t.a = glm::vec4(g[0], g[1], g[2], g[3]);
  t.b = glm::vec4(g[4], g[5], g[6], g[7]);
  t.c = glm::vec4(g[8], g[9], g[10], g[11]);
  t.d = glm::vec4(g[12], g[13], g[14], g[15]);
  const twin::AtmoOccSh r = twin::atmo_occ_square(t);
  const float got[16] = {r.a.x, r.a.y, r.a.z, r.a.w, r.b.x, r.b.y, r.b.z, r.b.w,
                         r.c.x, r.c.y, r.c.z, r.c.w, r.d.x, r.d.y, r.d.z, r.d.w};
  for (int i = 0; i < 16; ++i) EXPECT_NEAR(got[i], sq[i], 1e-5);
}

// The bounce's form factor: the distribution of the surface normals of the part of a sphere that p sees,
// weighted by the solid angle each patch subtends, against Monte Carlo over the cap's directions (each
// direction a ray to the sphere, its hit normal's zonal harmonics averaged).
TEST(SkyOcclusionInclude, FormFactorIsTheSeenNormalsDistribution) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (double deg : {5.0, 30.0, 60.0}) {
    const double theta = deg * M_PI / 180.0, s = std::sin(theta);
    const std::vector<double> zh = form_factor_zh(4, theta);
    // p at the origin, the sphere of radius s at distance 1 along +z; directions uniform in the cap's solid angle.
    double mc[4] = {0, 0, 0, 0};
    const int n = 200000;
    for (int k = 0; k < n; ++k) {
      const double cz = 1.0 - u(rng) * (1.0 - std::cos(theta)), phi = 2.0 * M_PI * u(rng);
      const glm::dvec3 d(std::sqrt(1.0 - cz * cz) * std::cos(phi), std::sqrt(1.0 - cz * cz) * std::sin(phi), cz);
      const double b = glm::dot(d, glm::dvec3(0, 0, 1)), disc = b * b - (1.0 - s * s);
      const double t = b - std::sqrt(std::max(disc, 0.0));
      const glm::dvec3 normal = (d * t - glm::dvec3(0, 0, 1)) / s;
      // The normal's angle from the axis towards p (-z).
      const ShVector y = sh_basis(4, {normal.x, normal.y, -normal.z});
      for (int l = 0; l < 4; ++l) mc[l] += y[l * (l + 1)] / n;
    }
    std::printf("form factor at %2.0f deg: ZH %.5f %.5f %.5f %.5f, Monte Carlo %.5f %.5f %.5f %.5f\n", deg, zh[0],
                zh[1], zh[2], zh[3], mc[0], mc[1], mc[2], mc[3]);
    for (int l = 0; l < 4; ++l) EXPECT_NEAR(zh[l], mc[l], 3e-3) << deg << " deg, band " << l;
  }
  // A point-like sphere: the clamped cosine (normalised), whose DC keeps a constant radiance constant.
  const std::vector<double> tiny = form_factor_zh(4, 1e-4), cosine = clamped_cosine_zh(4);
  for (int l = 0; l < 4; ++l) EXPECT_NEAR(tiny[l], cosine[l], 1e-3);
  EXPECT_NEAR(form_factor_zh(4, 0.7)[0], 1.0 / std::sqrt(4.0 * M_PI), 1e-9);
}

TEST(SkyOcclusionInclude, TwinMatchesTheDoubleStudyAtOrderFour) {
  const ShOrder order(4);
  const std::vector<glm::dvec3> sky = test_sky_sh16();
  OcclusionLimits limits;
  limits.bounce = false;
  limits.sin_cull = 1e-4;  // every sphere counts, sphere by sphere, as in the study (no stand-ins)
  limits.sin_far = 0.0;
  limits.sin_near = 1e-6;
  struct Case {
    const char* name;
    std::vector<glm::dvec4> spheres;
    glm::dvec3 p, n;
  };
  const std::vector<Case> cases = {
      {"one sphere at 30 deg overhead", {{0, 20, 10, 5}}, {0, 20, 0}, {0, 0, 1}},
      {"one sphere at 60 deg, tilted", {{3, 20, 6, 6.9}}, {0, 20, 0}, {0, 0, 1}},
      {"wing of 8 spheres", {{-8, 30, 4, 1.5}, {-6, 30, 4, 1.5}, {-4, 30, 4, 1.5}, {-2, 30, 4, 1.5}, {0, 30, 4, 1.5},
                             {2, 30, 4, 1.5}, {4, 30, 4, 1.5}, {6, 30, 4, 1.5}}, {1, 31, 0}, {0, 0, 1}},
      {"two intersecting", {{0, 25, 5, 3}, {2, 25, 5, 3}}, {1, 25, 0}, {0, 0, 1}},
      {"near a wall, facing it", {{0, 30, 3, 3}, {0, 30, 9, 3}, {6, 30, 3, 3}, {6, 30, 9, 3}}, {3, 24, 4}, {0, 1, 0}},
  };
  for (const Case& c : cases) {
    const std::vector<OccluderObject> objects = {make_occluder_object(c.spheres, glm::dvec3(0.5))};
    const OcclusionFrame frame = frame_of(objects, limits);
    const twin::AtmoSkyOcclusion got = twin::evaluate(frame, glm::vec3(c.p), glm::vec3(c.n));
    std::vector<glm::dvec4> rel;
    for (const glm::dvec4& s : c.spheres) rel.emplace_back(glm::dvec3(s) - c.p, s.w);
    const OccludedSky want = occluded_sky(order, rel, c.n, sky, ExpMethod::hybrid);
    const double open = want.open_lux.y;
    const double err = std::abs(got.sky_lux.y - want.sky_lux.y) / open;
    std::printf("%-30s twin %.1f lx, study %.1f lx (open %.1f): %.2f %% of open; AO %.3f vs %.3f\n", c.name,
                got.sky_lux.y, want.sky_lux.y, open, 100.0 * err, got.sky_visibility, want.sky_visibility);
    EXPECT_LT(err, 0.01) << c.name;
    EXPECT_NEAR(got.sky_visibility, want.sky_visibility, 0.01) << c.name;
  }
}

TEST(SkyOcclusionInclude, FarObjectsBlendIntoTheirProxyWithoutASeam) {
  const std::vector<glm::dvec4> spheres = {{-6, 0, 4, 2}, {-2, 0, 4, 2}, {2, 0, 4, 2}, {6, 0, 4, 2}, {0, 0, 7, 2.5}};
  const std::vector<OccluderObject> objects = {make_occluder_object(spheres, glm::dvec3(0.5))};
  const OcclusionFrame frame = frame_of(objects, OcclusionLimits{});
  // Walk away from the object: the answer changes smoothly (no step larger than the walk's slope allows).
  double last = -1.0, worst_step = 0.0;
  for (double d = 5.0; d < 400.0; d *= 1.02) {
    const double v = twin::evaluate(frame, glm::vec3(0, d, 0), glm::vec3(0, 0, 1)).sky_visibility;
    if (last >= 0.0) worst_step = std::max(worst_step, std::abs(v - last));
    last = v;
  }
  std::printf("walking away 5..400 m: largest step in sky visibility per 2 %% of distance %.4f\n", worst_step);
  EXPECT_LT(worst_step, 0.02);
  EXPECT_GT(last, 0.99);
}

TEST(SkyOcclusionInclude, DegenerateInputsStayFiniteAndBounded) {
  std::vector<glm::dvec4> spheres = {{0, 10, 0, 2},  {0, 12, 1, 0.0},  {3, 10, 0, 1e7 * 0 + 1.0}, {-3, 10, 2, 1.0},
                                     {0, 10, 3, 1e-9}, {50, 50, 50, 1e7}};
  const std::vector<OccluderObject> objects = {make_occluder_object(spheres, glm::dvec3(0.8)),
                                               make_occluder_object({}, glm::dvec3(0.5))};
  const OcclusionFrame frame = frame_of(objects, OcclusionLimits{});
  const glm::vec3 receivers[] = {{0, 10, 0}, {0, 10, 2}, {0, 10, -2}, {3, 10, 1}, {0, 1e6, 0}, {1e-7f, 10, 0}};
  const glm::vec3 normals[] = {{0, 0, 1}, {1, 0, 0}, {0, 0, -1}, glm::normalize(glm::vec3(1, 0, 1e-7f)), {0, 1, 0}};
  for (const glm::vec3& p : receivers)
    for (const glm::vec3& n : normals) {
      const twin::AtmoSkyOcclusion o = twin::evaluate(frame, p, n);
      const twin::AtmoSkyOcclusion open = twin::evaluate(frame_of({}, OcclusionLimits{}), p, n);
      SCOPED_TRACE(::testing::Message() << "receiver " << p.x << " " << p.y << " " << p.z << " normal " << n.x << " "
                                        << n.y << " " << n.z);
      for (int c = 0; c < 3; ++c) {
        EXPECT_TRUE(std::isfinite(o.sky_lux[c]) && std::isfinite(o.bounce_lux[c]));
        EXPECT_GE(o.sky_lux[c], 0.0f);
        EXPECT_LE(o.sky_lux[c], open.sky_lux[c] * 1.0001f + 1e-3f);
        EXPECT_GE(o.bounce_lux[c], 0.0f);
      }
      EXPECT_TRUE(o.sun_visibility >= 0.0f && o.sun_visibility <= 1.0f);
      EXPECT_TRUE(o.sky_visibility >= 0.0f && o.sky_visibility <= 1.0f);
    }
  // No objects: exactly the open sky, the Sun seen, no bounce.
  const twin::AtmoSkyOcclusion none = twin::evaluate(frame_of({}, OcclusionLimits{}), {0, 10, 0}, {0, 0, 1});
  EXPECT_EQ(none.sun_visibility, 1.0f);
  EXPECT_EQ(none.bounce_lux, glm::vec3(0.0f));
  EXPECT_GT(none.sky_lux.y, 0.0f);
}

}  // namespace
}  // namespace atmo::shadows
