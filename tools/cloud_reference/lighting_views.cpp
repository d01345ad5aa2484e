#include "lighting_views.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/clouds/cloud_clipmap.h"
#include "core/clouds/cloud_optics.h"
#include "core/clouds/procedural_clouds.h"
#include "reference_clouds.h"

namespace atmo::clouds::reference {
namespace {

// Prototype `index` of a procedural cumulus layer (seed 7, 1000-1800 m,
// voxels <= 30 m), at the origin, with extinction `extinction_per_m`.
CloudVolume cumulus_prototype(int index, float extinction_per_m) {
  CloudLayerSpec s;
  s.type = CloudLayerType::Cumulus;
  s.coverage_oktas = 3;
  s.base_m = 1000;
  s.top_m = 1800;
  s.area_size_m = 10000;
  s.seed = 7;
  s.max_voxel_size_m = 30;
  CloudVolume c = generate_cloud_layer(s).field.prototypes.at(static_cast<size_t>(index));
  c.origin_enu_m = glm::dvec3(0.0, 0.0, 1000.0);
  c.optics.extinction_per_m = extinction_per_m;
  return c;
}

// A homogeneous deck: 40 x 40 columns of 40 m, 8 voxels thick (one empty voxel
// above and below), vertical optical depth `tau`.
CloudVolume deck(double tau) {
  CloudVolume c;
  c.name = "deck";
  c.voxel_size_m = 40.0f;
  c.density = DenseGrid(40, 40, 10);
  for (int z = 1; z < 9; ++z)
    for (int y = 0; y < 40; ++y)
      for (int x = 0; x < 40; ++x) c.density.at(x, y, z) = 1.0f;
  c.optics.extinction_per_m = static_cast<float>(tau / (8 * 40.0));
  c.origin_enu_m = glm::dvec3(0, 0, 1000);
  return c;
}

// Prototype `index` of a procedural stratus deck (seed 3, 800-1100 m, 6 km
// area: 62 x 62 x 8 voxels of 50 m, with holes), extinction `extinction_per_m`.
CloudVolume stratus_tile(int index, float extinction_per_m) {
  CloudLayerSpec s;
  s.type = CloudLayerType::Stratus;
  s.coverage_oktas = 8;
  s.base_m = 800;
  s.top_m = 1100;
  s.area_size_m = 6000;
  s.seed = 3;
  CloudVolume c = generate_cloud_layer(s).field.prototypes.at(static_cast<size_t>(index));
  c.optics.extinction_per_m = extinction_per_m;
  return c;
}

// Unit vector towards the Sun: elevation, and azimuth from north (y) towards east (x).
glm::dvec3 sun_at(double elevation_deg, double azimuth_deg) {
  const double e = glm::radians(elevation_deg), a = glm::radians(azimuth_deg);
  return glm::dvec3(std::cos(e) * std::sin(a), std::cos(e) * std::cos(a), std::sin(e));
}

#include "path_traced_references.inc"

}  // namespace

const std::vector<LightingView>& development_views() {
  static const auto cu3 = [] { return cumulus_prototype(3, 0.06f); };
  static const std::vector<LightingView> v = {
      {"blob_eyesun", "blob, Sun behind the eye, 45 deg up", blob_cloud, glm::normalize(glm::dvec3(0, -1, 1)),
       glm::dvec3(0, -2000, 0)},
      {"blob_side", "blob, Sun to the side, 30 deg up", blob_cloud, glm::normalize(glm::dvec3(1, 0, 0.58)),
       glm::dvec3(0, -2000, 0)},
      {"blob_behind", "blob, Sun behind it, 20 deg up", blob_cloud, glm::normalize(glm::dvec3(0, 1, 0.36)),
       glm::dvec3(0, -2000, 0)},
      {"blob_below", "blob from below, Sun overhead", blob_cloud, glm::dvec3(0, 0, 1), glm::dvec3(0, -300, -1500)},
      {"cu0_side", "cumulus #0, Sun to the side, 45 deg up", [] { return cumulus_prototype(0, 0.06f); },
       sun_at(45, 90), glm::dvec3(0, -2000, 300)},
      {"cu_front", "cumulus #3, Sun high behind the eye", cu3, sun_at(60, 200), glm::dvec3(300, -2200, 200)},
      {"cu_low_sun", "cumulus #3, Sun 8 deg up to the side", cu3, sun_at(8, 70), glm::dvec3(-400, -2200, -100)},
      {"cu_below", "cumulus #3 from below, Sun 40 deg up", cu3, sun_at(40, 30), glm::dvec3(200, -500, -1400)},
      {"thin_side", "thin cumulus (tau <= 2), Sun 35 deg up", [] { return cumulus_prototype(5, 0.006f); },
       sun_at(35, 100), glm::dvec3(0, -1800, 100), 0.0, 16, 500000, 0.9f},
      {"deck_below", "deck tau 20 from below, Sun 50 deg up", [] { return deck(20.0); }, sun_at(50, 120),
       glm::dvec3(0, -300, -900), 30.0, 10, 300000},
      {"deck_above", "deck tau 20 from above, Sun 25 deg up", [] { return deck(20.0); }, sun_at(25, 250),
       glm::dvec3(0, -500, 900), 30.0, 10, 300000},
  };
  return v;
}

const std::vector<LightingView>& held_out_views() {
  static const std::vector<LightingView> v = {
      {"f_cu7_side", "cumulus #7, Sun 30 deg up, side-lit", [] { return cumulus_prototype(7, 0.06f); },
       sun_at(30, 120), glm::dvec3(-500, -2300, 0)},
      {"f_cu9_below", "cumulus #9 from below, Sun 65 deg up", [] { return cumulus_prototype(9, 0.06f); },
       sun_at(65, 300), glm::dvec3(300, -400, -1300)},
      {"f_st_below", "stratus tile (tau <= 7, holes) from below", [] { return stratus_tile(0, 0.04f); },
       sun_at(40, 200), glm::dvec3(0, -300, -900), 30.0, 10, 300000},
      {"f_st_thick_above", "stratus tile x2.5 (tau <= 18) from above", [] { return stratus_tile(3, 0.1f); },
       sun_at(20, 80), glm::dvec3(200, -600, 900), 30.0, 10, 300000},
      {"f_thin_behind", "thin cumulus (tau <= 5), Sun 20 deg up behind it", [] { return cumulus_prototype(11, 0.012f); },
       sun_at(20, 0), glm::dvec3(0, -1800, 0), 0.0, 16, 500000, 0.9f},
  };
  return v;
}

PinholeCamera camera_for(const LightingView& v, const CloudVolume& cloud) {
  PinholeCamera cam;
  cam.position_enu_m = cloud.centre_enu_m() + v.eye_offset;
  cam.forward = -v.eye_offset;
  cam.up = glm::dvec3(0, 0, 1);
  if (std::abs(glm::normalize(cam.forward).z) > 0.99) cam.up = glm::dvec3(0, 1, 0);
  cam.vertical_fov_rad = v.fov_deg > 0.0 ? glm::radians(v.fov_deg)
                                         : 2.0 * std::atan(cloud.bounding_radius_m() / glm::length(cam.forward)) * 0.9;
  cam.width = cam.height = v.res;
  return cam;
}

glm::dvec3 pixel_ray(const PinholeCamera& cam, int row, int col) {
  const glm::dvec3 fwd = glm::normalize(cam.forward);
  const glm::dvec3 right = glm::normalize(glm::cross(fwd, cam.up));
  const glm::dvec3 up = glm::cross(right, fwd);
  const double th = std::tan(0.5 * cam.vertical_fov_rad);
  const double y = (1.0 - 2.0 * (row + 0.5) / cam.height) * th;
  const double x = (2.0 * (col + 0.5) / cam.width - 1.0) * th;
  return glm::normalize(fwd + x * right + y * up);
}

const StoredReference* stored_reference(const char* key) {
  for (const StoredReference& r : kStoredReferences)
    if (std::string(r.key) == key) return &r;
  return nullptr;
}

LightingErrors compare_with_reference(const LightingView& v, const twin::CloudOctaves& octaves, LightingMarch how) {
  const CloudVolume cloud = v.cloud();
  const PinholeCamera cam = camera_for(v, cloud);
  const StoredReference* ref = stored_reference(v.key);
  LightingErrors e;
  if (!ref || ref->res != v.res) return e;
  const LightDepths depths = compute_light_depths(cloud, v.sun);
  const twin::CloudPhase phase = phase_for_droplet(cloud.optics.droplet_diameter_um);
  CloudLight sun, amb;
  sun.direction_enu = amb.direction_enu = v.sun;
  sun.illuminance_lux = glm::dvec3(kViewSunLux);
  amb.sky_radiance = glm::dvec3(kViewSkyCdm2);
  amb.ground_radiance = glm::dvec3(kViewGroundCdm2);
  const twin::CloudMarch m_sun = make_cloud_march(cloud, sun, 0.5f, 2048);
  const twin::CloudMarch m_amb = make_cloud_march(cloud, amb, 0.5f, 2048);
  // The layer march's clipmap of the one cloud, as set_clouds would place it.
  CloudField field;
  CloudClipmap clipmap;
  twin::CloudLayerMarch l_sun{}, l_amb{};
  if (how == LightingMarch::Layer) {
    field.prototypes.push_back(cloud);
    field.instances.push_back({0, cloud.origin_enu_m});
    const ClipmapSpec spec;
    const ClipmapGeometry geometry = clipmap_geometry(field, spec);
    clipmap = build_clipmap(field, build_prototype_mips(field, {depths}, v.sun), build_cloud_ray_index(field), spec,
                            geometry, clipmap_cell(geometry, cam.position_enu_m));
    l_sun = make_layer_march(clipmap, cam.position_enu_m, sun, 0.5f, 4096);
    l_amb = make_layer_march(clipmap, cam.position_enu_m, amb, 0.5f, 4096);
  }
  auto model = [&](const glm::dvec3& d, bool of_sun) {
    if (how == LightingMarch::Layer)
      return double(march_layer_ray(clipmap, of_sun ? l_sun : l_amb, octaves, d, 1e9).radiance.g);
    return double(
        march_cloud_ray(cloud, depths, of_sun ? m_sun : m_amb, phase, octaves, cam.position_enu_m, d, 1e9).radiance.g);
  };
  double sun_model = 0.0, sun_truth = 0.0, amb_model = 0.0, amb_truth = 0.0;
  for (int row = 0; row < v.res; ++row)
    for (int col = 0; col < v.res; ++col) {
      const float* px = ref->data + 5 * (static_cast<size_t>(row) * v.res + col);
      if (px[3] > v.max_transmittance) continue;
      const double truth_sun = px[0], truth_amb = px[1] + px[2], truth = truth_sun + truth_amb;
      const glm::dvec3 d = pixel_ray(cam, row, col);
      const double ms = model(d, true), ma = model(d, false);
      e.mean += std::abs(ms + ma - truth) / truth;
      e.bias += (ms + ma) / truth - 1.0;
      e.sun += std::abs(ms - truth_sun) / truth;
      e.ambient += std::abs(ma - truth_amb) / truth;
      e.noise += px[4];
      sun_model += ms, sun_truth += truth_sun, amb_model += ma, amb_truth += truth_amb;
      ++e.pixels;
    }
  if (e.pixels) {
    for (double* x : {&e.mean, &e.bias, &e.sun, &e.ambient, &e.noise}) *x /= e.pixels;
    e.sun_ratio = sun_model / sun_truth;
    e.ambient_ratio = amb_model / amb_truth;
  }
  return e;
}

ViewRays view_rays(const LightingView& v) {
  ViewRays r;
  r.cloud = v.cloud();
  const PinholeCamera cam = camera_for(v, r.cloud);
  r.eye = cam.position_enu_m;
  r.depths = compute_light_depths(r.cloud, v.sun);
  r.phase = phase_for_droplet(r.cloud.optics.droplet_diameter_um);
  CloudLight light;
  light.direction_enu = v.sun;
  light.illuminance_lux = glm::dvec3(kViewSunLux);
  light.sky_radiance = glm::dvec3(kViewSkyCdm2);
  light.ground_radiance = glm::dvec3(kViewGroundCdm2);
  r.march = make_cloud_march(r.cloud, light, 0.5f, 2048);
  const StoredReference* ref = stored_reference(v.key);
  for (int row = 0; row < v.res; ++row)
    for (int col = 0; col < v.res; ++col) {
      const size_t i = static_cast<size_t>(row) * v.res + col;
      if (ref && ref->res == v.res && ref->data[5 * i + 3] > v.max_transmittance) continue;
      r.directions.push_back(pixel_ray(cam, row, col));
    }
  return r;
}

std::vector<double> nelder_mead(const std::function<double(const std::vector<double>&)>& f, std::vector<double> x0,
                                int iterations) {
  const size_t n = x0.size();
  std::vector<std::vector<double>> s(n + 1, x0);
  std::vector<double> fv(n + 1);
  for (size_t i = 0; i < n; ++i) s[i + 1][i] += 0.2 * std::abs(x0[i]) + 0.02;
  for (size_t i = 0; i <= n; ++i) fv[i] = f(s[i]);
  for (int it = 0; it < iterations; ++it) {
    std::vector<size_t> o(n + 1);
    for (size_t i = 0; i <= n; ++i) o[i] = i;
    std::sort(o.begin(), o.end(), [&](size_t a, size_t b) { return fv[a] < fv[b]; });
    const auto S = s;
    const auto F = fv;
    for (size_t i = 0; i <= n; ++i) s[i] = S[o[i]], fv[i] = F[o[i]];
    std::vector<double> c(n, 0.0);
    for (size_t i = 0; i < n; ++i)
      for (size_t j = 0; j < n; ++j) c[j] += s[i][j] / n;
    auto along = [&](double t) {
      std::vector<double> r(n);
      for (size_t j = 0; j < n; ++j) r[j] = c[j] + t * (s[n][j] - c[j]);
      return r;
    };
    const auto xr = along(-1.0);
    const double fr = f(xr);
    if (fr < fv[0]) {
      const auto xe = along(-2.0);
      const double fe = f(xe);
      s[n] = fe < fr ? xe : xr, fv[n] = std::min(fe, fr);
    } else if (fr < fv[n - 1]) {
      s[n] = xr, fv[n] = fr;
    } else {
      const auto xc = along(fr < fv[n] ? -0.5 : 0.5);
      const double fc = f(xc);
      if (fc < std::min(fr, fv[n])) {
        s[n] = xc, fv[n] = fc;
      } else {
        for (size_t i = 1; i <= n; ++i) {
          for (size_t j = 0; j < n; ++j) s[i][j] = s[0][j] + 0.5 * (s[i][j] - s[0][j]);
          fv[i] = f(s[i]);
        }
      }
    }
  }
  return s[std::min_element(fv.begin(), fv.end()) - fv.begin()];
}

}  // namespace atmo::clouds::reference
