#!/bin/sh
# The shipped systemd unit and config work together (docs/deployment.md, "State directory"):
#  (a) systemd-analyze verify accepts deploy/dammloamd.service with its Exec paths pointed at this
#      build's dammloamd (a copy with a misspelt key must be reported: verify only warns on those,
#      so any message naming the unit fails the check);
#  (b) the unit declares StateDirectory=dammloam, and deploy/config/dammloamd.yaml with commands
#      enabled as its comments say (enabled: true, a token, the suggested save_map_on_shutdown)
#      keeps commands.map_root and save_map_on_shutdown inside /var/lib/dammloam;
#  (c) that config runs: /var/lib/dammloam is emulated under a temp dir the way systemd lays out
#      a DynamicUser state directory (var/lib/dammloam -> private/dammloam), dammloamd gets a short
#      simulated drive (dammloam-replay), `dammloam-command save_map` writes a map there and
#      SIGTERM writes the save_map_on_shutdown map there.
# usage: test_deploy_unit.sh BIN_DIR SOURCE_DIR [DOMAIN]   exit 0 pass, 1 fail, 77 skipped ((a)
# without a working systemd-analyze: (b) and (c) still run and fail the test if they fail)
set -u
bin=$(cd "$1" && pwd) src=$(cd "$2" && pwd) domain=${3:-213}  # absolute: they go into a unit
name=deploy
. "$src/tests/system/daemon_script.sh"
trap 'exit 1' HUP PIPE  # cleanup (the daemon too) also when run as `... | head`
unit=$src/deploy/dammloamd.service
config=$src/deploy/config/dammloamd.yaml
token=deploy-test-token
skipped=

# --- (a) systemd-analyze verify -----------------------------------------------------------------
# verify [DIR]: systemd-analyze verify of DIR/dammloamd.service; prints its messages, returns 1
# when it fails or says anything about the unit (unknown keys are warnings with exit code 0).
verify() {
  SYSTEMD_LOG_LEVEL=info SYSTEMD_LOG_COLOR=0 systemd-analyze verify --man=no $recursive \
    "$1/dammloamd.service" >"$1/verify.out" 2>&1
  rc=$?
  sed 's/^/  /' "$1/verify.out"
  [ "$rc" -eq 0 ] && ! grep -q 'dammloamd\.service' "$1/verify.out"
}
if ! command -v systemd-analyze >/dev/null; then
  echo "SKIP (a): systemd-analyze not installed (apt-get install systemd): unit not verified"
  skipped=yes
else
  recursive=
  # Errors of the units ours pulls in (network-online.target) are the host's, not ours.
  systemd-analyze --help 2>&1 | grep -q -- --recursive-errors && recursive=--recursive-errors=no
  mkdir -p "$work/unit" "$work/typo" "$work/probe"
  printf '[Service]\nExecStart=/bin/true\n' >"$work/probe/dammloamd.service"
  if ! verify "$work/probe" >/dev/null; then
    echo "SKIP (a): systemd-analyze verify fails on a trivial unit here:"; cat "$work/probe/verify.out"
    skipped=yes
  else
    sed "s#/usr/local/bin/dammloamd#$bin/dammloamd#g" "$unit" >"$work/unit/dammloamd.service"
    grep -q "^ExecStart=$bin/dammloamd " "$work/unit/dammloamd.service" &&
      grep -q "^ExecStartPre=$bin/dammloamd " "$work/unit/dammloamd.service" ||
      { echo "FAIL (a): ExecStart/ExecStartPre of $unit are not /usr/local/bin/dammloamd"; fail=1; }
    echo "(a) systemd-analyze verify $(systemd-analyze --version | head -n 1) $recursive:"
    if verify "$work/unit"; then
      echo "(a) the unit verifies"
    else
      echo "FAIL (a): systemd-analyze verify reports the unit above"; fail=1
    fi
    # The check itself: a misspelt key must be caught.
    sed 's/^ProtectSystem=/ProtectSystm=/' "$work/unit/dammloamd.service" >"$work/typo/dammloamd.service"
    if verify "$work/typo" >/dev/null; then
      echo "FAIL (a): a unit with 'ProtectSystm=' passed the check (verify output changed?)"; fail=1
    fi
  fi
