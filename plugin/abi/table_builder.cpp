#include "abi/table_builder.h"

#include <chrono>
#include <cstdio>
#include <exception>
#include <utility>

namespace atmo::abi {

core::AtmosphereSettings TableKey::settings() const {
  core::AtmosphereSettings s;
  s.visibility_m = visibility_m;
  s.aerosol_scale_height_m = aerosol_scale_height_m;
  s.ground_albedo = ground_albedo;
  return s;
}

TableKey table_key(const core::AtmosphereSettings& air, double sphere_radius_m) {
  return TableKey{air.visibility_m, air.aerosol_scale_height_m, air.ground_albedo, sphere_radius_m};
}

std::string describe(const TableKey& key) {
  char text[160];
  std::snprintf(text, sizeof(text), "visibility %.0f m, aerosol scale height %.0f m, ground albedo %.3g, sphere radius %.0f km",
                key.visibility_m, key.aerosol_scale_height_m, key.ground_albedo, key.radius_m / 1000.0);
  return text;
}

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

std::string format(const char* pattern, const char* name, int width, int height, double value) {
  char text[160];
  std::snprintf(text, sizeof(text), pattern, name, width, height, value);
  return text;
}

// Progress of one table: the overall fraction (this table covers [from, from + share])
// and a debug line at each quarter.
core::TableBuildControl stage(const char* name, int width, int height, double from, double share,
                              const std::atomic<bool>* stop, const std::function<void(TableLogLine)>& emit,
                              std::atomic<double>* fraction) {
  core::TableBuildControl control;
  control.stop = stop;
  control.progress = [=, &emit, quarter = 1](double f) mutable {
    if (fraction) fraction->store(from + share * f, std::memory_order_relaxed);
    for (; quarter < 4 && f >= 0.25 * quarter; ++quarter) {
      emit({ATMO_LOG_DEBUG, format("atmo: %s %dx%d: %.0f %%", name, width, height, 25.0 * quarter)});
    }
  };
  return control;
}

}  // namespace

bool build_tables(const TableKey& key, const std::atomic<bool>* stop, const std::function<void(TableLogLine)>& emit,
                  std::atomic<double>* fraction, AtmosphereTables* out, const std::string& where) {
  const Clock::time_point start = Clock::now();
  if (fraction) fraction->store(0.0, std::memory_order_relaxed);
  emit({ATMO_LOG_INFO, "atmo: building atmosphere tables (" + describe(key) + ") " + where});
  // The tables depend on the air and the sphere only, not on the sun's distance.
  const twin::AtmosphereParameters atm = core::make_atmosphere_parameters(key.settings(), key.radius_m, 1.0);

  // Shares of the overall fraction: the two tables take about as long (PERFORMANCE.md).
  const int tw = core::kTransmittanceWidth, th = core::kTransmittanceHeight;
  Clock::time_point t0 = Clock::now();
  twin::Lut2D transmittance = core::compute_transmittance_table(
      atm, tw, th, 256, stage("transmittance", tw, th, 0.0, 0.5, stop, emit, fraction));
  if (transmittance.width == 0) return false;  // stopped
  emit({ATMO_LOG_INFO, format("atmo: %s %dx%d ... done in %.0f ms", "transmittance", tw, th, ms_since(t0))});

  const int mw = core::kMultipleScatteringWidth, mh = core::kMultipleScatteringHeight;
  t0 = Clock::now();
  twin::Lut2D multiple_scattering = core::compute_multiple_scattering_table(
      atm, transmittance, mw, mh, 64, 20, stage("multiple scattering", mw, mh, 0.5, 0.5, stop, emit, fraction));
  if (multiple_scattering.width == 0) return false;
  emit({ATMO_LOG_INFO, format("atmo: %s %dx%d ... done in %.0f ms", "multiple scattering", mw, mh, ms_since(t0))});

  out->key = key;
  out->transmittance = std::move(transmittance);
  out->multiple_scattering = std::move(multiple_scattering);
  out->build_ms = ms_since(start);
  if (fraction) fraction->store(1.0, std::memory_order_relaxed);
  return true;
}

void TableWorker::request(const TableKey& key) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (stopping_) return;
  if (failed_ && *failed_ != key) failed_.reset();  // a failed key is retried once the air has moved on
  if (running_ && *running_ == key && !cancel_.load()) {
    waiting_.reset();  // the newest wish is the one being built
    return;
  }
  if ((waiting_ && *waiting_ == key) || (failed_ && *failed_ == key) || (finished_ && finished_->key == key)) return;
  waiting_ = key;
  if (thread_.joinable()) {
    wake_.notify_one();
  } else {
    thread_ = std::thread(&TableWorker::run, this);  // waits for the lock we hold
  }
}

void TableWorker::cancel_all() {
  std::lock_guard<std::mutex> lock(mutex_);
  waiting_.reset();
  finished_.reset();
  if (running_) cancel_.store(true);
  idle_.notify_all();
}

bool TableWorker::take_finished(AtmosphereTables* out) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!finished_) return false;
  *out = std::move(*finished_);
  finished_.reset();
  return true;
}

std::vector<TableLogLine> TableWorker::take_messages() {
  std::vector<TableLogLine> lines;
  std::lock_guard<std::mutex> lock(mutex_);
  lines.swap(messages_);
  return lines;
}

bool TableWorker::busy() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return running_.has_value() || waiting_.has_value();
}

void TableWorker::wait_idle() {
  std::unique_lock<std::mutex> lock(mutex_);
  idle_.wait(lock, [&] { return (!running_ && !waiting_) || stopping_ || !thread_.joinable(); });
}

void TableWorker::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
    waiting_.reset();
    cancel_.store(true);
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
  idle_.notify_all();
}

uint64_t TableWorker::builds_started() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return builds_started_;
}

void TableWorker::run() {
  // Lines go to the queue as they happen, so the host's thread can flush them while the build runs.
  const std::function<void(TableLogLine)> emit = [this](TableLogLine line) {
    std::lock_guard<std::mutex> lock(mutex_);
    messages_.push_back(std::move(line));
  };
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    wake_.wait(lock, [&] { return stopping_ || waiting_.has_value(); });
    if (stopping_) break;
    const TableKey key = *waiting_;
    waiting_.reset();
    running_ = key;
    cancel_.store(false);
    fraction_.store(0.0, std::memory_order_relaxed);
    ++builds_started_;
    lock.unlock();

    AtmosphereTables tables;
    bool built = false;
    std::string error;
    try {
      if (test_before_build) test_before_build(cancel_);
      built = !cancel_.load() &&
              build_tables(key, &cancel_, emit, &fraction_, &tables,
                           "on a worker thread; frames keep the current air until they are ready");
    } catch (const std::exception& e) {
      error = e.what();
    } catch (...) {
      error = "unknown exception";
    }

    lock.lock();
    running_.reset();
    try {
      if (built && !cancel_.load()) {
        finished_ = std::move(tables);  // replaces older tables nobody took
      } else if (!error.empty()) {
        failed_ = key;
        messages_.push_back({ATMO_LOG_WARNING, "atmo: building atmosphere tables (" + describe(key) +
                                                   ") failed: " + error + "; keeping the tables in use"});
      } else {
        messages_.push_back({ATMO_LOG_INFO, "atmo: atmosphere table build (" + describe(key) + ") cancelled" +
                                                (stopping_ ? " (context destroyed)" : "")});
      }
    } catch (...) {
      // Out of memory for a log line: the line is lost, the worker goes on.
    }
    if (!waiting_) idle_.notify_all();
  }
  running_.reset();
  idle_.notify_all();
}

}  // namespace atmo::abi
