// cloud_relight.h — the clouds' work off the host's thread. When the Sun or
// Moon has moved past the threshold (or a new field is first lit in full), a
// worker thread recomputes every prototype's optical depths
// (core/clouds/cloud_lighting) into its own copy of the light grids, with the
// shadow map and the layer march's prototype mips; a clipmap job resamples
// the field around the eye's new cell (core/clouds/cloud_clipmap); a field
// job generates the streamed set-up's decks at full resolution. The host's
// thread keeps drawing with what it has and swaps the new data in at the
// host frame the job is due (CloudJobSlot::due: ATMO_DEFERRED_FRAMES after it
// started, waiting for it if need be; abi/cloud_inputs), or at once
// (ATMO_CLOUD_SETUP_WAIT).
//
// Threads: a job reads the field (const, never changed while it lives: the
// owner stops the job before replacing or destroying the field) and writes
// only its own results; the owner (the host's thread) polls and takes them.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <thread>
#include <vector>

#include "atmo/atmo.h"
#include "core/clouds/cloud_clipmap.h"
#include "core/clouds/cloud_field.h"
#include "core/clouds/cloud_lighting.h"
#include "core/clouds/cloud_shadow.h"
#include "core/clouds/cloud_transmittance.h"
#include "core/clouds/field_light.h"

namespace atmo::abi {

// One computation on its own thread, started at construction; the destructor
// asks it to stop (the body polls `cancel`) and joins.
class CloudWorkerThread {
 public:
  using Body = std::function<void(const std::atomic<bool>& cancel)>;
  explicit CloudWorkerThread(Body body);
  ~CloudWorkerThread();
  CloudWorkerThread(const CloudWorkerThread&) = delete;
  CloudWorkerThread& operator=(const CloudWorkerThread&) = delete;
  bool done() const { return done_.load(std::memory_order_acquire); }
  void wait();                                     // blocks until done
  double elapsed_ms() const { return elapsed_ms_; }  // after done()

 private:
  std::atomic<bool> cancel_{false};
  std::atomic<bool> done_{false};
  double elapsed_ms_ = 0.0;
  std::thread thread_;  // last: starts once the rest exists
};

// What a relight computes besides tau_light.
struct RelightRequest {
  glm::dvec3 light_direction_enu{0.0, 0.0, 1.0};
  bool with_shadow = false;  // the shadow map for the new light
  // A field's first full lighting: tau_up and tau_down too (else kept from
  // the grids given), each prototype's grid continuing across `sides`.
  bool with_ambient = false;
  std::vector<clouds::ContinuingSides> sides;
  bool with_mips = false;    // the layer march's prototype mips for the new grids
  // The field's neighbour search (its index must outlive the job); empty: a scan of every instance.
  clouds::FieldNeighbours neighbours;
};

class CloudRelightJob {
 public:
  // Starts at once on a new thread; `depths` is the grids to update (one per
  // prototype; sized by the job when with_ambient).
  CloudRelightJob(const clouds::CloudField* field, std::vector<clouds::LightDepths> depths, RelightRequest request);
  CloudRelightJob(const CloudRelightJob&) = delete;
  CloudRelightJob& operator=(const CloudRelightJob&) = delete;

  bool done() const { return thread_.done(); }
  void wait() { thread_.wait(); }  // blocks until done (tests, and ATMO_CLOUD_SETUP_WAIT)
  // After done(): the grids (moved out) and what they were lit for.
  std::vector<clouds::LightDepths> take() { return std::move(depths_); }
  // After done(), when made with_shadow: the shadow map for the new light (moved out).
  clouds::CloudShadowMap take_shadow() { return std::move(shadow_); }
  // After done(), when made with_mips.
  std::shared_ptr<const std::vector<clouds::PrototypeMips>> take_mips() { return std::move(mips_); }
  bool has_shadow() const { return request_.with_shadow; }
  bool has_mips() const { return request_.with_mips; }
  const glm::dvec3& direction() const { return request_.light_direction_enu; }
  double elapsed_ms() const { return thread_.elapsed_ms(); }

