// Sky occlusion by spheres, error against cost (docs/SKY_OCCLUSION.md): the
// occluded sky irradiance of every receiver of tools/shadow_reference's
// configurations by SH order (2..6) and exponential (direct product of
// blockers, exact, optimal linear, hybrid; core/shadows/sphere_occlusion), and
// by the include's twin (order 4, hybrid, float: what ships), against the
// ray-traced reference; then the error as the spheres multiply (a random
// cluster of 1..64 spheres). Error: |E - E_ref| / E_open_ref per receiver;
// cost: CPU microseconds per receiver on this machine (median of repeats).
//   atmo_sky_occlusion_error_cost [--csv PATH]   (tools/sky_occlusion_chart.sh charts it)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "core/shadows/occlusion_frame.h"
#include "core/shadows/occlusion_twin.h"
#include "core/shadows/sphere_occlusion.h"
#include "occlusion_scenes.h"
#include "shadow_reference.h"

namespace sr = atmo::shadow_reference;
namespace sh = atmo::shadows;

namespace {

struct Case {
  std::vector<glm::dvec4> spheres;  // world
  sr::Receiver receiver;
  double reference = 0.0, open = 0.0;  // green channel, lux
};

struct Row {
  std::string study, method;
  int order = 4, spheres = 0;
  double median = 0, p90 = 0, worst = 0, cpu_us = 0;
};

template <typename F>
double micros(F f, int repeats) {
  std::vector<double> t;
  for (int r = 0; r < 3; ++r) {
    const auto a = std::chrono::steady_clock::now();
    for (int k = 0; k < repeats; ++k) f();
    t.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - a).count() / repeats);
  }
  std::sort(t.begin(), t.end());
  return t[1];
}

void reference_of(Case* c) {
  sr::Scene scene;
  for (const glm::dvec4& s : c->spheres) scene.spheres.push_back({glm::dvec3(s), s.w, 0});
  scene.object_albedo = {glm::dvec3(0.5)};
  scene.sky_radiance = sr::test_sky_radiance;
  c->open = sr::sky_irradiance(scene, c->receiver.position_m, c->receiver.normal, false, 40000).value.y;
  c->reference = sr::sky_irradiance(scene, c->receiver.position_m, c->receiver.normal, true, 100000).value.y;
}

Row summarise(std::vector<double> errors) {
  std::sort(errors.begin(), errors.end());
  Row r;
  r.median = errors[errors.size() / 2];
  r.p90 = errors[std::min(errors.size() - 1, errors.size() * 9 / 10)];
  r.worst = errors.back();
  return r;
}

// The study evaluator over the cases.
Row study(const std::vector<Case>& cases, const sh::ShOrder& order, const std::vector<glm::dvec3>& sky,
          sh::ExpMethod method) {
  std::vector<double> errors;
  double cost = 0.0;
  for (const Case& c : cases) {
    std::vector<glm::dvec4> rel;
    for (const glm::dvec4& s : c.spheres) rel.emplace_back(glm::dvec3(s) - c.receiver.position_m, s.w);
    sh::OccludedSky got;
    const int repeats = method == sh::ExpMethod::exact ? 3 : 20;
    cost += micros([&] { got = sh::occluded_sky(order, rel, c.receiver.normal, sky, method); }, repeats);
    errors.push_back(std::abs(got.sky_lux.y - c.reference) / c.open);
  }
  Row r = summarise(errors);
  r.cpu_us = cost / cases.size();
  r.method = sh::exp_method_name(method);
  r.order = order.order();
  return r;
}

