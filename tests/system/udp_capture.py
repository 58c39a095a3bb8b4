#!/usr/bin/env python3
"""Counts UDP/IPv4+IPv6 datagrams with a source or destination port in [LO, HI] on every interface
for SECONDS (AF_PACKET, needs CAP_NET_RAW), split into loopback and other interfaces, and whether
MARKER (bytes) appeared in any captured payload. Prints one line of key=value pairs at the end;
exits 77 when packet capture is not permitted. Started before the process under test; prints
"ready" on stderr once the socket is open."""
import select
import socket
import struct
import sys
import time

ETH_P_ALL = 0x0003


def udp_ports(frame):
    """(src, dst, payload) of an Ethernet frame carrying UDP, else None."""
    if len(frame) < 14:
        return None
    ethertype = struct.unpack("!H", frame[12:14])[0]
    ip = frame[14:]
    if ethertype == 0x0800 and len(ip) >= 20 and ip[9] == 17:
        udp = ip[(ip[0] & 0x0F) * 4:]
    elif ethertype == 0x86DD and len(ip) >= 40 and ip[6] == 17:
        udp = ip[40:]
    else:
        return None
    if len(udp) < 8:
        return None
    src, dst = struct.unpack("!HH", udp[:4])
    return src, dst, udp[8:]


def main():
    lo_port, hi_port, seconds = int(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3])
    marker = sys.argv[4].encode() if len(sys.argv) > 4 else None
    try:
        sock = socket.socket(socket.AF_PACKET, socket.SOCK_RAW, socket.htons(ETH_P_ALL))
    except PermissionError as e:
        print(f"packet capture not permitted: {e}", file=sys.stderr)
        return 77
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 8 << 20)
    print("ready", file=sys.stderr, flush=True)
    counts = {"loopback": 0, "other": 0}
    others, marker_seen = set(), False
    end = time.monotonic() + seconds
    while (left := end - time.monotonic()) > 0:
        if not select.select([sock], [], [], left)[0]:
            continue
        frame, addr = sock.recvfrom(65535)
        ifname, pkttype = addr[0], addr[2]
        if ifname == "lo" and pkttype == socket.PACKET_OUTGOING:
            continue  # every loopback datagram is seen twice: count it once, as received
        parsed = udp_ports(frame)
        if parsed is None:
            continue
        src, dst, payload = parsed
        if not (lo_port <= src <= hi_port or lo_port <= dst <= hi_port):
            continue
        if ifname == "lo":
            counts["loopback"] += 1
        else:
            counts["other"] += 1
            others.add(f"{ifname}:{src}->{dst}")
        if marker and marker in payload:
            marker_seen = True
    print(f"loopback={counts['loopback']} other={counts['other']} "
          f"marker_seen={int(marker_seen)} other_flows={','.join(sorted(others)) or '-'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
