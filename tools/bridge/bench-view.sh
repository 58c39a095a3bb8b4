#!/usr/bin/env bash
# bench-view.sh MODE OUT_DIR: the daemon's latency at 10 Hz (dammloam-bench-latency, OS1-64
# corridor, one fresh dammloamd) while the live view is connected, and the bridge's CPU share.
#   MODE: none | client (bridge + a Foxglove protocol client decoding every channel)
#         | browser (+ headless Chromium on the page) | browser-nice (Chromium at nice 19)
# Environment: SCANS (default 300), BIN (default build/bin). Needs tests/bridge/node's packages
# and chromium (bash deploy/install-deps.sh). Interleave the modes over several rounds: one
# 300-scan p99 is its third-worst latency, and it moves by 10 ms between rounds.
set -euo pipefail
MODE=$1
OUT=$2
SRC=$(cd "$(dirname "$0")/../.." && pwd)
BIN=${BIN:-$SRC/build/bin}
SCANS=${SCANS:-300}
mkdir -p "$OUT"
export CYCLONEDDS_URI=${CYCLONEDDS_URI:-file://$SRC/deploy/cyclonedds-loopback.xml}
domain=$((40 + RANDOM % 50))
node_dir=$SRC/tests/bridge/node
seconds=$((SCANS / 10 + 40))  # the clients stay through the daemon's start and the whole run
pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; }
trap cleanup EXIT
case $MODE in none | client | browser | browser-nice) ;; *) echo "unknown MODE $MODE" >&2; exit 2;; esac
if [ "$MODE" != none ]; then
  "$BIN/dammloam-bridge" --domain "$domain" --listen 127.0.0.1:0 --token bench --map-period 0.5 \
    >"$OUT/bridge.out" 2>"$OUT/bridge.log" &
  bridge=$!
  pids+=("$bridge")
  for _ in $(seq 50); do grep -q "page http://" "$OUT/bridge.out" && break; sleep 0.1; done
  hostport=$(sed -n 's#.*page http://\([^/]*\)/.*#\1#p' "$OUT/bridge.out")
  [ -n "$hostport" ] || { echo "dammloam-bridge did not start: $OUT/bridge.log" >&2; exit 1; }
  node "$node_dir/bridge_client.cjs" decode "ws://$hostport/?token=bench" "$seconds" \
    "$OUT/decode.json" 2>"$OUT/decode.err" &
  pids+=($!)
  nice_level=0
  [ "$MODE" = browser-nice ] && nice_level=19
  if [ "$MODE" != client ]; then
    nice -n "$nice_level" node "$node_dir/screenshot.cjs" "$(command -v chromium)" \
      "http://$hostport/?token=bench" "$seconds" "$OUT/page.png" "$OUT/page.json" 2>"$OUT/page.err" &
    pids+=($!)
  fi
  sleep 3
  cpu0=$(awk '{print $14 + $15}' "/proc/$bridge/stat")
  t0=$(date +%s.%N)
fi
"$BIN/dammloam-bench-latency" --domain "$domain" --rates 10 --sweep 10 --scans "$SCANS" --json "$OUT/latency.json" \
  >"$OUT/bench.log" 2>&1
if [ "$MODE" != none ]; then
  cpu1=$(awk '{print $14 + $15}' "/proc/$bridge/stat")
  t1=$(date +%s.%N)
  rss_kb=$(sed -n 's/^VmRSS:[[:space:]]*\([0-9]*\) kB/\1/p' "/proc/$bridge/status")
  ticks=$(getconf CLK_TCK)
  python3 -c "print(f'bridge: {100 * ($cpu1 - $cpu0) / $ticks / ($t1 - $t0):.1f} % of a core, RSS $rss_kb kB')" \
    | tee "$OUT/bridge_cpu.txt"
fi
python3 - "$OUT/latency.json" "$MODE" <<'PY'
import json, sys
run = json.load(open(sys.argv[1]))["runs"][0]
print(f"{sys.argv[2]}: latency median {run['latency_median_ms']:.1f} ms, p99 {run['latency_p99_ms']:.1f} ms, "
      f"max {run['latency_max_ms']:.1f} ms, drops {run['drops']}, received {run['received']}/{run['sent']}")
PY
