// The Foxglove WebSocket protocol to the bridge that served this page (same host and port; a
// ?token=... in the page's address is passed on), decoding ROS 2 CDR with Foxglove's reader
// from the ros2msg schemas the bridge advertises.
import { FoxgloveClient } from "@foxglove/ws-protocol";
import { parse } from "@foxglove/rosmsg";
import { MessageReader } from "@foxglove/rosmsg2-serialization";

export function connect(topics, onMessage, onState) {
  const scheme = location.protocol === "https:" ? "wss:" : "ws:";
  const url = `${scheme}//${location.host}/${location.search}`;
  const client = new FoxgloveClient({
    ws: new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]),
  });
  const decoders = new Map();  // subscription id -> { topic, decode }
  client.on("open", () => onState("connected"));
  client.on("close", () => {
    onState("disconnected, retrying");
    setTimeout(() => connect(topics, onMessage, onState), 2000);
  });
  client.on("error", () => onState("error"));
  client.on("status", (s) => console.warn("bridge:", s.message));
  client.on("advertise", (channels) => {
    for (const channel of channels) {
      if (!topics.includes(channel.topic)) continue;
      let decode;
      if (channel.encoding === "cdr") {
        const reader = new MessageReader(parse(channel.schema, { ros2: true }));
        decode = (data) => reader.readMessage(data);
      } else {
        const text = new TextDecoder();
        decode = (data) => JSON.parse(text.decode(data));
      }
      const id = client.subscribe(channel.id);
      decoders.set(id, { topic: channel.topic, decode });
    }
  });
  client.on("message", ({ subscriptionId, data }) => {
    const entry = decoders.get(subscriptionId);
    if (!entry) return;
    const bytes = new Uint8Array(data.buffer, data.byteOffset, data.byteLength);
    onMessage(entry.topic, entry.decode(bytes));
  });
}
