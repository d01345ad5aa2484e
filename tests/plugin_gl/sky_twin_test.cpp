// The sky and aerial-perspective passes on the GPU (llvmpipe) against the CPU
// twin: the same shaders/atmosphere/functions.glsl compiled as C++, fed the
// same inputs through the pure core. Agreement shows the GL layer passes the
// right numbers; it says nothing about the physics (that is the reference
// integrator's job).
#include "core/scene/scene.h"
#include "core/sky/sky_view_table.h"
#include "plugin_gl_fixture.h"

using namespace plugin_gl;

namespace {

struct Case {
  const char* name;
  double utc_posix_s;
  double height_m;
  double pitch_deg;
  double visibility_m;
};

double relative_difference(const glm::vec3& a, const glm::vec3& b) {
  double la = 0.2126 * a.r + 0.7152 * a.g + 0.0722 * a.b;
  double lb = 0.2126 * b.r + 0.7152 * b.g + 0.0722 * b.b;
  return std::abs(la - lb) / std::max(std::abs(lb), 1e-3);
}

}  // namespace

TEST(SkyPass, MatchesCpuTwinAcrossConditions) {
  Fixture f;
  const Case cases[] = {
      {"noon ground", 1718964000.0 /* 2024-06-21T10:00Z */, 300.0, 10.0, 40000.0},
      {"low sun hazy", 1718989800.0 /* 17:10Z */, 300.0, 2.0, 5000.0},
      {"twilight", 1718997000.0 /* 19:10Z */, 300.0, 5.0, 40000.0},
      {"30 km looking down", 1718964000.0, 30000.0, -20.0, 40000.0},
  };
  for (uint32_t method : {ATMO_SKY_METHOD_LUT, ATMO_SKY_METHOD_MARCH})
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    SCOPED_TRACE(method == ATMO_SKY_METHOD_LUT ? "LUT tier" : "march tier");
    f.fresh_context();  // the case's air in its first frame (a changed air shows once its tables are built)
    auto atm = atmo::make<AtmoAtmosphereState>(ATMO_TYPE_ATMOSPHERE_STATE);
    atm.visibility_m = c.visibility_m;
    f.context->set_atmosphere(atm);
    auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
    frame.utc_posix_s = c.utc_posix_s;
    f.context->set_frame(frame);

    glm::dmat4 view = look(270.0, c.pitch_deg);
    glm::dmat4 proj = glm::perspective(glm::radians(60.0), double(kWidth) / kHeight, 1.0, 1e5);
    AtmoViewState vs = innsbruck_view(c.height_m, 270.0, c.pitch_deg, proj);
    vs.exposure_scale = 1.0;  // output in cd/m^2
    vs.sky_method = method;
    f.view->set(vs);

    f.target->bind();
    f.target->clear(0, 0, 0, 0);
    ASSERT_EQ(f.view->render(ATMO_PASS_SKY), ATMO_SUCCESS);
    atmo::support::Image image = f.target->read_color();

    // The CPU twin, fed through the same pure core.
    atmo::core::CameraInput cam;
    cam.eye_is_geodetic = true;
    cam.eye_geodetic = {47.26, 11.35, c.height_m};
    cam.world_frame = atmo::core::WorldFrame::Enu;
    cam.world_origin = {47.26, 11.35, 0.0};
    cam.view_from_world = view;
    cam.clip_from_view = proj;
    atmo::core::EyeFrame eye;
    std::string why;
    ASSERT_TRUE(atmo::core::make_eye_frame(cam, &eye, &why)) << why;
    atmo::core::AtmosphereSettings settings;
    settings.visibility_m = c.visibility_m;
    atmo::core::Scene scene = atmo::core::make_scene(settings, c.utc_posix_s, 0.0, eye);
    auto lut = atmo::core::compute_transmittance_table(scene.atmosphere, atmo::core::kTransmittanceWidth,
                                                       atmo::core::kTransmittanceHeight);
    const glm::vec2 lut_size(lut.width, lut.height);
    auto ms = atmo::core::compute_multiple_scattering_table(scene.atmosphere, lut);
    const glm::vec2 ms_size(ms.width, ms.height);
    const float altitude = float(scene.eye_altitude_m);
    const glm::vec3 sun(scene.sun_direction_enu);
    atmo::twin::Lut2D sky_view;
    if (method == ATMO_SKY_METHOD_LUT)
      sky_view = atmo::core::compute_sky_view_table(scene.atmosphere, lut, ms, altitude, sun.z);

    double worst = 0.0;
    int compared = 0;
    for (int y = 2; y < kHeight; y += 7) {
      for (int x = 3; x < kWidth; x += 9) {
        glm::vec2 ndc((x + 0.5f) / kWidth * 2.0f - 1.0f, (y + 0.5f) / kHeight * 2.0f - 1.0f);
        glm::vec3 ray = atmo::twin::view_ray_from_ndc(glm::mat4(eye.view_from_clip), ndc, 0);
        glm::vec3 dir = glm::normalize(glm::mat3(eye.enu_from_view) * ray);
        glm::vec3 cpu = method == ATMO_SKY_METHOD_LUT
                            ? atmo::core::sky_radiance_from_table(scene.atmosphere, lut, sky_view, altitude, dir, sun)
                            : atmo::twin::sky_radiance(scene.atmosphere, lut, lut_size, ms, ms_size, altitude, dir,
                                                       sun, 32);
        const float* gpu = image.pixel(x, kHeight - 1 - y);  // image row 0 is the top
        ASSERT_TRUE(std::isfinite(gpu[0]) && std::isfinite(gpu[1]) && std::isfinite(gpu[2]));
        worst = std::max(worst, relative_difference(glm::vec3(gpu[0], gpu[1], gpu[2]), cpu));
        ++compared;
      }
    }
    std::printf("[ twin ] %-5s %-20s %d pixels, worst relative luminance difference GPU vs CPU twin: %.2e\n",
                method == ATMO_SKY_METHOD_LUT ? "LUT" : "march", c.name,
                compared, worst);
    EXPECT_LT(worst, 2e-3);
  }
}

TEST(SkyPass, NoonSkyIsBlueAndBrighterTowardsTheSun) {
  Fixture f;
  auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
  frame.utc_posix_s = 1718964000.0;
  f.context->set_frame(frame);
  const glm::dmat4 proj = glm::perspective(glm::radians(60.0), double(kWidth) / kHeight, 1.0, 1e5);
  AtmoViewState vs = innsbruck_view(300.0, 0.0, 89.0, proj);  // straight up
  f.view->set(vs);
  f.target->bind();
  f.target->clear(0, 0, 0, 0);
  ASSERT_EQ(f.view->render(ATMO_PASS_SKY), ATMO_SUCCESS);
  atmo::support::Image image = f.target->read_color();
  const float* zenith = image.pixel(kWidth / 2, kHeight / 2);
  std::printf("zenith radiance (cd/m^2): %.0f %.0f %.0f\n", zenith[0], zenith[1], zenith[2]);
  EXPECT_GT(zenith[2], zenith[1]);
  EXPECT_GT(zenith[1], zenith[0]);
  // A clear zenith sky at 60° sun elevation is a few thousand cd/m^2.
  double y = 0.2126 * zenith[0] + 0.7152 * zenith[1] + 0.0722 * zenith[2];
  EXPECT_GT(y, 1000.0);
  EXPECT_LT(y, 20000.0);
}