fi

# --- (b) the unit's state directory and the config --------------------------------------------
state_name=$(sed -n 's/^StateDirectory=//p' "$unit")
[ "$state_name" = dammloam ] ||
  { echo "FAIL (b): $unit declares StateDirectory=$state_name, expected dammloam"; fail=1; }
grep -q '^DynamicUser=yes' "$unit" && grep -q '^ProtectSystem=strict' "$unit" ||
  { echo "FAIL (b): $unit is no longer DynamicUser=yes + ProtectSystem=strict"; fail=1; }
state_dir=/var/lib/dammloam
# The suggestion the config's comments give for the shutdown save under the unit.
save=$(sed -n 's/^ *#  *save_map_on_shutdown: *\(\/[^ ]*\) *$/\1/p' "$config" | head -n 1)
[ -n "$save" ] || { echo "FAIL (b): $config suggests no save_map_on_shutdown for the unit"; fail=1; save=none; }
# Commands enabled as the comments say; every edit must apply to the shipped file.
enabled=$work/enabled.yaml
sed -e '/^  commands:/,/^  [a-z]/{s/^    enabled: false/    enabled: true/;s/^    token: ""/    token: '"$token"'/;}' \
  -e 's#^  save_map_on_shutdown: ""#  save_map_on_shutdown: '"$save"'#' "$config" >"$enabled"
for edit in "    enabled: true" "    token: $token" "  save_map_on_shutdown: $save"; do
  grep -q "^$edit" "$enabled" || { echo "FAIL (b): could not set '$edit' in $config"; fail=1; }
