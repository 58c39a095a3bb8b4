#!/bin/sh
# dammloam-bridge as users see it: dammloamd and dammloam-replay as processes (Cyclone pinned
# to loopback, domain $3), the bridge with a token, and at the same time during a 10 Hz replay:
#   - an independent Foxglove client (node/bridge_client.cjs: @foxglove/ws-protocol, ws and
#     Foxglove's CDR reader) that subscribes to and decodes every channel,
#   - ten such clients at once, each of which must keep the rate,
#   - a client that subscribes to everything and then stops reading (its queue drops, counted in
#     the status channel; the others are unaffected),
#   - malformed frames (answered with status errors; the connection stays) and an oversized one
#     (that connection only is closed), refused handshakes (no subprotocol, no/wrong token),
#   - headless Chromium loading the page: a screenshot shows the class colours and the
#     trajectory where the map is (node/screenshot.cjs).
# Exit 77 = skipped: node packages of tests/bridge/node or chromium missing
# (bash deploy/install-deps.sh installs both).
set -u
bin=$(cd "$1" && pwd) src=$(cd "$2" && pwd) domain=${3:-214}
name=bridge
. "$src/tests/system/daemon_script.sh"
export CYCLONEDDS_URI="${CYCLONEDDS_URI:-file://$src/deploy/cyclonedds-loopback.xml}"
node_dir=$src/tests/bridge/node
if ! command -v node >/dev/null || [ ! -d "$node_dir/node_modules/@foxglove/ws-protocol" ]; then
  echo "SKIP: node or tests/bridge/node/node_modules missing (bash deploy/install-deps.sh)"; exit 77
fi
chromium=$(command -v chromium || true)
[ -n "$chromium" ] || { echo "SKIP: chromium missing (bash deploy/install-deps.sh)"; exit 77; }
scans=60
token=t0k
bridge=
cleanup_bridge() { [ -n "$bridge" ] && kill "$bridge" 2>/dev/null && wait "$bridge" 2>/dev/null; cleanup; }
trap cleanup_bridge EXIT

"$bin/dammloam-simulate" --scene corridor --sensor vlp-16 --columns 900 --scans $scans --threads 1 \
  --out "$work/seq" >"$work/simulate.log" 2>&1 || { echo "FAIL: dammloam-simulate"; cat "$work/simulate.log"; exit 1; }
start_daemon
"$bin/dammloam-bridge" --domain "$domain" --listen 127.0.0.1:0 --token "$token" --map-period 0.5 \
  >"$work/bridge.out" 2>"$work/bridge.log" &
bridge=$!
for _ in $(seq 50); do
  grep -q "page http://" "$work/bridge.out" && break
  kill -0 "$bridge" 2>/dev/null || { echo "FAIL: dammloam-bridge exited"; cat "$work/bridge.log"; exit 1; }
  sleep 0.1
done
hostport=$(sed -n 's#.*page http://\([^/]*\)/.*#\1#p' "$work/bridge.out")
[ -n "$hostport" ] || { echo "FAIL: no address from dammloam-bridge"; cat "$work/bridge.out" "$work/bridge.log"; exit 1; }
url="ws://$hostport/?token=$token"
echo "bridge on $hostport"

client() { timeout 40 node "$node_dir/bridge_client.cjs" "$@"; }
# Everyone connects before the replay starts and stays until it has ended (about 6 s at 10 Hz).
client decode "$url" 12 "$work/decode.json" 2>"$work/decode.err" & p1=$!
client many "$url" 10 12 "$work/many.json" 2>"$work/many.err" & p2=$!
client stall "$url" 12 2>"$work/stall.err" & p3=$!
timeout 60 node "$node_dir/screenshot.cjs" "$chromium" "http://$hostport/?token=$token" 11 "$work/page.png" \
  "$work/page.json" 2>"$work/screenshot.err" & p4=$!
sleep 1.5
client malformed "$url" "$work/malformed.json" 2>"$work/malformed.err" & p5=$!
client handshake "$hostport" "$work/handshake.json" 2>"$work/handshake.err" & p6=$!
"$bin/dammloam-replay" "$work/seq" --domain "$domain" --rate 1 --wait-subscriber 10 \
  >"$work/replay.log" 2>&1 || { echo "FAIL: dammloam-replay"; cat "$work/replay.log"; fail=1; }
