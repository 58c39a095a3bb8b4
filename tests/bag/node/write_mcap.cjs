// node write_mcap.cjs '<json>': writes the scans of a dammloam sequence directory (scans/*.bin
// x y z intensity t ring as float32, times.txt) as sensor_msgs/msg/PointCloud2 messages into an
// MCAP file with @mcap/core, an MCAP writer that is not ours. Options (JSON):
//   sequence, out            input directory, output .mcap
//   layout                   xyzitr | velodyne | ouster | nebula   (field layouts of the drivers)
//   compression              none | zstd | lz4
//   endian                   little | big                          (CDR encapsulation)
//   chunked, summary         booleans (default true)
//   topic                    default /points
//   extra                    also a std_msgs/String topic and a second PointCloud2 topic
//   stamp                    start | end   (header stamp at the first or the last point)
//   rosbag2                  write <dir of out>/metadata.yaml (storage mcap) too
//   payload                  cloud (default) | string: /points carries std_msgs/String bytes
//                            under the PointCloud2 schema (a wrong-schema recording)
"use strict";
const fs = require("fs");
const path = require("path");
const { McapWriter } = require("@mcap/core");
const zstd = require("@foxglove/wasm-zstd");
const lz4js = require("lz4js");
const { CdrWriter } = require("./cdr_writer.cjs");

const F32 = 7, U8 = 2, U16 = 4, U32 = 6;
const LAYOUTS = {
  xyzitr: { step: 24, fields: [["x", 0, F32], ["y", 4, F32], ["z", 8, F32], ["intensity", 12, F32], ["t", 16, F32], ["ring", 20, U16]] },
  velodyne: { step: 32, fields: [["x", 0, F32], ["y", 4, F32], ["z", 8, F32], ["intensity", 16, F32], ["ring", 20, U16], ["time", 24, F32]] },
  ouster: { step: 48, fields: [["x", 0, F32], ["y", 4, F32], ["z", 8, F32], ["intensity", 16, F32], ["t", 20, U32], ["reflectivity", 24, U16], ["ring", 26, U16], ["ambient", 28, U16], ["range", 32, U32]] },
  nebula: { step: 32, fields: [["x", 0, F32], ["y", 4, F32], ["z", 8, F32], ["intensity", 12, U8], ["return_type", 13, U8], ["channel", 14, U16], ["azimuth", 16, F32], ["elevation", 20, F32], ["distance", 24, F32], ["time_stamp", 28, U32]] },
};

// Exact nanoseconds of a decimal text such as "100.25" or "1.5e2" (BigInt, no float rounding).
function decimalToNs(text) {
  const m = /^(-?)(\d*)(?:\.(\d*))?(?:[eE]([+-]?\d+))?$/.exec(text.trim());
  if (!m) throw new Error(`bad time '${text}'`);
  let digits = (m[2] || "0") + (m[3] || "");
  let point = (m[2] || "0").length + (m[4] ? parseInt(m[4], 10) : 0) + 9;  // shift by 1e9
  if (point < 0) throw new Error(`time '${text}' below a nanosecond`);
  while (digits.length < point) digits += "0";
  const rest = digits.slice(point);
  if (/[1-9]/.test(rest)) throw new Error(`time '${text}' is not a whole number of nanoseconds`);
  const ns = BigInt(digits.slice(0, point) || "0");
  return m[1] === "-" ? -ns : ns;
}

function readSequence(dir) {
  const times = fs.readFileSync(path.join(dir, "times.txt"), "utf8").split("\n").filter((l) => l.trim());
  return times.map((t, i) => {
    const name = String(i).padStart(6, "0") + ".bin";
    const raw = fs.readFileSync(path.join(dir, "scans", name));
    const values = new Float32Array(raw.buffer.slice(raw.byteOffset, raw.byteOffset + raw.length));
    return { stampNs: decimalToNs(t), values };
  });
}

// Point bytes are little-endian whatever the CDR byte order (is_bigendian = false).
function pointBytes(layoutName, values, shiftSeconds) {
  const layout = LAYOUTS[layoutName];
  const n = values.length / 6;
  const out = Buffer.alloc(n * layout.step);
  for (let i = 0; i < n; i++) {
    const [x, y, z, intensity, t, ring] = values.subarray(6 * i, 6 * i + 6);
    const time = t - shiftSeconds;
    const base = i * layout.step;
    for (const [name, offset, type] of layout.fields) {
      const at = base + offset;
      const v = { x, y, z, intensity, ring, channel: ring, t: time, time, time_stamp: time,
                  reflectivity: 7, ambient: 9, range: 1000, return_type: 1,
                  azimuth: Math.atan2(y, x), elevation: 0, distance: Math.hypot(x, y, z) }[name];
      if (type === F32) out.writeFloatLE(v, at);
      else if (type === U8) out.writeUInt8(Math.min(255, Math.round(v)), at);
      else if (type === U16) out.writeUInt16LE(Math.round(v), at);
      else if (type === U32) out.writeUInt32LE(Math.round(v * 1e9) >>> 0, at);  // ns
    }
  }
  return { bytes: out, count: n };
}