 private:
  void run(const std::atomic<bool>& cancel);
  const clouds::CloudField* field_;
  std::vector<clouds::LightDepths> depths_;
  RelightRequest request_;
  clouds::CloudShadowMap shadow_;
  std::shared_ptr<const std::vector<clouds::PrototypeMips>> mips_;
  CloudWorkerThread thread_;  // last
};

// The clipmap for an eye cell, built on a worker (core/clouds/cloud_clipmap).
struct ClipmapRequest {
  const clouds::CloudField* field = nullptr;                          // read while the job lives
  std::shared_ptr<const std::vector<clouds::PrototypeMips>> mips;     // kept alive by the job
  const clouds::CloudRayIndex* index = nullptr;                       // read while the job lives
  clouds::ClipmapSpec spec;
  clouds::ClipmapGeometry geometry;
  glm::ivec2 cell{0};
  uint64_t built_for = 0;  // the owner's version of the field and its light
};

class CloudClipmapJob {
 public:
  explicit CloudClipmapJob(ClipmapRequest request);
  CloudClipmapJob(const CloudClipmapJob&) = delete;
  CloudClipmapJob& operator=(const CloudClipmapJob&) = delete;
  bool done() const { return thread_.done(); }
  void wait() { thread_.wait(); }
  clouds::CloudClipmap take() { return std::move(clipmap_); }  // after done()
  uint64_t built_for() const { return request_.built_for; }
  double elapsed_ms() const { return thread_.elapsed_ms(); }

 private:
  ClipmapRequest request_;
  clouds::CloudClipmap clipmap_;
  CloudWorkerThread thread_;  // last
};

// A field built on a worker: the streamed set-up's decks at full resolution
// (set_clouds drew them coarse). `build` polls the flag and returns early
// (an empty field) when it is raised.
class CloudFieldJob {
 public:
  using Build = std::function<clouds::CloudField(const std::atomic<bool>& cancel)>;
  explicit CloudFieldJob(Build build);
  CloudFieldJob(const CloudFieldJob&) = delete;
  CloudFieldJob& operator=(const CloudFieldJob&) = delete;
  bool done() const { return thread_.done(); }
  void wait() { thread_.wait(); }
  clouds::CloudField take() { return std::move(field_); }  // after done()
  double elapsed_ms() const { return thread_.elapsed_ms(); }

 private:
  Build build_;
  clouds::CloudField field_;
  CloudWorkerThread thread_;  // last
};

// Where an owner keeps a job, declared before the field the job reads: a
// move (of the owner) cancels and joins the jobs on both sides before the
// field moves, so no job ever reads a field that moved or died; the owner's
// destructor must call reset() first (members die in reverse order). A
// cancelled job is simply asked for again by the next frame.
//
// A job takes effect at a host frame fixed when it starts (started_frame +
// AtmoFrameState.deferred_frames: due()), never at "the first call after it ends",
// so every channel of a multi-channel host switches on the same frame
// whatever its machine's pace; the owner waits for a job that is due and
// not done. A host frame number that went back makes a job due.
template <class Job>
struct CloudJobSlot {
  std::unique_ptr<Job> job;
  uint64_t started_frame = 0, due_frame = 0;
  void start(std::unique_ptr<Job> j, uint64_t frame, uint64_t deferred_frames = ATMO_DEFERRED_FRAMES) {
    job = std::move(j);
    started_frame = frame;
    due_frame = frame + deferred_frames;
  }
  bool due(uint64_t frame) const { return job && (frame >= due_frame || frame < started_frame); }
  CloudJobSlot() = default;
  CloudJobSlot(CloudJobSlot&& o) noexcept { o.job.reset(); }
  CloudJobSlot& operator=(CloudJobSlot&& o) noexcept {
    job.reset();
    o.job.reset();
    return *this;
  }
  void reset() { job.reset(); }
};
using CloudRelightSlot = CloudJobSlot<CloudRelightJob>;
using CloudClipmapSlot = CloudJobSlot<CloudClipmapJob>;
using CloudFieldSlot = CloudJobSlot<CloudFieldJob>;

// The whole relight on the calling thread (the draft's lighting, and the
// job's body): each grid's own optical depth to the light, then what the
// light crosses in the other grids (core/clouds/field_light.h: deck tiles).
// Stops early, leaving the grids partly updated, when *cancel becomes true.
void relight_all(const clouds::CloudField& field, const glm::dvec3& light_direction_enu,
                 std::vector<clouds::LightDepths>* depths, const std::atomic<bool>* cancel = nullptr,
                 const clouds::FieldNeighbours* neighbours = nullptr);

// The plugin's shadow map of the clouds for a light (`texels`^2, steps of `step_voxels`).
clouds::CloudShadowMap make_shadow_map(const clouds::CloudField& field, const glm::dvec3& light_direction_enu,
                                       int texels = 256, float step_voxels = 2.0f, int threads = 1);

}  // namespace atmo::abi
