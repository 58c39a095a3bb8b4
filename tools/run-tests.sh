#!/usr/bin/env bash
# Installs dependencies, checks the include floors, builds and runs every test: the release
# build, then the core and tool suites again under ASan+UBSan, then the threaded pipeline suites
# under TSan, then a short run of the fuzz targets (tools/fuzz.sh).
# This is the README's test command and what .ci/run calls.
set -euo pipefail
cd "$(dirname "$0")/.."
JOBS=${JOBS:-$(nproc)}

bash deploy/install-deps.sh

# Include floors (core <- drivers, io <- services <- tools): no include or link runs up a floor.
echo "== include floors"
bash tools/check-floors.sh

echo "== release build + all tests"
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DDAMMLOAM_BUILD_TESTS=ON >/dev/null
cmake --build build -j"$JOBS"
ctest --test-dir build --output-on-failure -j"$JOBS"

if [ "${DAMMLOAM_SKIP_SANITIZERS:-0}" != "1" ]; then
  # Everything that parses outside bytes or runs the algorithm, again under AddressSanitizer +
  # UBSan: packet decoders and pcap (drivers), DDS sample checks and the daemon's config
  # (system), back-end and map store (backend), YAML/sequence/PCD I/O (tools), the runner, the
  # core and the simulator: every suite labelled sanitize. The DDS end-to-end suites (label
  # system, not sanitize) stay in the release run: they drive whole processes over loopback and
  # parse nothing the unit suites do not.
  echo "== ASan+UBSan build + tests (all areas; DDS end-to-end suites excluded)"
  cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDAMMLOAM_SANITIZE=ON \
    -DDAMMLOAM_TEST_AREAS="geometry;core;odometry;tools;sim;drivers;backend;runner;system" >/dev/null
  cmake --build build-asan -j"$JOBS" --target dammloam_tests_sanitize dammloam-evaluate \
    dammloam-simulate dammloam-odometry dammloam-driver
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --test-dir build-asan --output-on-failure -j"$JOBS" -L sanitize

  # Every suite labelled tsan under ThreadSanitizer: the daemon's threaded pipeline and its
  # queues (system), the threaded use of the odometry (odometry) and the back-end's loop
  # closure thread (backend).
  echo "== TSan build + tests labelled tsan"
  # Exported for the build too: gtest test discovery runs the instrumented test binaries.
  export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:suppressions=$PWD/tests/support/tsan.supp"
  cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDAMMLOAM_TSAN=ON \
    -DDAMMLOAM_TEST_AREAS="system;odometry;backend" >/dev/null
  cmake --build build-tsan -j"$JOBS" --target dammloam_tests_tsan
  ctest --test-dir build-tsan --output-on-failure -j"$JOBS" -L tsan
fi

if [ "${DAMMLOAM_SKIP_FUZZ:-0}" != "1" ]; then
  # libFuzzer targets of every parser of outside bytes (tests/fuzz, clang + ASan + UBSan): the
  # kept crash inputs of tests/fuzz/regressions are replayed, then 20 s of fuzzing per target.
  echo "== fuzz targets (20 s each)"
  JOBS="$JOBS" bash tools/fuzz.sh 20
fi
echo "== all tests passed"
