// sky_accuracy — the real-time sky (through its CPU twin, which matches the GPU
// to 2e-4) and the analytic Preetham tier against the brute-force spectral
// multiple-scattering reference (tools/reference), at the views the sky issue
// names. Prints PSNR of the linear radiance image (peak = the reference's
// maximum) and the relative luminance error per direction (median, p95), and
// writes them as CSV. Sun disc excluded: the reference treats the sun as a point.
//   sky_accuracy [--visibility M] [--width W] [--height H] [--paths N] [--csv FILE]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "core/atmosphere_model.h"
#include "core/preetham.h"
#include "core/spectral/spectral_atmosphere.h"
#include "reference.h"

namespace {

using atmo::reference::Camera;

struct View {
  const char* name;
  double sun_elevation_deg, sun_azimuth_deg;
  double eye_altitude_m;
  double heading_deg, pitch_deg, vfov_deg;
};

struct Errors {
  double psnr_db, median, p95;
};

Errors compare(const std::vector<glm::dvec3>& test, const std::vector<glm::dvec3>& ref) {
  double peak = 0.0, se = 0.0;
  std::vector<double> rel;
  for (size_t i = 0; i < ref.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      peak = std::max(peak, ref[i][c]);
      se += (test[i][c] - ref[i][c]) * (test[i][c] - ref[i][c]);
    }
    double yt = 0.2126 * test[i].r + 0.7152 * test[i].g + 0.0722 * test[i].b;
    double yr = 0.2126 * ref[i].r + 0.7152 * ref[i].g + 0.0722 * ref[i].b;
    rel.push_back(std::abs(yt - yr) / std::max(yr, 1e-3));
  }
  double rmse = std::sqrt(se / (3.0 * ref.size()));
  std::sort(rel.begin(), rel.end());
  return {20.0 * std::log10(peak / std::max(rmse, 1e-30)), rel[rel.size() / 2], rel[rel.size() * 95 / 100]};
}

}  // namespace

int main(int argc, char** argv) {
  int width = 48, height = 32, paths = 8;
  std::string csv = "sky_accuracy.csv";
  double visibility_m = 40000.0;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--width")) width = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--height")) height = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--paths")) paths = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--csv")) csv = argv[i + 1];
    else if (!std::strcmp(argv[i], "--visibility")) visibility_m = std::atof(argv[i + 1]);
  }
  const View views[] = {
      {"noon", 60.0, 180.0, 300.0, 90.0, 30.0, 100.0},
      {"sun at 5 deg", 5.0, 270.0, 300.0, 240.0, 20.0, 100.0},
      {"sun at -4 deg", -4.0, 270.0, 300.0, 240.0, 20.0, 100.0},
      {"10 km", 30.0, 180.0, 10000.0, 90.0, 0.0, 100.0},
      {"30 km", 30.0, 180.0, 30000.0, 90.0, -5.0, 100.0},
  };
  const double radius_m = 6370000.0;
  auto spectral = atmo::spectral::make_spectral_atmosphere(visibility_m, 1200.0, 0.1, radius_m);
  atmo::core::AtmosphereSettings settings;
  settings.visibility_m = visibility_m;
  auto atm = atmo::core::make_atmosphere_parameters(settings, radius_m, 1.0);
  auto t = atmo::core::compute_transmittance_table(atm, 256, 64);
  auto ms = atmo::core::compute_multiple_scattering_table(atm, t);
  const double turbidity = atmo::core::preetham_turbidity_from_visibility(visibility_m);

  std::ofstream out(csv);
  out << "visibility_m,view,model,psnr_db,rel_luminance_median,rel_luminance_p95,pixels\n";
  std::printf("visibility %.0f m (Preetham turbidity %.2f); %dx%d, reference with %d paths per step\n", visibility_m,
              turbidity, width, height, paths);
  for (const View& v : views) {
    const double el = v.sun_elevation_deg * M_PI / 180.0, az = v.sun_azimuth_deg * M_PI / 180.0;
    const glm::dvec3 sun(std::sin(az) * std::cos(el), std::cos(az) * std::cos(el), std::sin(el));
    Camera cam;
    cam.enu_from_view = atmo::reference::enu_from_view(v.heading_deg, v.pitch_deg);
    cam.vertical_fov_rad = v.vfov_deg * M_PI / 180.0;
    cam.width = width;
    cam.height = height;
    atmo::reference::Settings rs;
    rs.paths_per_step = paths;
    rs.view_steps = 128;
    atmo::reference::Image ref = atmo::reference::render_image(spectral, v.eye_altitude_m, cam, sun, rs, 2);

    std::vector<glm::dvec3> ours(ref.linear_srgb.size()), preetham(ref.linear_srgb.size());
    auto coefficients = atmo::core::preetham_coefficients(turbidity, M_PI / 2.0 - el);
    const double tan_half = std::tan(0.5 * cam.vertical_fov_rad), aspect = double(width) / height;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        glm::dvec3 view((x + 0.5) / width * 2.0 - 1.0, 1.0 - (y + 0.5) / height * 2.0, -1.0);
        view.x *= tan_half * aspect;
        view.y *= tan_half;
        glm::vec3 dir(glm::normalize(cam.enu_from_view * view));
        auto r = atmo::twin::sky_radiance_parts(atm, t, glm::vec2(t.width, t.height), ms, glm::vec2(ms.width, ms.height),
                                                float(v.eye_altitude_m), dir, glm::vec3(sun), 32);
        ours[static_cast<size_t>(y) * width + x] = glm::dvec3(r.diffuse);
        preetham[static_cast<size_t>(y) * width + x] = glm::dvec3(atmo::twin::preetham_sky_rgb(coefficients, dir, glm::vec3(sun)));
      }
    Errors e = compare(ours, ref.linear_srgb);
    Errors p = compare(preetham, ref.linear_srgb);
    auto valid = atmo::core::preetham_validity(turbidity, el, v.eye_altitude_m);
    std::printf("%-14s real-time model: PSNR %6.2f dB, rel. luminance error median %6.2f %%, p95 %6.2f %%\n", v.name,
                e.psnr_db, 100 * e.median, 100 * e.p95);
    std::printf("%-14s Preetham:        PSNR %6.2f dB, rel. luminance error median %6.2f %%, p95 %6.2f %%  (%s)\n", "",
                p.psnr_db, 100 * p.median, 100 * p.p95, valid.valid ? "in its validity region" : valid.reason.c_str());
    out << visibility_m << ",\"" << v.name << "\",real_time," << e.psnr_db << ',' << e.median << ',' << e.p95 << ',' << ours.size() << '\n';
    out << visibility_m << ",\"" << v.name << "\",preetham," << p.psnr_db << ',' << p.median << ',' << p.p95 << ',' << ours.size() << '\n';
  }
  return 0;
}
