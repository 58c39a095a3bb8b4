// The page dammloam-bridge serves: the map by class, the trajectory, loop closures and the
// daemon's status, live over the Foxglove WebSocket protocol.
import { CLASS_COLORS } from "./colors.js";
import { connect } from "./connection.js";
import { Scene } from "./scene.js";

const scene = new Scene(document.getElementById("view"));
const statusBox = document.getElementById("status");
const connection = document.getElementById("connection");
document.getElementById("legend").innerHTML = CLASS_COLORS.map(
  (c) => `<span><i style="background:#${c.hex.toString(16).padStart(6, "0")}"></i>${c.name}</span>`,
).join("");

const STATES = ["starting", "waiting", "tracking", "degraded", "stopping", "localizing"];
const fmt = (v) => (typeof v === "number" ? v.toFixed(1) : "-");

function showStatus({ daemon: d, bridge: b }) {
  const rows = [
    `state <b>${STATES[d.state] || d.state}</b>, tracking ${d.tracking || "-"}, loop closure ${d.loop_closure || "-"}`,
    `scans ${d.scans_received} received, ${d.scans_processed} processed, ${d.scans_dropped} dropped, ${d.scans_rejected} rejected`,
    `latency ms: median ${fmt(d.latency_median_ms)}, p99 ${fmt(d.latency_p99_ms)}, max ${fmt(d.latency_max_ms)}`,
    `errors ${d.error_count}${d.last_error ? `: <span class="bad">${escapeHtml(d.last_error)}</span>` : ""}`,
    `bridge: ${b.clients} clients, ${b.frames_dropped} frames dropped, ${b.map_points} map points`,
  ];
  statusBox.innerHTML = rows.map((r) => `<div>${r}</div>`).join("");
}

function escapeHtml(text) {
  return text.replace(/[&<>"]/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;" })[c]);
}

const handlers = {
  "/dammloam/map": (m) => scene.setCloud(scene.map, m),
  "/dammloam/labelled_cloud": (m) => scene.setCloud(scene.scan, m),
  "/dammloam/trajectory": (m) => scene.setLines(scene.trajectory, m),
  "/dammloam/loop_closures": (m) => scene.setLines(scene.loops, m),
  "/dammloam/odometry": (m) => scene.setPose(m),
  "/dammloam/status": showStatus,
};
connect(Object.keys(handlers), (topic, message) => handlers[topic](message),
  (state) => { connection.textContent = state; });
