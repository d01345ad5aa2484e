#!/usr/bin/env bash
# The whole test suite on a fresh Debian 12 machine: install what is missing,
# build, run every test (GL tests run headless on Mesa llvmpipe through EGL and
# fail, never skip, without a context), then the same suite built with
# AddressSanitizer + UndefinedBehaviorSanitizer.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
jobs=$(nproc)

echo "[atmo] release build and tests"
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo
cmake --build build -j"$jobs"
ctest --test-dir build -j"$jobs" --output-on-failure

echo "[atmo] AddressSanitizer + UBSan build and tests"
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DATMO_SANITIZE=ON -DATMO_BUILD_BENCH=OFF
cmake --build build-asan -j"$jobs"
# Leaks inside Mesa/LLVM (llvmpipe's JIT) are not ours; see tests/lsan.supp.
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1"
export LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
if ! ctest --test-dir build-asan -j"$jobs" --output-on-failure 2>&1 | tee build-asan/ctest-first-run.log; then
  # LeakSanitizer's own tracer now and then crashes at exit while llvmpipe's
  # threads wind down ("Tracer caught signal 11 ... LeakSanitizer has
  # encountered a fatal error") after the test itself passed. Failed tests
  # are run once more, named here; a real failure fails again.
  echo "[atmo] AddressSanitizer run: re-running the failed tests once:"
  grep -E "^\s+[0-9]+ - " build-asan/ctest-first-run.log || true
  grep -c "LeakSanitizer has encountered a fatal error" build-asan/ctest-first-run.log \
    | sed 's/^/[atmo] LeakSanitizer tracer crashes in the first run: /' || true
  ctest --test-dir build-asan --rerun-failed --output-on-failure
fi
