# Sourced by tools/run-tests.sh, tools/fuzz.sh and tools/run-tests-long.sh: how the sanitizer
# builds are configured, in one place, so that the scripts share one build directory each.
#
# Both compile at -O1 -g1 (line tables for the reports' stacks): at -O2 -g the Eigen-heavy
# registration alone took over 10 minutes and 4.5 GB under GCC's ASan+UBSan; clang compiles the
# same file with ASan+UBSan in about a third of GCC's time.
#
# build-asan (clang-14): ASan + UBSan over everything, libFuzzer coverage over the parsers
#   (-DDAMMLOAM_FUZZ=ON): the suites labelled sanitize and the fuzz targets come from one build.
# build-tsan (clang-14): ThreadSanitizer over the areas whose suites are labelled tsan.
SANITIZER_CFLAGS="-O1 -g1 -DNDEBUG"

# Every build uses Ninja: unlike Make it starts a target's objects before the libraries it links
# are done, so both cores stay busy behind the long Eigen translation units.
# A build directory configured earlier with another generator gets a fresh cache.
# And every build of the test commands is a unity build (CMake joins up to 8 files of a target
# into one translation unit): the Eigen, standard-library and spdlog headers are parsed, and
# their inline functions compiled, once per batch instead of once per file. On a clean clone it
# took the release objects from 1829 to 1291 task-seconds and the ASan+UBSan ones from 2025 to
# 1402. DAMMLOAM_UNITY_BUILD=OFF builds file by file (what an IDE's incremental build does),
# which also shows a file that compiles only thanks to its batch's includes.
configure_ninja() {  # configure_ninja BUILD_DIR CMAKE_ARGS...
  local dir=$1
  shift
  if [ -f "$dir/CMakeCache.txt" ] && ! grep -q '^CMAKE_GENERATOR:INTERNAL=Ninja$' "$dir/CMakeCache.txt"; then
    rm -rf "$dir/CMakeCache.txt" "$dir/CMakeFiles"
  fi
  cmake -S . -B "$dir" -G Ninja "-DCMAKE_UNITY_BUILD=${DAMMLOAM_UNITY_BUILD:-ON}" "$@" >/dev/null
}

# Seventeen long drives run in the test command's release stage only, and under ASan+UBSan in
# tools/run-tests-long.sh: under ASan+UBSan they take 27-440 s each (up to 25x release), and every
# function they call is also run under ASan by the shorter drives of the same suites (corridor
# axis, start while moving, the corridor-return and repetitive-corridor loop closures), by the
# runner's saved-map localization (the relocalizer) and, for the benchmark's streaming runner, by
# the runner CLI's sequences (the same odometry per scan; the stream's own bookkeeping is plain
# vectors); the moving labels' 150-scan agreement with the simulator's truth by the 40-scan
# moving-class drive and the moving-points unit tests. The zigzag and outdoor drives and the
# outdoor loop closure (40, 27 and 57 s under ASan) joined them when the test command passed 30
# minutes: the corridor drives and the corridor-return loop run the same code. The 2 Hz corridor
# (140 registrations at 2 Hz) runs the same search and hold as the 2 Hz swing test. The two-floor
# walk (245 keyframes, twice) runs the verifier and the consistency test of the unit tests.
# Three more left when the test command reached 35 minutes (2026-12-06; 30, 26 and 24 s under
# ASan+UBSan): the scan turned by 90 degrees takes the lost path that the 2-second cover and the
# carried-elsewhere drives also take; every preset walked through the simulate CLI walks the
# library presets that Presets.EveryPresetStaysInsideItsScene runs, and the CLI's own parsing has
# its shorter tests; the SIGKILLs during saves run the map store's save that its other tests run.
ASAN_LONG_DRIVES='OdometryIntegration\.(MapSizeIsBoundedOnALongDrive|LongSparseCorridorDoesNotCollapseToStandstill|InterpolatedStartPosesFollowAHandHeldWalk|TheCorrespondenceGateFollowsTheSceneSize|PoseCovarianceGrowsAlongTheWeakAxisWhileItIsWeak|ZigzagCorridorIsTracked|OutdoorLoopIsTracked)|LoopClosure\.(LapsOverMappedGroundKeepPosesButNotClouds|OutdoorLoopHalvesApeAndAcceptsOnlyTrueLoops|TwoFloorsAreNeverJoined)|Relocalization\.TwentyRandomPosesInASavedMap|BenchStream\.ModesSeeTheSameScansOfAPresetPrefix|MovingClass\.LabelsAgreeWithTheSimulatorsTruth|TrackingHealthOnSequences\.(SparseCorridorScansKeepUpWithTheWalk|AScanTurnedBy90DegreesIsLostAndNeverMapped)|SimulatePresetCli\.EveryPresetWalksAsInTheLibrary|MapStoreCrash\.SigkillDuringSavesAlwaysLeavesTheOldOrTheNewMap'

# Suites of the TSan areas that run on one thread only (TSan has nothing to find there).
TSAN_SINGLE_THREADED='LoopClosure\.TwoFloorsAreNeverJoined'

configure_clang() {  # configure_clang BUILD_DIR CMAKE_ARGS...
  local dir=$1
  shift
  CC=clang-14 CXX=clang++-14 configure_ninja "$dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=$SANITIZER_CFLAGS" "-DCMAKE_C_FLAGS_RELWITHDEBINFO=$SANITIZER_CFLAGS" \
    "$@"
}

configure_asan() {  # configure_asan BUILD_DIR
  configure_clang "$1" -DDAMMLOAM_FUZZ=ON \
    -DDAMMLOAM_TEST_AREAS="geometry;core;odometry;tools;sim;drivers;backend;runner;system;bag;bridge"
}

configure_tsan() {  # configure_tsan BUILD_DIR
  configure_clang "$1" -DDAMMLOAM_TSAN=ON -DDAMMLOAM_TEST_AREAS="system;odometry;backend;bridge"
}
