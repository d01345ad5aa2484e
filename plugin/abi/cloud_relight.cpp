#include "abi/cloud_relight.h"

#include <chrono>

#include "core/clouds/field_light.h"

namespace atmo::abi {

namespace {
constexpr int kSlab = 8;  // z-slices between checks of the cancel flag (set_clouds, destroy)
}  // namespace

void relight_all(const clouds::CloudField& field, const glm::dvec3& dir, std::vector<clouds::LightDepths>* depths,
                 const std::atomic<bool>* cancel) {
  for (size_t p = 0; p < field.prototypes.size(); ++p) {
    const clouds::CloudVolume& v = field.prototypes[p];
    for (int z = 0; z < v.density.nz; z += kSlab) {
      if (cancel && cancel->load(std::memory_order_relaxed)) return;
      clouds::compute_light_depth_slices(v, dir, z, std::min(v.density.nz, z + kSlab), &(*depths)[p]);
    }
  }
  // Then what the light crosses in the neighbouring grids (deck tiles), once every grid holds its own.
  for (size_t p = 0; p < field.prototypes.size(); ++p) {
    if (cancel && cancel->load(std::memory_order_relaxed)) return;
    const clouds::FieldLightPlan plan = clouds::plan_field_light(field, static_cast<int>(p), dir);
    if (plan.prototype < 0) continue;
    const int nz = field.prototypes[p].density.nz;
    for (int z = 0; z < nz; z += kSlab) {
      if (cancel && cancel->load(std::memory_order_relaxed)) return;
      clouds::add_field_light_slices(field, plan, z, std::min(nz, z + kSlab), &(*depths)[p]);
    }
  }
}

clouds::CloudShadowMap make_shadow_map(const clouds::CloudField& field, const glm::dvec3& dir) {
  return clouds::compute_cloud_shadow_map(field, dir, 256, 100000.0, 2.0f);
}

CloudRelightJob::CloudRelightJob(const clouds::CloudField* field, std::vector<clouds::LightDepths> depths,
                                 const glm::dvec3& dir, bool with_shadow)
    : field_(field), depths_(std::move(depths)), direction_(dir), with_shadow_(with_shadow) {
  thread_ = std::thread([this] { run(); });
}

CloudRelightJob::~CloudRelightJob() {
  cancel_.store(true);
  if (thread_.joinable()) thread_.join();
}

void CloudRelightJob::wait() {
  if (thread_.joinable()) thread_.join();
}

void CloudRelightJob::run() {
  const auto t0 = std::chrono::steady_clock::now();
  relight_all(*field_, direction_, &depths_, &cancel_);
  if (with_shadow_ && !cancel_.load()) shadow_ = make_shadow_map(*field_, direction_);
  elapsed_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  done_.store(true, std::memory_order_release);
}

}  // namespace atmo::abi
