// Independent Foxglove WebSocket clients for tests/bridge/test_bridge_live.sh: Foxglove's own
// protocol client (@foxglove/ws-protocol over `ws`) and ROS 2 CDR reader
// (@foxglove/rosmsg2-serialization from the advertised ros2msg schemas), none of our code.
//   node bridge_client.cjs decode URL SECONDS OUT.json   subscribe to every channel, decode all
//   node bridge_client.cjs many URL N SECONDS OUT.json   N decoding clients at once
//   node bridge_client.cjs stall URL SECONDS             subscribe to all, then never read
//   node bridge_client.cjs malformed URL OUT.json        bad frames; status errors expected
//   node bridge_client.cjs handshake HOSTPORT OUT.json   refused upgrades (subprotocol, token)
"use strict";
const fs = require("fs");
const WebSocket = require("ws");
const { FoxgloveClient } = require("@foxglove/ws-protocol");
const { parse } = require("@foxglove/rosmsg");
const { MessageReader } = require("@foxglove/rosmsg2-serialization");

const [mode, ...args] = process.argv.slice(2);

// Checks one decoded message; returns an error text or "" (what a viewer relies on).
function check(topic, m) {
  const finite = (v) => Number.isFinite(v);
  switch (topic) {
    case "/dammloam/odometry": {
      const p = m.pose.pose.position;
      if (!finite(p.x) || !finite(p.y) || !finite(p.z)) return "odometry position not finite";
      if (m.pose.covariance.length !== 36) return "odometry covariance is not 6x6";
      if (!m.child_frame_id) return "odometry without child_frame_id";
      return "";
    }
    case "/tf":
      return m.transforms.length === 1 && m.transforms[0].header.frame_id ? "" : "tf without one transform";
    case "/dammloam/labelled_cloud":
    case "/dammloam/map": {
      const names = m.fields.map((f) => f.name).join(",");
      if (names !== "x,y,z,label") return `${topic} fields ${names}`;
      if (m.data.length !== m.width * m.height * m.point_step) return `${topic} data size`;
      return "";
    }
    case "/dammloam/trajectory":
    case "/dammloam/loop_closures":
      return m.markers.length === 1 && m.markers[0].type === 5 ? "" : `${topic} is not one LINE_LIST`;
    case "/dammloam/status":
      return m.daemon && Number.isInteger(m.daemon.scans_processed) && m.bridge ? "" : "status without counters";
    default:
      return `unexpected topic ${topic}`;
  }
}

// A decoding client: resolves with per-topic counts, labels seen in clouds, errors.
function decodingClient(url, seconds) {
  return new Promise((resolve) => {
    const result = { counts: {}, labels: {}, errors: [], channels: 0, server: "", last: {} };
    const client = new FoxgloveClient({ ws: new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]) });
    const decoders = new Map();
    client.on("serverInfo", (info) => { result.server = info.name; });
    client.on("error", (e) => result.errors.push(`client error: ${e.message || e}`));
    client.on("status", (s) => result.errors.push(`server status: ${s.message}`));
    client.on("advertise", (channels) => {
      result.channels += channels.length;
      for (const channel of channels) {
        let decode;
        if (channel.encoding === "cdr" && channel.schemaEncoding === "ros2msg") {
          const reader = new MessageReader(parse(channel.schema, { ros2: true }));
          decode = (bytes) => reader.readMessage(bytes);
        } else if (channel.encoding === "json") {
          decode = (bytes) => JSON.parse(Buffer.from(bytes).toString("utf8"));
        } else {
          result.errors.push(`channel ${channel.topic}: encoding ${channel.encoding}`);
          continue;
        }
        decoders.set(client.subscribe(channel.id), { topic: channel.topic, decode });
      }
    });
    client.on("message", ({ subscriptionId, data }) => {
      const entry = decoders.get(subscriptionId);
      if (!entry) { result.errors.push(`message for unknown subscription ${subscriptionId}`); return; }
      const bytes = new Uint8Array(data.buffer, data.byteOffset, data.byteLength);
      let message;
      try {
        message = entry.decode(bytes);
      } catch (e) {
        result.errors.push(`${entry.topic}: cannot decode: ${e.message}`);
        return;
      }
      const problem = check(entry.topic, message);
      if (problem) result.errors.push(problem);
      result.counts[entry.topic] = (result.counts[entry.topic] || 0) + 1;
      if (entry.topic === "/dammloam/map" || entry.topic === "/dammloam/labelled_cloud") {
        for (let i = 0; i < message.width * message.height; ++i) {
          const label = message.data[i * message.point_step + 12];
          result.labels[label] = (result.labels[label] || 0) + 1;
        }
      }
      if (entry.topic === "/dammloam/status") result.last.status = message;
    });
    setTimeout(() => { client.close(); resolve(result); }, seconds * 1000);
  });
}

