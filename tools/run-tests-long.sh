#!/usr/bin/env bash
# What does not fit the test command's half hour (README): the release and sanitizer suites of
# tools/run-tests.sh, the thirteen long drives that it runs in release only (here under ASan+UBSan
# too), longer fuzzing of every parser (FUZZ_SECONDS per target, default 600, two targets at a
# time) and the full soak (dammloam-soak: 10,000 VLP-16 scans at 20 Hz through dammloamd, the
# publisher SIGKILLed and restarted, malformed samples, save_map every 1000 scans, RSS growth
# checked). About 1.5 hours on 2 cores (the test command, ~15 min of long drives, 30 min of
# fuzzing, ~9 min soak). Environment: as tools/run-tests.sh, plus FUZZ_SECONDS, SOAK_SCANS.
set -euo pipefail
cd "$(dirname "$0")/.."
JOBS=${JOBS:-$(nproc)}
source tools/sanitizer-builds.sh
DAMMLOAM_SKIP_FUZZ=1 bash tools/run-tests.sh

echo "== the long drives under ASan+UBSan"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --test-dir build-asan --output-on-failure -j"$JOBS" -R "$ASAN_LONG_DRIVES"

echo "== long fuzzing: ${FUZZ_SECONDS:-600} s per target"
FUZZ_BUILD_DIR=build-asan JOBS="$JOBS" bash tools/fuzz.sh "${FUZZ_SECONDS:-600}"

echo "== full soak: ${SOAK_SCANS:-10000} scans"
mkdir -p out/soak
CYCLONEDDS_URI=file://$PWD/deploy/cyclonedds-loopback.xml build/bin/dammloam-soak \
  --scans "${SOAK_SCANS:-10000}" --save-every 1000 --domain 197 --max-rss-growth 10 \
  --rss-csv out/soak/rss.csv --json out/soak/report.json
echo "== long tests passed"
