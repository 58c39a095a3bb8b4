#!/usr/bin/env bash
# Builds the libFuzzer targets of tests/fuzz (clang-14, ASan+UBSan, -DDAMMLOAM_FUZZ=ON) and runs
# each for SECONDS: its seed corpus is written first (from ../shared/data captures when that
# folder exists, and from inline/synthetic inputs made by the project's own code always), the
# kept crash inputs of tests/fuzz/regressions/<target>/ are replayed, then the fuzzer runs.
#
#   bash tools/fuzz.sh SECONDS [TARGET...]     targets: ouster velodyne pcap point_cloud map_store config mcap
#                                             pointcloud2_cdr ros1_bag ply
#
# Environment: FUZZ_BUILD_DIR (default build-asan, shared with tools/run-tests.sh), JOBS (build
# jobs and targets fuzzed at once, default 1).
# Per target: <build>/fuzz-work/<target>/{seeds,corpus,artifacts,fuzz.log,<target>.dict}; the
# corpus is kept between runs. Exits non-zero when any target crashes (or a regression input
# crashes again), printing the crash file. One summary line per target.
set -euo pipefail
cd "$(dirname "$0")/.."

ALL_TARGETS=(ouster velodyne pcap point_cloud map_store config mcap pointcloud2_cdr ros1_bag ply)
usage() { echo "usage: bash tools/fuzz.sh SECONDS [TARGET...]   (targets: ${ALL_TARGETS[*]})" >&2; exit 2; }
[ $# -ge 1 ] || usage
SECONDS_PER_TARGET=$1
shift
[[ "$SECONDS_PER_TARGET" =~ ^[0-9]+$ ]] && [ "$SECONDS_PER_TARGET" -gt 0 ] || usage
TARGETS=("$@")
[ ${#TARGETS[@]} -gt 0 ] || TARGETS=("${ALL_TARGETS[@]}")
for t in "${TARGETS[@]}"; do
  [[ " ${ALL_TARGETS[*]} " == *" $t "* ]] || { echo "fuzz: unknown target '$t'" >&2; usage; }
done

BUILD=${FUZZ_BUILD_DIR:-build-asan}
# UBSan reports with their stack (every report aborts: the build has -fno-sanitize-recover).
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1}
JOBS=${JOBS:-1}
for tool in clang-14 clang++-14; do
  command -v "$tool" >/dev/null || { echo "fuzz: $tool not found (bash deploy/install-deps.sh)" >&2; exit 1; }
done

# The ASan+UBSan build of tools/run-tests.sh (tools/sanitizer-builds.sh): when it ran before, only
# the fuzz targets that are not up to date are built.
source tools/sanitizer-builds.sh
echo "== fuzz: configure + build ($BUILD, -j$JOBS): ${TARGETS[*]}"
mkdir -p "$BUILD"
configure_asan "$BUILD" >"$BUILD/configure-fuzz.log" 2>&1 || { cat "$BUILD/configure-fuzz.log" >&2; exit 1; }
build_targets=()
for t in "${TARGETS[@]}"; do build_targets+=(--target "fuzz_$t"); done
cmake --build "$BUILD" -j"$JOBS" "${build_targets[@]}"

SHARED=""
if [ -d ../shared/data ]; then SHARED=$(cd ../shared/data && pwd); fi
echo "== fuzz: seeds from ${SHARED:-inline inputs only (no ../shared/data)}"

# Largest input per target: a metadata JSON / calibration YAML plus a few packets, a pcap's
# first records, a small map directory, a config file.
max_len() {
  case $1 in
    ouster | velodyne | pcap) echo 65536 ;;
    point_cloud | pointcloud2_cdr) echo 8192 ;;
    mcap | ros1_bag) echo 65536 ;;
    ply) echo 16384 ;;
    map_store | config) echo 16384 ;;
  esac
}