function save(path, value) { fs.writeFileSync(path, JSON.stringify(value, null, 1)); }

// Opens a raw socket (the `ws` package, subprotocol offered) and resolves when it is open.
function rawSocket(url, protocols = [FoxgloveClient.SUPPORTED_SUBPROTOCOL], options = {}) {
  return new Promise((resolve, reject) => {
    const ws = new WebSocket(url, protocols, options);
    ws.once("open", () => resolve(ws));
    ws.once("error", reject);
    ws.once("unexpected-response", (req, res) => reject(new Error(`HTTP ${res.statusCode}`)));
  });
}

async function main() {
  if (mode === "decode") {
    const [url, seconds, out] = args;
    save(out, await decodingClient(url, Number(seconds)));
  } else if (mode === "many") {
    const [url, n, seconds, out] = args;
    const results = await Promise.all(Array.from({ length: Number(n) }, () => decodingClient(url, Number(seconds))));
    save(out, results);
  } else if (mode === "stall") {
    // Subscribes to everything, then stops reading: the kernel's buffers fill and the bridge's
    // queue for this client must drop, not grow, while the others keep their rate.
    const [url, seconds] = args;
    setTimeout(() => process.exit(0), Number(seconds) * 1000);
    const ws = new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
    ws.on("error", (e) => { console.error(`stall client: ${e.message}`); process.exit(1); });
    ws.on("message", (data, binary) => {
      if (binary) return;
      const m = JSON.parse(data.toString());
      if (m.op !== "advertise") return;
      ws.send(JSON.stringify({ op: "subscribe",
        subscriptions: m.channels.map((c, i) => ({ id: i, channelId: c.id })) }));
      setTimeout(() => ws._socket.pause(), 200);
    });
  } else if (mode === "malformed") {
    const [url, out] = args;
    const ws = await rawSocket(url);
    const statuses = [];
    let closedCode = null;
    ws.on("message", (data, binary) => {
      if (binary) return;
      const m = JSON.parse(data.toString());
      if (m.op === "status") statuses.push(m.message);
    });
    const frames = [
      "{not json",
      "[1,2,3]",
      JSON.stringify({ op: "explode" }),
      JSON.stringify({ op: "subscribe", subscriptions: [{ id: 1, channelId: 999 }] }),
      JSON.stringify({ op: "subscribe", subscriptions: [{ id: -4, channelId: 1 }] }),
      JSON.stringify({ op: "unsubscribe", subscriptionIds: [42] }),
      JSON.stringify({ op: "getParameters", parameterNames: [] }),
    ];
    for (const f of frames) ws.send(f);
    ws.send(Buffer.from([0x01, 0x00, 0x00]), { binary: true });
    await new Promise((r) => setTimeout(r, 1000));
    const alive = ws.readyState === WebSocket.OPEN;
    // A text frame that is not UTF-8 breaks RFC 6455: that connection is closed (1007).
    let invalidUtf8ClosedWith = null;
    ws.on("close", (code) => { invalidUtf8ClosedWith = code; });
    ws.send(Buffer.from([0x7b, 0xff, 0xfe, 0x7d]), { binary: false });
    // A frame over the bridge's 64 KiB client limit: that connection (only) is closed.
    const big = await rawSocket(url);
    big.on("close", (code) => { closedCode = code; });
    big.send("x".repeat(200 * 1024));
    await new Promise((r) => setTimeout(r, 1000));
    ws.terminate();
    save(out, { statuses, alive_after_bad_frames: alive, oversized_closed_with: closedCode,
      invalid_utf8_closed_with: invalidUtf8ClosedWith });
    process.exit(0);
  } else if (mode === "handshake") {
    const [hostport, out] = args;
    const outcome = async (url, protocols, options) => {
      try { const ws = await rawSocket(url, protocols, options); ws.terminate(); return "open"; }
      catch (e) { return e.message; }
    };
    save(out, {
      no_subprotocol: await outcome(`ws://${hostport}/?token=t0k`, []),
      no_token: await outcome(`ws://${hostport}/`),
      wrong_token: await outcome(`ws://${hostport}/?token=nope`),
      query_token: await outcome(`ws://${hostport}/?token=t0k`),
      header_token: await outcome(`ws://${hostport}/`, [FoxgloveClient.SUPPORTED_SUBPROTOCOL],
        { headers: { Authorization: "Bearer t0k" } }),
    });
    process.exit(0);
  } else {
    console.error(`unknown mode ${mode}`);
    process.exit(2);
  }
}
main().catch((e) => { console.error(e); process.exit(1); });