for p in $p1 $p2 $p3 $p4 $p5 $p6; do wait $p || { echo "FAIL: a client (pid $p) failed"; fail=1; }; done
kill -0 "$bridge" 2>/dev/null || { echo "FAIL: dammloam-bridge died"; fail=1; }
rss_kb=$(sed -n 's/^VmRSS:[[:space:]]*\([0-9]*\) kB/\1/p' "/proc/$bridge/status" 2>/dev/null)
echo "bridge RSS after the run: ${rss_kb:-?} kB"
# BRIDGE_SCREENSHOT=FILE keeps the page's screenshot (the README's picture).
[ -n "${BRIDGE_SCREENSHOT:-}" ] && cp "$work/page.png" "$BRIDGE_SCREENSHOT"
[ -n "$rss_kb" ] && [ "$rss_kb" -lt 150000 ] ||
  { echo "FAIL: bridge RSS ${rss_kb:-?} kB (queues are bounded at 16 MiB per client)"; fail=1; }
# The committed bundle must be what its sources give (when the page's npm packages are there).
web=$src/tools/bridge/web
if [ -x "$web/node_modules/.bin/esbuild" ]; then
  (cd "$web" && ./node_modules/.bin/esbuild src/main.js --bundle --minify --format=iife \
    --target=es2020 --outfile="$work/viewer.js" --log-level=error) &&
    cmp -s "$work/viewer.js" "$web/site/viewer.js" ||
    { echo "FAIL: tools/bridge/web/site/viewer.js is stale: cmake --build build --target dammloam-bridge-page"; fail=1; }
else
  echo "note: tools/bridge/web/node_modules missing, bundle not compared with its sources"
fi

python3 - "$work" "$scans" <<'PY' || fail=1
import json, sys
work, scans = sys.argv[1], int(sys.argv[2])
load = lambda name: json.load(open(f"{work}/{name}"))
problems = []
decode = load("decode.json")
topics = ["/dammloam/odometry", "/tf", "/dammloam/labelled_cloud", "/dammloam/map",
          "/dammloam/loop_closures", "/dammloam/trajectory", "/dammloam/status"]
print("decode client:", json.dumps(decode["counts"]), "labels", json.dumps(decode["labels"]))
if decode["channels"] != len(topics): problems.append(f"advertised {decode['channels']} channels")
for t in topics:
    if decode["counts"].get(t, 0) < 1: problems.append(f"nothing decoded on {t}")
if decode["errors"]: problems.append(f"decode errors: {decode['errors'][:5]}")
odometry = decode["counts"].get("/dammloam/odometry", 0)
if odometry < 0.8 * scans: problems.append(f"odometry {odometry} of {scans} scans")
for label, name in ((1, "ground"), (3, "wall")):
    if decode["labels"].get(str(label), 0) < 100: problems.append(f"few {name} points in the clouds")
dropped = decode.get("last", {}).get("status", {}).get("bridge", {}).get("frames_dropped", 0)
print("frames dropped for the stalled client (status channel):", dropped)
if dropped <= 0: problems.append("the stalled client's queue dropped nothing")
many = load("many.json")
rates = [c["counts"].get("/dammloam/odometry", 0) for c in many]
print("ten clients, odometry messages each:", rates)
if len(many) != 10 or min(rates) < 0.8 * scans: problems.append(f"ten clients: {rates}")
for c in many:
    if c["errors"]: problems.append(f"a client of ten: {c['errors'][:3]}")
bad = load("malformed.json")
print("malformed frames:", json.dumps(bad))
if len(bad["statuses"]) < 8: problems.append(f"{len(bad['statuses'])} status errors for 8 bad frames")
if not bad["alive_after_bad_frames"]: problems.append("a client was dropped for bad frames")
if bad["oversized_closed_with"] is None: problems.append("an oversized frame did not close its connection")
hs = load("handshake.json")
print("handshakes:", json.dumps(hs))
expected = {"no_subprotocol": "HTTP 400", "no_token": "HTTP 401", "wrong_token": "HTTP 401",
            "query_token": "open", "header_token": "open"}
for k, v in expected.items():
    if hs.get(k) != v: problems.append(f"handshake {k}: {hs.get(k)}, expected {v}")
page = load("page.json")
print("page pixels:", json.dumps(page["counts"]), "| text:", page["page_text"][:200])
# Seen from above, the corridor's roof hides much of its ground: walls, three classes at least
# and the trajectory must show.
classes = [n for n in ("unknown", "ground", "roof", "wall", "edge", "moving") if page["counts"][n] >= 100]
if len(classes) < 3: problems.append(f"the screenshot shows only the class colours {classes}")
for name, least in (("wall", 200), ("trajectory", 30)):
    if page["counts"][name] < least: problems.append(f"the screenshot shows {page['counts'][name]} {name} pixels")
if page["console"]: print("page console:", page["console"][:5])
for p in problems: print("FAIL:", p)
sys.exit(1 if problems else 0)
PY
if [ "$fail" -ne 0 ]; then
  for f in bridge.log decode.err many.err stall.err screenshot.err malformed.err handshake.err; do
    echo "--- $f"; tail -n 20 "$work/$f"
  done
  exit 1
fi
echo "PASS"