# Dictionary: the keys and keywords the parser compares against, taken from its source (so it
# follows the code), plus the format's punctuation.
write_dict() {
  local target=$1 out=$2 sources=() extra=()
  case $target in
    ouster) sources=(drivers/ouster/metadata.cpp)
            extra=('{' '}' '[' ']' '":' '-1' '1e308' 'null' 'true' '"1024x10"' '"x"') ;;
    velodyne) sources=(drivers/velodyne/calibration.cpp)
              extra=(': ' '- ' '{' '}' '[' ']' '.nan' '.inf' '-.inf' '~' '&a ' '*a' '!!str ' '? ' '1e308') ;;
    map_store) sources=(io/mapstore/map_store.cpp)
               extra=('VERSION 0.7' 'FIELDS' 'SIZE' 'TYPE' 'COUNT' 'WIDTH' 'HEIGHT' 'VIEWPOINT'
                      'POINTS' 'DATA ascii' 'DATA binary' 'DATA binary_compressed' 'DMKF' 'END!'
                      '{' '}' '":' '1e308' '-1') ;;
    config) sources=(io/config_yaml.cpp io/backend_config_yaml.cpp services/dammloamd/daemon_config.cpp)
            extra=(': ' '- ' '{' '}' '[' ']' '.nan' '.inf' '-.inf' '~' '&a ' '*a' '!!str ' '? ' '<<: '
                   '1e308' '-1' 'true' 'false' 'auto' 'off') ;;
    mcap) sources=(io/bag/mcap_reader.cpp io/bag/decompress.cpp io/bag/bag_scans.cpp)
          extra=('MCAP0' 'zstd' 'lz4' 'ros2msg' 'cdr' 'ros2' 'sensor_msgs/msg/PointCloud2') ;;
    ros1_bag) sources=(io/bag/ros1_bag.cpp io/bag/decompress.cpp)
              extra=('#ROSBAG V2.0' 'op=' 'index_pos=' 'conn=' 'topic=' 'type=' 'time=' 'compression='
                     'size=' 'none' 'bz2' 'lz4' 'BZh9' 'sensor_msgs/PointCloud2') ;;
    ply) sources=(io/ply.cpp)
         extra=('ply' 'format ascii 1.0' 'format binary_little_endian 1.0' 'element vertex '
                'property float ' 'property double ' 'property list uchar int ' 'end_header' 'comment'
                'intensity' 'time' 'ring' 'nan' 'inf' '1e308') ;;
    pointcloud2_cdr) sources=(core/cloud/point_cloud2.cpp)
                     extra=('x' 'y' 'z' 'intensity' 't' 'time' 'time_stamp' 'timestamp' 'ring'
                            'channel' 'lidar') ;;
    *) return 1 ;;
  esac
  {
    grep -ohE '"[A-Za-z_][A-Za-z0-9_]*"' "${sources[@]}" | sort -u
    for e in "${extra[@]}"; do
      printf '"%s"\n' "$(printf '%s' "$e" | sed 's/\\/\\\\/g; s/"/\\"/g')"
    done
  } >"$out"
}

# Scratch files of the targets (inputs written as files): in /dev/shm when there is one, removed
# at the end even when a target crashed (its own exit handler does not run then).
scratch_base=/tmp
if [ -d /dev/shm ] && [ -w /dev/shm ]; then scratch_base=/dev/shm; fi
DAMMLOAM_FUZZ_SCRATCH=$(mktemp -d "$scratch_base/dammloam-fuzz-run-XXXXXX")
export DAMMLOAM_FUZZ_SCRATCH
trap 'rm -rf "$DAMMLOAM_FUZZ_SCRATCH"' EXIT