// The include's twin (as shipped) over the cases: one object per case, the frame's camera ahead of it.
Row twin(const std::vector<Case>& cases) {
  const glm::dvec3 sun = glm::normalize(glm::dvec3(0.3, -0.5, 0.8));
  const sh::SkyTransfer transfer = sh::make_sky_transfer(sr::test_sky_sh(4), sun, glm::dvec3(9e4));
  std::vector<double> errors;
  double cost = 0.0;
  for (const Case& c : cases) {
    const sh::OccluderObject object = sh::make_occluder_object(c.spheres, glm::dvec3(0.5));
    const glm::dmat4 pose = glm::dmat4(1.0);
    glm::dmat4 clip(1.0);  // any camera: every object in the one tile
    const sh::OcclusionFrame frame = sh::make_occlusion_frame({&object}, {pose}, clip, glm::dmat3(1.0), 32, 32,
                                                              transfer, sun, glm::dvec3(9e4), sh::OcclusionLimits{});
    sh::twin::AtmoSkyOcclusion got;
    cost += micros([&] { got = sh::twin::evaluate(frame, glm::vec3(c.receiver.position_m), glm::vec3(c.receiver.normal)); }, 50);
    errors.push_back(std::abs(got.sky_lux.y - c.reference) / c.open);
  }
  Row r = summarise(errors);
  r.cpu_us = cost / cases.size();
  r.method = "include (float, order 4, hybrid)";
  r.order = 4;
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  std::string csv_path;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--csv") && i + 1 < argc) {
      csv_path = argv[++i];
    } else {
      std::fprintf(stderr, "usage: %s [--csv PATH]\n", argv[0]);
      return 2;
    }
  }
  // The configurations' receivers; their references once.
  std::vector<Case> cases;
  for (const sr::OcclusionConfig& c : sr::occlusion_configs())
    for (const sr::Receiver& r : c.receivers) cases.push_back({c.spheres, r});
  std::fprintf(stderr, "reference: %zu receivers ...\n", cases.size());
  for (Case& c : cases) reference_of(&c);

  std::vector<Row> rows;
  const sh::ExpMethod methods[4] = {sh::ExpMethod::direct_product, sh::ExpMethod::exact, sh::ExpMethod::optimal_linear,
                                    sh::ExpMethod::hybrid};
  for (int order = 2; order <= 6; ++order) {
    std::fprintf(stderr, "order %d ...\n", order);
    const sh::ShOrder o(order);
    const std::vector<glm::dvec3> sky = sr::test_sky_sh(order);
    for (sh::ExpMethod m : methods) {
      Row r = study(cases, o, sky, m);
      r.study = "configurations";
      rows.push_back(r);
    }
  }
  {
    Row r = twin(cases);
    r.study = "configurations";
    rows.push_back(r);
  }
  // Sphere count: a random cluster of n spheres (radius 0.4..1.4 m) 3..7 m over 5 receivers on the ground.
  std::fprintf(stderr, "sphere count ...\n");
  const sh::ShOrder o4(4);
  const std::vector<glm::dvec3> sky4 = sr::test_sky_sh(4);
  for (int n : {1, 2, 4, 8, 16, 32, 64}) {
    std::vector<Case> cluster;
    uint32_t s = 777u + n;
    auto rnd = [&s]() { s = s * 1664525u + 1013904223u; return (s >> 8) / 16777216.0; };
    std::vector<glm::dvec4> spheres;
    for (int i = 0; i < n; ++i)
      spheres.push_back({10.0 * rnd() - 5.0, 10.0 * rnd() - 5.0, 3.0 + 4.0 * rnd(), 0.4 + 1.0 * rnd()});
    for (double x : {-4.0, -2.0, 0.0, 2.0, 4.0}) cluster.push_back({spheres, {{x, 0.0, 0.0}, {0, 0, 1}}});
    for (Case& c : cluster) reference_of(&c);
    for (sh::ExpMethod m : methods) {
      Row r = study(cluster, o4, sky4, m);
      r.study = "sphere count";
      r.spheres = n;
      rows.push_back(r);
    }
  }

  std::printf("%-15s %-34s %5s %7s %9s %9s %9s %10s\n", "study", "method", "order", "spheres", "median %", "p90 %",
              "worst %", "cpu us");
  for (const Row& r : rows)
    std::printf("%-15s %-34s %5d %7d %9.2f %9.2f %9.2f %10.2f\n", r.study.c_str(), r.method.c_str(), r.order,
                r.spheres, 100 * r.median, 100 * r.p90, 100 * r.worst, r.cpu_us);
  if (!csv_path.empty()) {
    std::ofstream out(csv_path);
    out << "study,method,order,spheres,median,p90,worst,cpu_us\n";
    for (const Row& r : rows)
      out << r.study << ',' << r.method << ',' << r.order << ',' << r.spheres << ',' << r.median << ',' << r.p90 << ','
          << r.worst << ',' << r.cpu_us << '\n';
    if (!out) {
      std::fprintf(stderr, "cannot write %s\n", csv_path.c_str());
      return 1;
    }
  }
  return 0;
}
