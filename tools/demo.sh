#!/usr/bin/env bash
# The README's main command: installs, builds, simulates a corridor, runs the dammloamd service on
# it over DDS (loopback only), records the poses that come back and prints their accuracy.
# --view: also starts dammloam-bridge and prints the page's address (http://127.0.0.1:8765/, or
# BRIDGE_LISTEN), waits VIEW_WAIT (5) seconds for the page to be opened, and keeps the page up
# after the run until Ctrl-C (when run from a terminal).
set -euo pipefail
VIEW=no
for arg in "$@"; do
  case "$arg" in
    --view) VIEW=yes ;;
    *) echo "usage: bash tools/demo.sh [--view]" >&2; exit 2 ;;
  esac
done
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
TARGETS=(dammloam-simulate dammloam-evaluate dammloam-odometry dammloamd dammloam-replay dammloam-record)
[ "$VIEW" = yes ] && TARGETS+=(dammloam-bridge)
cmake --build "$BUILD" -j"$JOBS" --target "${TARGETS[@]}"

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
BRIDGE=
trap 'kill $DAEMON $RECORD $BRIDGE 2>/dev/null || true' EXIT
if [ "$VIEW" = yes ]; then
  "$BIN/dammloam-bridge" --domain "$DOMAIN" --listen "${BRIDGE_LISTEN:-127.0.0.1:8765}" \
    >"$OUT/bridge.out" 2>"$OUT/bridge.log" &
  BRIDGE=$!
  sleep 1
  kill -0 $BRIDGE 2>/dev/null || { cat "$OUT/bridge.log"; exit 1; }
  echo "== watch it live: $(sed -n 's/^dammloam-bridge: //p' "$OUT/bridge.out")"
  echo "   (open the page now; the replay starts in ${VIEW_WAIT:-5} s)"
  sleep "${VIEW_WAIT:-5}"
fi
sleep 1

# Lock-step with --view too: at a fixed 10 Hz a 2-core machine running a browser next to the
# daemon drops scans (measured: 20 of 150), and the accuracy printed below would change.
echo "== 3/4 replaying the sequence into the daemon in lock-step"
"$BIN/dammloam-replay" "$OUT/seq" --domain "$DOMAIN" --lockstep
wait $RECORD
kill -TERM $DAEMON && wait $DAEMON || true

echo "== 4/4 accuracy of the poses received over DDS against ground truth"
"$BIN/dammloam-evaluate" "$OUT/seq/gt.tum" "$OUT/poses_dds.tum" --plot "$OUT/trajectory.svg"
echo "outputs in $OUT (trajectory.svg shows both trajectories from above)"
if [ -n "$BRIDGE" ] && [ -t 0 ]; then
  echo "the page stays up: $(sed -n 's/^dammloam-bridge: //p' "$OUT/bridge.out"); Ctrl-C to stop"
  wait $BRIDGE || true
fi
kill $BRIDGE 2>/dev/null || true
trap - EXIT