# fuzz_one TARGET: writes the target's summary line to <work>/summary; exits non-zero when it
# crashed (or a kept input crashes again).
fuzz_one() {
  local t=$1 bin="$BUILD/fuzz/fuzz_$t" work="$BUILD/fuzz-work/$t"
  mkdir -p "$work/corpus" "$work/artifacts"
  rm -rf "$work/seeds" "$work/summary"
  DAMMLOAM_FUZZ_SEEDS="$work/seeds" DAMMLOAM_FUZZ_SHARED_DATA="$SHARED" "$bin" >"$work/seeds.log" 2>&1 ||
    { cat "$work/seeds.log" >&2; echo "fuzz $t: writing the seed corpus failed" >&2
      echo "fuzz $t: SEED CORPUS FAILED (log $work/seeds.log)" >"$work/summary"; return 1; }
  local common=(-timeout=10 -rss_limit_mb=2048 -max_len="$(max_len "$t")")
  local dict=()
  if write_dict "$t" "$work/$t.dict"; then dict=(-dict="$work/$t.dict"); fi

  # Kept crash inputs first: each must run clean now.
  local regressions=()
  shopt -s nullglob
  regressions=(tests/fuzz/regressions/"$t"/*)
  shopt -u nullglob
  if [ ${#regressions[@]} -gt 0 ]; then
    if ! "$bin" "${common[@]}" "${regressions[@]}" >"$work/regressions.log" 2>&1; then
      tail -n 60 "$work/regressions.log" >&2
      echo "fuzz $t: a regression input crashes again (tests/fuzz/regressions/$t/, log $work/regressions.log)" >&2
      echo "fuzz $t: REGRESSION CRASH (${#regressions[@]} kept inputs)" >"$work/summary"
      return 1
    fi
  fi

  echo "== fuzz $t: ${SECONDS_PER_TARGET} s ($(ls "$work/seeds" | wc -l) seeds, ${#regressions[@]} regression inputs)"
  local start rc elapsed runs speed corpus crash close_fd=0
  start=$(date +%s)
  # Stderr of the target itself (PCL's warnings, for the map store) is closed; libFuzzer and the
  # sanitizers keep their own channel.
  if [ "$t" = map_store ]; then close_fd=2; fi
  set +e
  "$bin" "${common[@]}" "${dict[@]}" -max_total_time="$SECONDS_PER_TARGET" -print_final_stats=1 \
    -close_fd_mask=$close_fd -artifact_prefix="$work/artifacts/" "$work/corpus" "$work/seeds" \
    >"$work/fuzz.log" 2>&1
  rc=$?
  set -e
  elapsed=$(( $(date +%s) - start ))
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$work/fuzz.log" | tail -n 1)
  speed=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$work/fuzz.log" | tail -n 1)
  corpus=$( (grep -oE 'corp: [0-9]+/[0-9]+[a-zA-Z]*' "$work/fuzz.log" || true) | tail -n 1 | sed 's/corp: //')
  if [ $rc -ne 0 ]; then
    crash=$(sed -n 's/.*Test unit written to \(.*\)$/\1/p' "$work/fuzz.log" | tail -n 1)
    grep -E 'ERROR: |SUMMARY: |FUZZ FINDING|==[0-9]+==|#[0-9]+ 0x' "$work/fuzz.log" | head -n 40 >&2 || true
    echo "fuzz $t: CRASH (exit $rc), input: ${crash:-none written} (log $work/fuzz.log)" >&2
    echo "fuzz $t: CRASH after ${runs:-?} runs, ${elapsed} s: ${crash:-see $work/fuzz.log}" >"$work/summary"
    return 1
  fi
  echo "fuzz $t: ${runs:-?} runs (${speed:-?} exec/s), corpus ${corpus:-?} inputs/bytes, ${elapsed} s, no crash" >"$work/summary"
}

# Each libFuzzer process is single-threaded: JOBS targets fuzz at once (one per core).
failed=0
running=0
for t in "${TARGETS[@]}"; do
  if [ "$running" -ge "$JOBS" ]; then
    wait -n || failed=1
    running=$((running - 1))
  fi
  fuzz_one "$t" &
  running=$((running + 1))
done
while [ "$running" -gt 0 ]; do
  wait -n || failed=1
  running=$((running - 1))
done

echo "== fuzz summary"
for t in "${TARGETS[@]}"; do
  cat "$BUILD/fuzz-work/$t/summary" 2>/dev/null || { echo "fuzz $t: NO RESULT"; failed=1; }
done
exit $failed
