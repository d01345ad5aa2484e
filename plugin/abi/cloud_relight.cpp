#include "abi/cloud_relight.h"

#include <chrono>

#ifdef __linux__
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>
#endif

#include "core/clouds/field_light.h"

namespace atmo::abi {

namespace {
constexpr int kSlab = 8;  // z-slices between checks of the cancel flag (set_clouds, destroy)
constexpr int kWorkerNice = 10;  // the workers' niceness (Linux: per thread)
}  // namespace

void relight_all(const clouds::CloudField& field, const glm::dvec3& dir, std::vector<clouds::LightDepths>* depths,
                 const std::atomic<bool>* cancel, const clouds::FieldNeighbours* neighbours) {
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
    const clouds::FieldLightPlan plan = clouds::plan_field_light(field, static_cast<int>(p), dir, {}, neighbours);
    if (plan.prototype < 0) continue;
    const int nz = field.prototypes[p].density.nz;
    for (int z = 0; z < nz; z += kSlab) {
      if (cancel && cancel->load(std::memory_order_relaxed)) return;
      clouds::add_field_light_slices(field, plan, z, std::min(nz, z + kSlab), &(*depths)[p]);
    }
  }
}

clouds::CloudShadowMap make_shadow_map(const clouds::CloudField& field, const glm::dvec3& dir, int texels,
                                       float step_voxels, int threads) {
  return clouds::compute_cloud_shadow_map(field, dir, texels, 100000.0, step_voxels, threads);
}

CloudWorkerThread::CloudWorkerThread(Body body)
    : thread_([this, body = std::move(body)] {
#ifdef __linux__
        // Below the host's threads (and the GL driver's): on a busy machine the
        // set-up takes longer rather than the frames.
        setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), kWorkerNice);
#endif
        const auto t0 = std::chrono::steady_clock::now();
        body(cancel_);
        elapsed_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        done_.store(true, std::memory_order_release);
      }) {}

CloudWorkerThread::~CloudWorkerThread() {
  cancel_.store(true);
  if (thread_.joinable()) thread_.join();
}

void CloudWorkerThread::wait() {
  if (thread_.joinable()) thread_.join();
}

CloudRelightJob::CloudRelightJob(const clouds::CloudField* field, std::vector<clouds::LightDepths> depths,
                                 RelightRequest request)
    : field_(field),
      depths_(std::move(depths)),
      request_(std::move(request)),
      thread_([this](const std::atomic<bool>& cancel) { run(cancel); }) {}

void CloudRelightJob::run(const std::atomic<bool>& cancel) {
  const clouds::CloudField& field = *field_;
  const glm::dvec3& dir = request_.light_direction_enu;
  if (request_.with_ambient) {
    depths_.resize(field.prototypes.size());
    for (size_t p = 0; p < field.prototypes.size(); ++p) {
      if (cancel.load(std::memory_order_relaxed)) return;
      clouds::compute_ambient_depths(field.prototypes[p], &depths_[p],
                                     p < request_.sides.size() ? request_.sides[p] : clouds::ContinuingSides{});
    }
  }
  relight_all(field, dir, &depths_, &cancel, request_.neighbours.index ? &request_.neighbours : nullptr);
  if (request_.with_shadow && !cancel.load()) shadow_ = make_shadow_map(field, dir);
  if (request_.with_mips && !cancel.load())
    mips_ = std::make_shared<const std::vector<clouds::PrototypeMips>>(clouds::build_prototype_mips(field, depths_, dir));
}

CloudClipmapJob::CloudClipmapJob(ClipmapRequest request)
    : request_(std::move(request)), thread_([this](const std::atomic<bool>& cancel) {
        const ClipmapRequest& r = request_;
        clipmap_ = clouds::build_clipmap(*r.field, *r.mips, *r.index, r.spec, r.geometry, r.cell, &cancel);
      }) {}

CloudFieldJob::CloudFieldJob(Build build)
    : build_(std::move(build)),
      thread_([this](const std::atomic<bool>& cancel) { field_ = build_(cancel); }) {}

}  // namespace atmo::abi
