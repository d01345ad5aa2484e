// cloud_relight.h — relighting the clouds off the host's thread. When the Sun
// or Moon has moved past the threshold, one worker thread recomputes every
// prototype's optical depth to the light (core/clouds/cloud_lighting) into its
// own copy of the light grids; the host's thread keeps drawing with the old
// grids and swaps the new ones in on the first cloud pass after the job ends.
// No frame waits for it (the first lighting of a new field is the exception:
// there is nothing to draw before it).
//
// Threads: the job reads the field (const, never changed while it lives: the
// owner stops the job before replacing or destroying the field) and writes
// only its own grids; the owner (the host's thread) polls and takes them.
#pragma once

#include <atomic>
#include <memory>
#include <thread>
#include <vector>

#include "core/clouds/cloud_field.h"
#include "core/clouds/cloud_lighting.h"
#include "core/clouds/cloud_shadow.h"

namespace atmo::abi {

class CloudRelightJob {
 public:
  // Starts at once on a new thread; `depths` is the grids to update (their
  // tau_up and tau_down are kept, tau_light replaced).
  CloudRelightJob(const clouds::CloudField* field, std::vector<clouds::LightDepths> depths,
                  const glm::dvec3& light_direction_enu, bool with_shadow);
  ~CloudRelightJob();  // cancels a running job and joins
  CloudRelightJob(const CloudRelightJob&) = delete;
  CloudRelightJob& operator=(const CloudRelightJob&) = delete;

  bool done() const { return done_.load(std::memory_order_acquire); }
  // Blocks until done (tests, and the first lighting).
  void wait();
  // After done(): the grids (moved out) and what they were lit for.
  std::vector<clouds::LightDepths> take() { return std::move(depths_); }
  // After done(), when made with_shadow: the shadow map for the new light (moved out).
  clouds::CloudShadowMap take_shadow() { return std::move(shadow_); }
  bool has_shadow() const { return with_shadow_; }
  const glm::dvec3& direction() const { return direction_; }
  double elapsed_ms() const { return elapsed_ms_; }

 private:
  void run();
  const clouds::CloudField* field_;
  std::vector<clouds::LightDepths> depths_;
  glm::dvec3 direction_;
  bool with_shadow_;
  clouds::CloudShadowMap shadow_;
  double elapsed_ms_ = 0.0;
  std::atomic<bool> cancel_{false};
  std::atomic<bool> done_{false};
  std::thread thread_;
};

// Where an owner keeps its job, declared before the field the job reads: a
// move (of the owner) cancels and joins the jobs on both sides before the
// field moves, so no job ever reads a field that moved or died; the owner's
// destructor must call reset() first (members die in reverse order). A
// cancelled relight is simply asked for again by the next frame.
struct CloudRelightSlot {
  std::unique_ptr<CloudRelightJob> job;
  CloudRelightSlot() = default;
  CloudRelightSlot(CloudRelightSlot&& o) noexcept { o.job.reset(); }
  CloudRelightSlot& operator=(CloudRelightSlot&& o) noexcept {
    job.reset();
    o.job.reset();
    return *this;
  }
  void reset() { job.reset(); }
};

// The whole relight on the calling thread (the first lighting, and the job's
// body): each grid's own optical depth to the light, then what the light
// crosses in the other grids (core/clouds/field_light.h: deck tiles).
// Stops early, leaving the grids partly updated, when *cancel becomes true.
void relight_all(const clouds::CloudField& field, const glm::dvec3& light_direction_enu,
                 std::vector<clouds::LightDepths>* depths, const std::atomic<bool>* cancel = nullptr);

// The plugin's shadow map of the clouds for a light (256^2, 2-voxel steps).
clouds::CloudShadowMap make_shadow_map(const clouds::CloudField& field, const glm::dvec3& light_direction_enu);

}  // namespace atmo::abi
