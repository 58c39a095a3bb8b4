// node read_mcap.cjs FILE: reads an MCAP with @mcap/core twice (the indexed reader, through the
// summary, chunk indexes and message indexes, every CRC validated; and the streaming reader,
// front to back to the footer), decodes every message from its channel's ros2msg schema
// (ros2msg_decoder.cjs) and prints one JSON object: schemas, channels, statistics, and per
// topic the decoded messages (point data summarised). Exit status 1 on any error.
"use strict";
const fs = require("fs");
const { McapIndexedReader, McapStreamReader } = require("@mcap/core");
const zstd = require("@foxglove/wasm-zstd");
const lz4 = require("@foxglove/wasm-lz4");
const { parseSchema, decode } = require("./ros2msg_decoder.cjs");

const decompressHandlers = {
  zstd: (buffer, size) => zstd.decompress(buffer, Number(size)),
  lz4: (buffer, size) => lz4(buffer, Number(size)),
};

function summarise(value) {
  if (Buffer.isBuffer(value)) return { bytes: value.length };
  if (typeof value === "bigint") return value.toString();
  if (Array.isArray(value)) return value.map(summarise);
  if (value && typeof value === "object") {
    const out = {};
    for (const [k, v] of Object.entries(value)) out[k] = summarise(v);
    return out;
  }
  return value;
}

// Labels of a dammloam labelled cloud, counted, and its first point.
function cloudSummary(cloud) {
  const field = (name) => cloud.fields.find((f) => f.name === name);
  const data = cloud.data;
  const labels = {};
  const label = field("label");
  for (let i = 0; label && i < cloud.width * cloud.height; i++) {
    const v = data[i * cloud.point_step + label.offset];
    labels[v] = (labels[v] || 0) + 1;
  }
  const x = field("x");
  const first = x ? [0, 4, 8].map((d) => data.readFloatLE(x.offset + d)) : null;
  return { labels, first };
}

async function main() {
  const file = process.argv[2];
  await zstd.isLoaded;
  await lz4.isLoaded;
  const handle = await fs.promises.open(file, "r");
  const size = (await handle.stat()).size;
  const readable = {
    size: async () => BigInt(size),
    read: async (offset, length) => {
      const buf = Buffer.alloc(Number(length));
      await handle.read(buf, 0, Number(length), Number(offset));
      return buf;
    },
  };
  const reader = await McapIndexedReader.Initialize({ readable, decompressHandlers });
  const out = {
    profile: reader.header.profile,
    schemas: [...reader.schemasById.values()].map((s) => ({ name: s.name, encoding: s.encoding })),
    channels: [...reader.channelsById.values()].map((c) => ({
      topic: c.topic, encoding: c.messageEncoding, schema: reader.schemasById.get(c.schemaId).name,
      metadata: Object.fromEntries(c.metadata) })),
    statistics: reader.statistics ? { messages: reader.statistics.messageCount.toString(),
                                      chunks: reader.statistics.chunkCount } : null,
    chunkIndexes: reader.chunkIndexes.length,
    topics: {},
  };
  const types = new Map();
  for (const [id, s] of reader.schemasById) types.set(id, parseSchema(s.name, new TextDecoder().decode(s.data)));
  for await (const m of reader.readMessages({ validateCrcs: true })) {
    const channel = reader.channelsById.get(m.channelId);
    const schema = reader.schemasById.get(channel.schemaId);
    const value = decode(types.get(channel.schemaId), schema.name, m.data);
    const entry = { log_time: m.logTime.toString(), value: summarise(value) };
    if (schema.name === "sensor_msgs/msg/PointCloud2") Object.assign(entry, cloudSummary(value));
    (out.topics[channel.topic] = out.topics[channel.topic] || []).push(entry);
  }
  // Front to back as a player would: every record, chunk CRCs, up to a valid footer.
  const stream = new McapStreamReader({ decompressHandlers, validateCrcs: true });
  stream.append(fs.readFileSync(file));
  let streamed = 0;
  for (let r; (r = stream.nextRecord());) if (r.type === "Message") streamed++;
  if (!stream.done()) throw new Error("streaming reader did not reach the footer");
  out.streamedMessages = streamed;
  await handle.close();
  process.stdout.write(JSON.stringify(out));
}

main().catch((e) => { console.error(e.stack || String(e)); process.exit(1); });