done
# value KEY FILE: the value of dammloamd.KEY (commands.map_root or a top-level key), unquoted.
value() {
  case $1 in
    commands.*) awk -v k="${1#commands.}:" '/^  commands:/ {c = 1; next} c && /^  [^ ]/ {c = 0}
                  c && $1 == k {print $2; exit}' "$2" ;;
    *) awk -v k="$1:" '/^  [^ ]/ && $1 == k {print $2; exit}' "$2" ;;
  esac | tr -d "\"'"
}
map_root=$(value commands.map_root "$enabled")
save_value=$(value save_map_on_shutdown "$enabled")
echo "(b) StateDirectory=$state_name; enabled config: map_root '$map_root', save_map_on_shutdown '$save_value'"
case $map_root in
  "$state_dir" | "$state_dir"/*) ;;
  *) echo "FAIL (b): commands.map_root '$map_root' is not $state_dir (the unit's state directory)"; fail=1 ;;
esac
case $save_value in
  *..*) echo "FAIL (b): save_map_on_shutdown '$save_value' has '..'"; fail=1 ;;
  "$state_dir"/?*) ;;
  *) echo "FAIL (b): save_map_on_shutdown '$save_value' is not inside $state_dir"; fail=1 ;;
esac
# Outside the unit (no /var/lib/dammloam) the check names what is missing.
if [ ! -e "$state_dir" ]; then
  out=$("$bin/dammloamd" --config "$enabled" --check-config 2>&1)
  case $out in
    *"'dammloamd."*"$state_dir"*) echo "(b) without the unit: $out" ;;
    *) echo "FAIL (b): --check-config without $state_dir does not name the key and path: $out"; fail=1 ;;
  esac
fi

# --- (c) the config in an emulated state directory --------------------------------------------
# systemd with DynamicUser=yes: /var/lib/private (0700) holds the directory, /var/lib/dammloam
# is a symlink to it.
root=$work/root
mkdir -p "$root/var/lib/private/$state_name"
chmod 0700 "$root/var/lib/private"
ln -s "private/$state_name" "$root$state_dir"
real_state=$root/var/lib/private/$state_name
sed "s#$state_dir#$root$state_dir#g" "$enabled" >"$work/dammloamd.yaml"
"$bin/dammloamd" --config "$work/dammloamd.yaml" --check-config >"$work/check.log" 2>&1 ||
  { echo "FAIL (c): --check-config in the emulated state directory:"; cat "$work/check.log"; exit 1; }

export CYCLONEDDS_URI="file://$src/deploy/cyclonedds-loopback.xml"  # never the default network
"$bin/dammloam-simulate" --scene zigzag --sensor vlp-16 --columns 900 --scans 12 --threads 1 \
  --out "$work/seq" >"$work/simulate.log" 2>&1 || { echo "FAIL: dammloam-simulate"; cat "$work/simulate.log"; exit 1; }

"$bin/dammloamd" --config "$work/dammloamd.yaml" --sensor-meta "$work/seq/meta.json" \
  --domain "$domain" >"$work/daemon.log" 2>&1 &
daemon=$!
for _ in $(seq 100); do
  grep -q "dammloamd on domain $domain" "$work/daemon.log" && break
  kill -0 "$daemon" 2>/dev/null || { echo "FAIL: dammloamd exited"; cat "$work/daemon.log"; exit 1; }
  sleep 0.1
done
grep -q "commands on .* in $root$state_dir" "$work/daemon.log" ||
  { echo "FAIL (c): the daemon does not take commands in $root$state_dir"; fail=1; }
grep -q "map saved on shutdown: $root$state_dir/" "$work/daemon.log" ||
  { echo "FAIL (c): the daemon does not save on shutdown inside $root$state_dir"; fail=1; }

"$bin/dammloam-replay" "$work/seq" --domain "$domain" --lockstep --lockstep-timeout 20 \
  --wait-subscriber 10 >"$work/replay.log" 2>&1 ||
  { echo "FAIL (c): dammloam-replay"; cat "$work/replay.log"; fail=1; }

out=$("$bin/dammloam-command" save_map deploy-check --domain "$domain" --timeout 15 --token "$token" 2>&1)
rc=$?
echo "(c) dammloam-command save_map deploy-check: rc=$rc $out"
[ "$rc" -eq 0 ] || { echo "FAIL (c): save_map was not carried out"; fail=1; }
[ -f "$real_state/deploy-check/map.json" ] ||
  { echo "FAIL (c): no map in the state directory ($real_state/deploy-check/map.json)"; fail=1; }
# The confinement still holds with the symlinked root: a path out of it is refused.
out=$("$bin/dammloam-command" save_map "$work/outside" --domain "$domain" --timeout 15 --token "$token" 2>&1)
rc=$?
echo "(c) dammloam-command save_map $work/outside: rc=$rc $out"
case $out in
  *path_outside_map_root*) [ ! -e "$work/outside" ] || { echo "FAIL (c): $work/outside written"; fail=1; } ;;
  *) echo "FAIL (c): a save outside map_root was not refused as path_outside_map_root"; fail=1 ;;
esac

kill "$daemon"
wait "$daemon"; rc=$?
daemon=
[ "$rc" -eq 0 ] || { echo "FAIL (c): dammloamd exit code $rc after SIGTERM"; fail=1; }
shutdown_map=$real_state/${save_value#"$state_dir"/}
[ -f "$shutdown_map/map.json" ] ||
  { echo "FAIL (c): no save_map_on_shutdown map after SIGTERM ($shutdown_map/map.json)"; fail=1; }
echo "(c) state directory after SIGTERM:"
(cd "$real_state" && find . -mindepth 1 -maxdepth 2 | sort | sed 's/^/  /')

if [ "$fail" -ne 0 ]; then
  for log in daemon replay; do echo "--- $log log"; cat "$work/$log.log"; done
  exit 1
fi
if [ -n "$skipped" ]; then
  echo "SKIP: (b) and (c) passed, (a) did not run (see above)"
  exit 77
fi
echo "PASS"
