# Shared set-up of the shell tests that run dammloamd as a process (sourced, POSIX sh).
# Set bin, src, domain and name before sourcing. Defines: base (the domain's first DDSI port),
# work (a fresh directory, removed on exit together with the daemon), daemon (its pid, empty
# while none runs), fail, and start_capture.
base=$((7400 + 250 * domain))
work=$(mktemp -d "${TMPDIR:-/tmp}/dammloam-$name.XXXXXX")
daemon=
cleanup() {
  [ -n "$daemon" ] && kill "$daemon" 2>/dev/null && wait "$daemon" 2>/dev/null
  rm -rf "$work"
}
trap cleanup EXIT
trap 'exit 1' INT TERM
fail=0

# start_capture SECONDS [MARKER]: udp_capture.py on the domain's port range in the background
# (capture_pid); capture=yes once its socket is ready, no if it may not capture (not root).
start_capture() {
  capture=no
  python3 "$src/tests/system/udp_capture.py" "$base" $((base + 249)) "$@" \
    >"$work/capture.out" 2>"$work/capture.err" &
  capture_pid=$!
  for _ in $(seq 50); do
    grep -q ready "$work/capture.err" 2>/dev/null && { capture=yes; break; }
    kill -0 "$capture_pid" 2>/dev/null || break
    sleep 0.1
  done
}

# start_daemon [ENV=VALUE ...]: dammloamd on $domain in the background (daemon), returning once
# its participant is up (the log line follows the participant's creation); fails the test if it
# exits first.
start_daemon() {
  env "$@" "$bin/dammloamd" --domain "$domain" >"$work/daemon.log" 2>&1 &
  daemon=$!
  for _ in $(seq 100); do
    grep -q "dammloamd on domain $domain" "$work/daemon.log" && return 0
    kill -0 "$daemon" 2>/dev/null || { echo "FAIL: dammloamd exited"; cat "$work/daemon.log"; exit 1; }
    sleep 0.1
  done
}
