#pragma once
// Splits [0, n) into contiguous bands, one per thread, for work whose items
// are independent and each written by one thread: the result does not depend
// on the thread count (the caller keeps any sum inside one item).
#include <algorithm>
#include <exception>
#include <thread>
#include <vector>

namespace atmo::clouds {

// How many bands for_bands cuts [0, n) into for `threads` threads.
inline int band_count(int n, int threads) { return std::clamp(threads, 1, std::max(1, n)); }

// Calls fn(band, begin, end) for band_count(n, threads) bands of [0, n),
// band b being [b n / bands, (b + 1) n / bands); band 0 runs on the calling
// thread. Returns when all have finished; an exception from a band is
// rethrown here (the lowest band's first).
template <typename Fn>
void for_numbered_bands(int n, int threads, const Fn& fn) {
  const int bands = band_count(n, threads);
  std::vector<std::exception_ptr> errors(static_cast<size_t>(bands));
  auto run = [&](int b) {
    try {
      fn(b, b * n / bands, (b + 1) * n / bands);
    } catch (...) {
      errors[static_cast<size_t>(b)] = std::current_exception();
    }
  };
  std::vector<std::thread> helpers;
  helpers.reserve(static_cast<size_t>(bands - 1));
  for (int b = 1; b < bands; ++b) helpers.emplace_back(run, b);
  run(0);
  for (std::thread& h : helpers) h.join();
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
}

// As for_numbered_bands, fn(begin, end).
template <typename Fn>
void for_bands(int n, int threads, const Fn& fn) {
  for_numbered_bands(n, threads, [&](int, int begin, int end) { fn(begin, end); });
}

}  // namespace atmo::clouds
