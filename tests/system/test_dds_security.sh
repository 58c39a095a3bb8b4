#!/bin/sh
# deploy/security on loopback with Debian's Cyclone DDS security plugins (docs/network-and-security.md):
# a PKI made by deploy/security/make-pki.sh, dammloamd unchanged under its own identity, then
#  - dammloam-operator's command reaches the daemon and is answered (refused [disabled]: commands
#    stay disabled, the point is that it arrives), its argument never visible in clear on lo;
#  - dammloam-consumer may not even create a writer on dammloam_command;
#  - a participant without security does not see the daemon at all.
# usage: test_dds_security.sh BIN_DIR SOURCE_DIR [DOMAIN]   exit 0 pass, 1 fail, 77 skipped
set -u
bin=$1 src=$2 domain=${3:-212}
libdir=${DAMMLOAM_SECURITY_LIBDIR:-/usr/lib/x86_64-linux-gnu/libddsc0debian}
[ -f "$libdir/libdds_security_auth.so" ] || { echo "SKIP: no Cyclone DDS security plugins in $libdir"; exit 77; }
command -v openssl >/dev/null || { echo "SKIP: openssl not installed"; exit 77; }
name=security
. "$src/tests/system/daemon_script.sh"

"$src/deploy/security/make-pki.sh" -o "$work/pki" -d 2 >"$work/pki.log" 2>&1 ||
  { echo "FAIL: make-pki.sh"; cat "$work/pki.log"; exit 1; }
export DAMMLOAM_SECURITY_DIR="$work/pki" DAMMLOAM_SECURITY_LIBDIR="$libdir"
plain="file://$src/deploy/cyclonedds-loopback.xml"
export CYCLONEDDS_URI="$plain,file://$src/deploy/security/cyclonedds-security.xml"

start_daemon DAMMLOAM_IDENTITY=dammloamd

marker="dammloam-secret-$$"
start_capture 6 "$marker"

out=$(DAMMLOAM_IDENTITY=dammloam-operator "$bin/dammloam-command" save_map "$marker" --domain "$domain" --timeout 10 2>&1)
rc=$?
echo "operator: rc=$rc $out"
case $out in
  *"refused [disabled]"*) ;;
  *) echo "FAIL: the operator's command got no answer from the daemon"; fail=1 ;;
esac

out=$(DAMMLOAM_IDENTITY=dammloam-consumer "$bin/dammloam-command" save_map x --domain "$domain" --timeout 5 2>&1)
rc=$?
echo "consumer: rc=$rc $out"
case $out in
  *"Not Allowed By Security"*) [ "$rc" -eq 1 ] || { echo "FAIL: consumer exit code $rc"; fail=1; } ;;
  *) echo "FAIL: the consumer identity was allowed to write dammloam_command"; fail=1 ;;
esac

out=$(CYCLONEDDS_URI="$plain" "$bin/dammloam-command" save_map x --domain "$domain" --timeout 3 2>&1)
rc=$?
echo "no security: rc=$rc $out"
[ "$rc" -eq 3 ] || { echo "FAIL: a participant without security reached the daemon (exit $rc)"; fail=1; }

if [ "$capture" = yes ]; then
  wait "$capture_pid"
  result=$(cat "$work/capture.out")
  echo "capture, UDP ports $base..$((base + 249)): $result"
  case $result in
    loopback=0*) echo "FAIL: the capture saw no DDSI datagram on lo"; fail=1 ;;
  esac
  case $result in
    *"marker_seen=1"*) echo "FAIL: the command's argument travelled in clear"; fail=1 ;;
  esac
else
  kill "$capture_pid" 2>/dev/null
  echo "note: packet capture not permitted; encryption not checked on the wire"
fi

grep -q "'save_map' '$marker'" "$work/daemon.log" || { echo "FAIL: daemon did not log the operator's command"; fail=1; }
kill "$daemon"
wait "$daemon"; rc=$?
daemon=
[ "$rc" -eq 0 ] || { echo "FAIL: dammloamd exit code $rc after SIGTERM"; fail=1; }
[ "$fail" -eq 0 ] && echo "PASS" || { echo "--- daemon log"; cat "$work/daemon.log"; }
exit "$fail"
