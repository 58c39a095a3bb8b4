// node write_ouster_packets_mcap.cjs CAPTURE.pcap OUT.mcap [LIDAR_PORT] [IMU_PORT]: what
// ouster-ros records from a sensor, rebuilt from a capture: every UDP payload to LIDAR_PORT
// (default 7502) as ouster_sensor_msgs/msg/PacketMsg on /ouster/lidar_packets and every one to
// IMU_PORT (default 7503) on /ouster/imu_packets, logged at the capture's time, written with
// @mcap/core (not dammloam's writer). The pcap is parsed here from the libpcap format (classic,
// little-endian, Ethernet, IPv4, UDP).
"use strict";
const fs = require("fs");
const { McapWriter } = require("@mcap/core");
const { CdrWriter } = require("./cdr_writer.cjs");

function* udpPayloads(file) {
  const b = fs.readFileSync(file);
  if (b.readUInt32LE(0) !== 0xa1b2c3d4) throw new Error(`${file}: not a little-endian microsecond pcap`);
  let at = 24;
  while (at + 16 <= b.length) {
    const sec = b.readUInt32LE(at), usec = b.readUInt32LE(at + 4), caplen = b.readUInt32LE(at + 8);
    const frame = b.subarray(at + 16, at + 16 + caplen);
    at += 16 + caplen;
    if (frame.length < 14 + 20 + 8 || frame.readUInt16BE(12) !== 0x0800) continue;
    const ihl = (frame[14] & 0x0f) * 4;
    if (frame[14 + 9] !== 17) continue;  // UDP
    const udp = 14 + ihl;
    const port = frame.readUInt16BE(udp + 2), length = frame.readUInt16BE(udp + 4);
    yield { timeNs: BigInt(sec) * 1000000000n + BigInt(usec) * 1000n, port,
            payload: frame.subarray(udp + 8, udp + length) };
  }
}

class FileWritable {
  constructor(file) { this.fd = fs.openSync(file, "w"); this.pos = 0n; }
  async write(buffer) { fs.writeSync(this.fd, buffer); this.pos += BigInt(buffer.byteLength); }
  position() { return this.pos; }
  close() { fs.closeSync(this.fd); }
}

async function main() {
  const [capture, out, lidarPort = "7502", imuPort = "7503"] = process.argv.slice(2);
  const writable = new FileWritable(out);
  const writer = new McapWriter({ writable, useChunks: true, chunkSize: 256 * 1024 });
  await writer.start({ profile: "ros2", library: "@mcap/core (dammloam tests)" });
  const schema = await writer.registerSchema({
    name: "ouster_sensor_msgs/msg/PacketMsg", encoding: "ros2msg", data: new TextEncoder().encode("uint8[] buf\n"),
  });
  const channels = {
    [Number(lidarPort)]: await writer.registerChannel({ topic: "/ouster/lidar_packets", schemaId: schema, messageEncoding: "cdr", metadata: new Map() }),
    [Number(imuPort)]: await writer.registerChannel({ topic: "/ouster/imu_packets", schemaId: schema, messageEncoding: "cdr", metadata: new Map() }),
  };
  let sequence = 0, written = 0;
  for (const { timeNs, port, payload } of udpPayloads(capture)) {
    if (!(port in channels)) continue;
    const w = new CdrWriter(true);
    w.u32(payload.length);
    w.bytes(payload);
    await writer.addMessage({ channelId: channels[port], sequence: sequence++, logTime: timeNs, publishTime: timeNs, data: w.data() });
    ++written;
  }
  await writer.end();
  writable.close();
  console.log(`${written} packets`);
}

main().catch((e) => { console.error(e.stack || String(e)); process.exit(1); });
