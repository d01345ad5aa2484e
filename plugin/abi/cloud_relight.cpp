#include "abi/cloud_relight.h"

#include <chrono>

namespace atmo::abi {

void relight_all(const clouds::CloudField& field, const glm::dvec3& dir, std::vector<clouds::LightDepths>* depths,
                 const std::atomic<bool>* cancel) {
  for (size_t p = 0; p < field.prototypes.size(); ++p) {
    const clouds::CloudVolume& v = field.prototypes[p];
    // A slab of slices at a time, so a cancel (set_clouds, destroy) is heard soon.
    constexpr int kSlab = 8;
    for (int z = 0; z < v.density.nz; z += kSlab) {
      if (cancel && cancel->load(std::memory_order_relaxed)) return;
      clouds::compute_light_depth_slices(v, dir, z, std::min(v.density.nz, z + kSlab), &(*depths)[p]);
    }
  }
}

CloudRelightJob::CloudRelightJob(const clouds::CloudField* field, std::vector<clouds::LightDepths> depths,
                                 const glm::dvec3& dir)
    : field_(field), depths_(std::move(depths)), direction_(dir) {
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
  elapsed_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  done_.store(true, std::memory_order_release);
}

}  // namespace atmo::abi
