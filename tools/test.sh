#!/usr/bin/env bash
# The whole test suite on a fresh Debian 12 machine: install what is missing,
# build, run every test (GL tests run headless on Mesa llvmpipe through EGL and
# fail, never skip, without a context), then the same suite built with
# AddressSanitizer + UndefinedBehaviorSanitizer, then the libFuzzer targets
# (fuzz/, built by clang; each fuzzes for ATMO_FUZZ_SECONDS).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
jobs=$(nproc)

echo "[atmo] release build and tests"
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo
cmake --build build -j"$jobs"
ctest --test-dir build -j"$jobs" --output-on-failure --output-junit "$PWD/build/ctest-junit.xml"
python3 tools/check_no_skips.py build/ctest-junit.xml  # no test skipped, disabled or not run

echo "[atmo] AddressSanitizer + UBSan build and tests"
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DATMO_SANITIZE=ON -DATMO_BUILD_BENCH=OFF
cmake --build build-asan -j"$jobs"
# Leaks inside Mesa/LLVM (llvmpipe's JIT) are not ours; see tests/lsan.supp.
# intercept_tls_get_addr=0: GCC 12's sanitizer runtime takes a dynamic TLS
# block whose start is 16 bytes past a page boundary for a pre-2.25 glibc
# header and reads garbage bounds from it, so LeakSanitizer's tracer dies at
# exit ("Tracer caught signal 11 ... DTLS 10 at 0x13b0-0x18000024b2") after
# the test passed. Where blocks land depends on the environment's size, so it
# came and went with the working directory. Fixed upstream in GCC 14/LLVM 17.
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1:intercept_tls_get_addr=0"
export LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
# Left out of the sanitizer run, and run in the release suite above (docs/TESTING.md, "What the sanitizer
# run leaves out"): tests whose time goes to numbers, not to code paths no other sanitized test drives --
# the depth-convention re-renders, the include-root compile probes, and accuracy sweeps against the
# Monte Carlo, the path tracer and the direct cloud march. 1 300 of its 2 800 CPU seconds at -O1.
asan_left_out='^(depth_|layering\.)|^FogMultipleScattering\.ModelAgainstMonteCarlo$|^CloudOctaves\.(StoredReferencesMatchThePathTracer|MultipleScatteringApproximationAgainstPathTracer)$|^CloudsPass\.The(Haze|HorizonSky)UnderAnOvercastDeckIsInItsShadow$|^CloudImpostors\.(FlightIntoTheLayerNeverDepartsFromTheDirectMarch|FreshImpostorsMatchTheDirectMarch|StaleImpostorsUnderTheThresholdStillMatch)$'
echo "[atmo] left out under the sanitizers (run in release): $(ctest --test-dir build-asan -N -R "$asan_left_out" -FA '.*' | tail -1)"
ctest --test-dir build-asan -j"$jobs" -E "$asan_left_out" --output-on-failure --output-junit "$PWD/build-asan/ctest-junit.xml"
python3 tools/check_no_skips.py build-asan/ctest-junit.xml

echo "[atmo] libFuzzer targets (clang, ASan + UBSan; docs/TESTING.md)"
cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DATMO_FUZZ=ON -DATMO_BUILD_TESTS=OFF -DATMO_BUILD_SAMPLES=OFF -DATMO_BUILD_BENCH=OFF
cmake --build build-fuzz -j"$jobs" --target atmo_fuzz_targets
ctest --test-dir build-fuzz -L fuzz -j"$jobs" --output-on-failure --output-junit "$PWD/build-fuzz/ctest-junit.xml"
python3 tools/check_no_skips.py build-fuzz/ctest-junit.xml
