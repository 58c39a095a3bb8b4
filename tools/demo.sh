#!/usr/bin/env bash
# The README's main command: installs, builds, simulates a corridor, runs the dammloamd service on
# it over DDS (loopback only), records the poses that come back and prints their accuracy.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
JOBS=${JOBS:-$(nproc)}
SCENE=${SCENE:-corridor}
SENSOR=${SENSOR:-os1-64}
SCANS=${SCANS:-150}
OUT=${OUT:-$ROOT/out/demo}
BUILD=${BUILD:-build}

bash deploy/install-deps.sh
cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$BUILD" -j"$JOBS" --target dammloam-simulate dammloam-evaluate dammloam-odometry \
  dammloamd dammloam-replay dammloam-record

BIN=$ROOT/$BUILD/bin
rm -rf "$OUT" && mkdir -p "$OUT"
# Never let DDS discovery leave this machine: pin Cyclone DDS to the loopback interface.
export CYCLONEDDS_URI=file://$ROOT/deploy/cyclonedds-loopback.xml
DOMAIN=${DOMAIN:-77}

echo "== 1/4 simulating $SCANS scans of a $SCENE with an $SENSOR"
"$BIN/dammloam-simulate" --scene "$SCENE" --sensor "$SENSOR" --scans "$SCANS" --out "$OUT/seq"

echo "== 2/4 starting dammloamd (domain $DOMAIN) and the recorder"
"$BIN/dammloamd" --config deploy/config/dammloamd.yaml --domain "$DOMAIN" --sensor-meta "$OUT/seq/meta.json" >"$OUT/dammloamd.log" 2>&1 &
DAEMON=$!
"$BIN/dammloam-record" --domain "$DOMAIN" --poses "$OUT/poses_dds.tum" --events "$OUT/events.jsonl" \
  --count "$SCANS" --timeout 30 >"$OUT/record.log" 2>&1 &
RECORD=$!
trap 'kill $DAEMON $RECORD 2>/dev/null || true' EXIT
sleep 1

echo "== 3/4 replaying the sequence into the daemon in lock-step"
"$BIN/dammloam-replay" "$OUT/seq" --domain "$DOMAIN" --lockstep
wait $RECORD
kill -TERM $DAEMON && wait $DAEMON || true
trap - EXIT

echo "== 4/4 accuracy of the poses received over DDS against ground truth"
"$BIN/dammloam-evaluate" "$OUT/seq/gt.tum" "$OUT/poses_dds.tum" --plot "$OUT/trajectory.svg"
echo "outputs in $OUT (trajectory.svg shows both trajectories from above)"
