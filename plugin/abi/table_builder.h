// table_builder.h — the CPU lookup tables of a context (transmittance and
// multiple scattering, ~0.4 s of CPU to build: docs/ABI.md) and the worker thread that rebuilds
// them off the render thread when the air changes.
//
// Threads: the host's thread (the one calling the plugin) asks for tables,
// takes finished ones and logs; one worker thread per context builds. The
// worker touches only its own copies (the key it builds, the tables it makes)
// and hands them over under a mutex; it never calls the host (the log service
// may only be called on threads the host calls the plugin on), so its progress
// lines wait in a queue until the host's thread flushes them. No GL here.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "atmo/atmo.h"
#include "core/atmosphere/atmosphere_model.h"

namespace atmo::abi {

// What the tables depend on: the air, the ground albedo and the model sphere.
struct TableKey {
  double visibility_m = -1, aerosol_scale_height_m = -1, ground_albedo = -1, radius_m = -1;

  bool operator==(const TableKey& o) const {
    return visibility_m == o.visibility_m && aerosol_scale_height_m == o.aerosol_scale_height_m &&
           ground_albedo == o.ground_albedo && radius_m == o.radius_m;
  }
  bool operator!=(const TableKey& o) const { return !(*this == o); }
  bool valid() const { return radius_m > 0.0; }
  core::AtmosphereSettings settings() const;
};

TableKey table_key(const core::AtmosphereSettings& air, double sphere_radius_m);

// "visibility 40000 m, aerosol scale height 1200 m, ground albedo 0.1, sphere radius 6370 km"
std::string describe(const TableKey& key);

// A finished pair of tables and what they were built for.
struct AtmosphereTables {
  TableKey key;
  twin::Lut2D transmittance;
  twin::Lut2D multiple_scattering;
  double build_ms = 0.0;  // both tables, on the thread that built them
};

struct TableLogLine {
  AtmoLogSeverity severity;
  std::string text;
};

// Builds both tables for `key` on the calling thread. `emit` gets the progress
// lines on the calling thread (the start, with `where`; each table's time at
// info level; its quarters at debug level); `fraction` (may be null) follows
// the build from 0 to 1. False, and *out untouched, when *stop became true
// (checked per table row; stop may be null).
bool build_tables(const TableKey& key, const std::atomic<bool>* stop,
                  const std::function<void(TableLogLine)>& emit, std::atomic<double>* fraction,
                  AtmosphereTables* out, const std::string& where);

// One worker thread, started on the first request, building one pair of tables
// at a time. A request while a build runs waits (only the newest: it replaces
// any request already waiting) and starts when the running build ends.
class TableWorker {
 public:
  TableWorker() = default;
  ~TableWorker() { stop(); }
  TableWorker(const TableWorker&) = delete;
  TableWorker& operator=(const TableWorker&) = delete;

  // Tables for `key`: built now if the worker is idle, else next (replacing
  // what was waiting). Nothing if `key` is already running or waiting, or its
  // build failed before (out of memory: no retry every frame).
  void request(const TableKey& key);
  // Drops the waiting request and cancels the running build (its result is
  // discarded): the air went back to the tables in use.
  void cancel_all();
  // The newest finished tables not taken yet, if any.
  bool take_finished(AtmosphereTables* out);
  // Progress lines the worker wrote since the last call, oldest first.
  std::vector<TableLogLine> take_messages();
  // A build runs or waits.
  bool busy() const;
  // Blocks until no build runs or waits (tests, offline rendering).
  void wait_idle();
  // Cancels the running build (promptly: checked per table row), drops the
  // waiting one and joins the thread. Idempotent; the destructor calls it.
  void stop();
  // Fraction of the running build done, in [0, 1].
  double progress() const { return fraction_.load(std::memory_order_relaxed); }
  // Builds the worker started (for tests).
  uint64_t builds_started() const;

  // Test hook: when set (before the request that starts the thread), called
  // on the worker at the start of each build, before any work, with the flag
  // that cancels it. A test blocks here to hold a build.
  std::function<void(const std::atomic<bool>& cancel)> test_before_build;

 private:
  void run();

  mutable std::mutex mutex_;
  std::condition_variable wake_;  // the worker waits for a request or stop
  std::condition_variable idle_;  // wait_idle waits for the worker
  std::thread thread_;
  bool stopping_ = false;
  std::atomic<bool> cancel_{false};  // cancels the running build (stop, cancel_all)
  std::optional<TableKey> running_, waiting_, failed_;
  std::optional<AtmosphereTables> finished_;
  std::vector<TableLogLine> messages_;
  std::atomic<double> fraction_{0.0};
  uint64_t builds_started_ = 0;
};

}  // namespace atmo::abi
