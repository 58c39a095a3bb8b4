#!/usr/bin/env bash
# The README's test command and what .ci/run calls: installs dependencies, checks the include
# floors, then builds and runs every test:
#   release     every suite (-O3 libraries; the test code itself at -O1);
#   asan        one clang build with ASan + UBSan over everything and libFuzzer coverage over the
#               parsers (tools/sanitizer-builds.sh): every suite labelled sanitize, then the fuzz
#               targets' kept crash inputs and 20 s of fuzzing each (tools/fuzz.sh);
#   tsan        every suite labelled tsan under ThreadSanitizer.
# Prints the time of each stage at the end (also when a stage fails). The longer fuzzing and the
# full soak are tools/run-tests-long.sh.
# Environment: JOBS (tests at once, default nproc), BUILD_JOBS (compile jobs, default JOBS + 1:
# one more than the cores keeps them busy through links, PCH loads and the test discovery steps),
# DAMMLOAM_SKIP_SANITIZERS=1 (release only),
# DAMMLOAM_SKIP_FUZZ=1 (no fuzzing), FUZZ_SECONDS (default 10; tools/run-tests-long.sh fuzzes 600 s each),
# DAMMLOAM_UNITY_BUILD=OFF (file by file; default ON, see tools/sanitizer-builds.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
JOBS=${JOBS:-$(nproc)}
BUILD_JOBS=${BUILD_JOBS:-$((JOBS + 1))}
source tools/sanitizer-builds.sh

STAGES=()
RUN_START=$(date +%s)
stage_start=$RUN_START
stage_name=""
begin() {  # begin NAME: ends the stage before, starts NAME
  local now
  now=$(date +%s)
  if [ -n "$stage_name" ]; then STAGES+=("$(printf '%-34s %5d s' "$stage_name" $((now - stage_start)))"); fi
  stage_name=$1
  stage_start=$now
  echo "== $1"
}
report() {
  local rc=$? now
  now=$(date +%s)
  if [ -n "$stage_name" ]; then
    STAGES+=("$(printf '%-34s %5d s%s' "$stage_name" $((now - stage_start)) "$([ $rc -ne 0 ] && echo '  FAILED')")")
  fi
  echo "== stage times"
  printf '%s\n' "${STAGES[@]}"
  printf '%-34s %5d s (%d min)\n' total $((now - RUN_START)) $(((now - RUN_START + 59) / 60))
  if [ $rc -eq 0 ]; then echo "== all tests passed"; else echo "== FAILED (exit $rc)"; fi
}
trap report EXIT

begin "dependencies (apt)"
bash deploy/install-deps.sh

# core <- drivers, io <- services <- tools: no include or link runs up a floor.
begin "include floors"
bash tools/check-floors.sh

begin "release: build"
configure_ninja build -DCMAKE_BUILD_TYPE=Release -DDAMMLOAM_BUILD_TESTS=ON
cmake --build build -j"$BUILD_JOBS"
begin "release: tests"
ctest --test-dir build --output-on-failure -j"$JOBS"

if [ "${DAMMLOAM_SKIP_SANITIZERS:-0}" != "1" ]; then
  # Everything that parses outside bytes or runs the algorithm: packet decoders and pcap
  # (drivers), DDS sample checks and the daemon's config (system), back-end and map store
  # (backend), YAML/sequence/PCD I/O (tools), recorded bags (bag), the runner, the core and the
  # simulator: every suite labelled sanitize. The DDS end-to-end suites (label system, not
  # sanitize) stay in the release run: they drive whole processes over loopback and parse nothing
  # the unit suites do not.
  begin "asan+ubsan: build (+ fuzz targets)"
  configure_asan build-asan
  asan_targets=(dammloam_tests_sanitize dammloam-evaluate dammloam-simulate dammloam-odometry
    dammloam-driver)
  if [ "${DAMMLOAM_SKIP_FUZZ:-0}" != "1" ]; then asan_targets+=(dammloam_fuzzers); fi
  target_args=()
  for t in "${asan_targets[@]}"; do target_args+=(--target "$t"); done
  cmake --build build-asan -j"$BUILD_JOBS" "${target_args[@]}"
  begin "asan+ubsan: tests"
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --test-dir build-asan --output-on-failure -j"$JOBS" -L sanitize -E "$ASAN_LONG_DRIVES"

  if [ "${DAMMLOAM_SKIP_FUZZ:-0}" != "1" ]; then
    # libFuzzer targets of every parser of outside bytes (tests/fuzz), from the same build: the
    # kept crash inputs of tests/fuzz/regressions are replayed, then FUZZ_SECONDS of fuzzing each.
    begin "fuzz: ${FUZZ_SECONDS:-10} s per target"
    FUZZ_BUILD_DIR=build-asan JOBS="$JOBS" bash tools/fuzz.sh "${FUZZ_SECONDS:-10}"
  fi

  # The daemon's threaded pipeline and its queues (system), the threaded use of the odometry
  # (odometry) and the back-end's loop closure thread (backend).
  begin "tsan: build"
  # Exported for the build too: gtest test discovery runs the instrumented test binaries.
  export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:suppressions=$PWD/tests/support/tsan.supp"
  configure_tsan build-tsan
  cmake --build build-tsan -j"$BUILD_JOBS" --target dammloam_tests_tsan
  begin "tsan: tests"
  ctest --test-dir build-tsan --output-on-failure -j"$JOBS" -L tsan -E "$TSAN_SINGLE_THREADED"
fi
