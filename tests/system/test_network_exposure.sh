#!/bin/sh
# What dammloamd exposes on the network with deploy/cyclonedds-loopback.xml (docs/network-and-security.md):
#  - its UDP sockets (ss): the transmit socket bound to 127.0.0.1, and the two DDSI unicast
#    receive sockets (discovery, user data) on 0.0.0.0 at the documented ports of the domain and
#    participant index; Cyclone 0.10 binds receive sockets to INADDR_ANY whatever the
#    configuration says. No multicast ports, no TCP, no IPv6, nothing else;
#  - what it sends (AF_PACKET capture, when permitted): DDSI datagrams on lo, none on any other
#    interface.
# usage: test_network_exposure.sh BIN_DIR SOURCE_DIR [DOMAIN]   exit 0 pass, 1 fail, 77 skipped
set -u
bin=$1 src=$2 domain=${3:-211}
command -v ss >/dev/null || { echo "SKIP: ss (iproute2) not installed"; exit 77; }
# DDSI port mapping (Discovery/Ports defaults): PB=7400 DG=250 PG=2 d0=0 d1=10 d2=1 d3=11
max_index=32  # Discovery/MaxAutoParticipantIndex of the loopback config
name=exposure
. "$src/tests/system/daemon_script.sh"

export CYCLONEDDS_URI="file://$src/deploy/cyclonedds-loopback.xml"  # never the default network

start_capture 8

start_daemon  # sockets exist once the participant is up
sleep 0.5
ss -H -a -n -p -u -t -w -x >"$work/ss.all" 2>&1
grep "pid=$daemon," "$work/ss.all" | grep -E '^(udp|tcp|raw|p_raw)' >"$work/ss.inet" || true
echo "sockets of dammloamd (pid $daemon, domain $domain, ports $base..$((base + 249))):"
cat "$work/ss.inet"

# ss -H -a -n -p -u -t -w: netid state recv-q send-q local peer process
udp_count=0 loopback=0 wildcard=0 disc=
while read -r netid _ _ _ local _ _; do
  port=${local##*:} addr=${local%:*}
  case $netid in
    udp) udp_count=$((udp_count + 1)) ;;
    *) echo "FAIL: $netid socket $local"; fail=1; continue ;;
  esac
  case $addr in
    127.0.0.1|'[::1]') loopback=$((loopback + 1)) ;;
    0.0.0.0)
      wildcard=$((wildcard + 1))
      off=$((port - base))
      # unicast discovery d1 + PG*i or user data d3 + PG*i, i in 0..MaxAutoParticipantIndex
      if [ "$off" -ge 10 ] && [ "$off" -le $((11 + 2 * max_index)) ]; then
        [ $((off % 2)) -eq 0 ] && disc="$disc $port"
      else
        echo "FAIL: 0.0.0.0:$port is not a DDSI unicast port of domain $domain"; fail=1
      fi ;;
    *) echo "FAIL: socket bound to $local (neither loopback nor the documented wildcard ports)"; fail=1 ;;
  esac
done <"$work/ss.inet"
[ "$udp_count" -eq 3 ] || { echo "FAIL: expected 3 UDP sockets, found $udp_count"; fail=1; }
[ "$loopback" -eq 1 ] || { echo "FAIL: expected the transmit socket on 127.0.0.1, found $loopback"; fail=1; }
[ "$wildcard" -eq 2 ] || { echo "FAIL: expected 2 wildcard receive sockets, found $wildcard"; fail=1; }
# The two wildcard sockets are one participant index: discovery port P and data port P+1.
set -- $disc
if [ $# -eq 1 ]; then
  grep -q "0.0.0.0:$(($1 + 1)) " "$work/ss.inet" || { echo "FAIL: no data port next to discovery port $1"; fail=1; }
  echo "participant index $((($1 - base - 10) / 2)): discovery port $1, data port $(($1 + 1))"
else
  echo "FAIL: expected one discovery port, found:$disc"; fail=1
fi
# Multicast ports (d0, d2) are never bound: AllowMulticast is false.
if grep -qE "[:.]($base|$((base + 1))) " "$work/ss.inet"; then echo "FAIL: multicast port bound"; fail=1; fi

if [ "$capture" = yes ]; then
  wait "$capture_pid"
  result=$(cat "$work/capture.out")
  echo "capture on all interfaces, UDP ports $base..$((base + 249)): $result"
  case $result in
    *" other=0 "*) ;;
    *) echo "FAIL: DDSI datagrams of domain $domain on a non-loopback interface"; fail=1 ;;
  esac
  case $result in
    loopback=0*) echo "FAIL: the capture saw no DDSI datagram on lo (capture broken?)"; fail=1 ;;
  esac
else
  kill "$capture_pid" 2>/dev/null
  echo "note: packet capture not permitted ($(cat "$work/capture.err")); sockets checked only"
fi

kill "$daemon"
wait "$daemon"; rc=$?
daemon=
[ "$rc" -eq 0 ] || { echo "FAIL: dammloamd exit code $rc after SIGTERM"; fail=1; }
[ "$fail" -eq 0 ] && echo "PASS" || { echo "--- daemon log"; cat "$work/daemon.log"; }
exit "$fail"