function pointCloud2(opts, scan) {
  const layout = LAYOUTS[opts.layout];
  let stamp = scan.stampNs, shift = 0;
  if (opts.stamp === "end") {
    let last = 0;
    for (let i = 4; i < scan.values.length; i += 6) last = Math.max(last, scan.values[i]);
    stamp += BigInt(Math.round(last * 1e9));
    shift = Number(BigInt(Math.round(last * 1e9))) * 1e-9;
  }
  const { bytes, count } = pointBytes(opts.layout, scan.values, shift);
  // ouster-ros publishes organised clouds: two rows when the count allows it.
  const height = opts.layout === "ouster" && count % 2 === 0 ? 2 : 1;
  const w = new CdrWriter(opts.endian !== "big");
  w.i32(Number(stamp / 1000000000n));
  w.u32(Number(stamp % 1000000000n));
  w.string("lidar");
  w.u32(height);
  w.u32(count / height);
  w.u32(layout.fields.length);
  for (const [name, offset, type] of layout.fields) {
    w.string(name);
    w.u32(offset);
    w.u8(type);
    w.u32(1);
  }
  w.bool(false);
  w.u32(layout.step);
  w.u32(layout.step * (count / height));
  w.u32(bytes.length);
  w.bytes(bytes);
  w.bool(true);
  return { data: w.data(), stamp };
}

class FileWritable {
  constructor(file) { this.fd = fs.openSync(file, "w"); this.pos = 0n; }
  async write(buffer) { fs.writeSync(this.fd, buffer); this.pos += BigInt(buffer.byteLength); }
  position() { return this.pos; }
  close() { fs.closeSync(this.fd); }
}

async function main() {
  const opts = Object.assign({ layout: "xyzitr", compression: "zstd", endian: "little", chunked: true,
                               summary: true, topic: "/points", extra: false, stamp: "start", payload: "cloud" },
                             JSON.parse(process.argv[2]));
  await zstd.isLoaded;
  const scans = readSequence(opts.sequence);
  const writable = new FileWritable(opts.out);
  const compressChunk = {
    none: undefined,
    zstd: (data) => ({ compression: "zstd", compressedData: zstd.compress(data, 3) }),
    lz4: (data) => ({ compression: "lz4", compressedData: lz4js.compress(data) }),
  }[opts.compression];
  const writer = new McapWriter({
    writable, useChunks: opts.chunked, chunkSize: 64 * 1024, compressChunk,
    useStatistics: opts.summary, useSummaryOffsets: opts.summary, useChunkIndex: opts.summary,
    useMessageIndex: opts.summary, repeatSchemas: opts.summary, repeatChannels: opts.summary,
    useAttachmentIndex: opts.summary, useMetadataIndex: opts.summary,
  });
  await writer.start({ profile: "ros2", library: "@mcap/core (dammloam tests)" });
  const schema = await writer.registerSchema({
    name: "sensor_msgs/msg/PointCloud2", encoding: "ros2msg",
    data: new TextEncoder().encode("# test schema text\nstd_msgs/Header header\n"),
  });
  const points = await writer.registerChannel({ topic: opts.topic, schemaId: schema, messageEncoding: "cdr", metadata: new Map() });
  let strings, second;
  if (opts.extra) {
    const stringSchema = await writer.registerSchema({ name: "std_msgs/msg/String", encoding: "ros2msg", data: new TextEncoder().encode("string data\n") });
    strings = await writer.registerChannel({ topic: "/chatter", schemaId: stringSchema, messageEncoding: "cdr", metadata: new Map() });
    second = await writer.registerChannel({ topic: "/points_rear", schemaId: schema, messageEncoding: "cdr", metadata: new Map() });
  }
  let sequence = 0;
  for (const scan of scans) {
    let { data, stamp } = pointCloud2(opts, scan);
    if (opts.payload === "string") {
      const w = new CdrWriter(true);
      w.string(`not a cloud ${sequence}`);
      data = w.data();
    }
    const logTime = scan.stampNs + 50000000n;
    if (opts.extra) {
      const w = new CdrWriter(true);
      w.string(`scan ${sequence}`);
      await writer.addMessage({ channelId: strings, sequence, logTime, publishTime: logTime, data: w.data() });
      // The rear cloud: the same scan with every point mirrored, so a wrong topic shows.
      const mirrored = Float32Array.from(scan.values);
      for (let i = 0; i < mirrored.length; i += 6) mirrored[i] = -mirrored[i];
      const rear = pointCloud2(opts, { stampNs: scan.stampNs, values: mirrored });
      await writer.addMessage({ channelId: second, sequence, logTime, publishTime: logTime, data: rear.data });
    }
    await writer.addMessage({ channelId: points, sequence: sequence++, logTime, publishTime: stamp, data });
  }
  await writer.end();
  writable.close();
  if (opts.rosbag2) {
    const dir = path.dirname(opts.out);
    const topics = [[opts.topic, "sensor_msgs/msg/PointCloud2"]];
    if (opts.extra) topics.push(["/chatter", "std_msgs/msg/String"], ["/points_rear", "sensor_msgs/msg/PointCloud2"]);
    const yaml = ["rosbag2_bagfile_information:", "  version: 5", "  storage_identifier: mcap",
      `  duration:\n    nanoseconds: 0`, `  starting_time:\n    nanoseconds_since_epoch: 0`,
      `  message_count: ${scans.length * topics.length}`, "  topics_with_message_count:"];
    for (const [name, type] of topics) {
      yaml.push("    - topic_metadata:", `        name: ${name}`, `        type: ${type}`,
                "        serialization_format: cdr", "        offered_qos_profiles: \"\"",
                `      message_count: ${scans.length}`);
    }
    yaml.push("  compression_format: \"\"", "  compression_mode: \"\"", "  relative_file_paths:",
              `    - ${path.basename(opts.out)}`, "  files: []");
    fs.writeFileSync(path.join(dir, "metadata.yaml"), yaml.join("\n") + "\n");
  }
}

main().catch((e) => { console.error(e.stack || String(e)); process.exit(1); });
