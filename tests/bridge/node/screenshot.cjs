// Headless Chromium (Debian's `chromium`) loads the bridge's page, waits, and takes a screenshot
// over the DevTools protocol; the PNG is decoded (pngjs) and the pixels of each class colour of
// tools/bridge/web/src/colors.js counted.
//   node screenshot.cjs CHROMIUM PAGE_URL SECONDS OUT.png OUT.json
"use strict";
const fs = require("fs");
const os = require("os");
const path = require("path");
const { spawn } = require("child_process");
const WebSocket = require("ws");
const { PNG } = require("pngjs");

const [chromium, pageUrl, seconds, outPng, outJson] = process.argv.slice(2);
// The colours the page draws (tools/bridge/web/src/colors.js), written out again here on
// purpose: the test states what a user sees.
const COLORS = {
  unknown: 0x9e9e9e, ground: 0x8d6e63, roof: 0xe53935, wall: 0x1e88e5, edge: 0xfdd835,
  moving: 0xff6d00, trajectory: 0x00ffff, loop: 0xff00ff,
};
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

async function main() {
  const profile = fs.mkdtempSync(path.join(os.tmpdir(), "dammloam-chromium-"));
  const browser = spawn(chromium, [
    "--headless=new", "--no-sandbox", "--no-first-run", "--disable-extensions",
    "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--window-size=1000,700",
    `--user-data-dir=${profile}`, "--remote-debugging-port=0", "about:blank",
  ], { stdio: ["ignore", "ignore", "pipe"] });
  let stderr = "";
  browser.stderr.on("data", (d) => { stderr += d; });
  try {
    let port;
    for (let i = 0; i < 100 && !port; ++i) {
      await sleep(100);
      const file = path.join(profile, "DevToolsActivePort");
      if (fs.existsSync(file)) port = fs.readFileSync(file, "utf8").split("\n")[0];
    }
    if (!port) throw new Error(`chromium did not start:\n${stderr}`);
    const targets = await (await fetch(`http://127.0.0.1:${port}/json/list`)).json();
    const page = targets.find((t) => t.type === "page");
    const ws = new WebSocket(page.webSocketDebuggerUrl);
    await new Promise((r) => ws.once("open", r));
    let next = 1;
    const pending = new Map();
    const console_ = [];
    ws.on("message", (raw) => {
      const m = JSON.parse(raw.toString());
      if (m.id && pending.has(m.id)) { pending.get(m.id)(m); pending.delete(m.id); }
      if (m.method === "Runtime.consoleAPICalled") console_.push(m.params.args.map((a) => a.value).join(" "));
      if (m.method === "Runtime.exceptionThrown") console_.push(`exception: ${m.params.exceptionDetails.text} ${JSON.stringify(m.params.exceptionDetails.exception?.description || "")}`);
    });
    const call = (method, params = {}) => new Promise((resolve) => {
      const id = next++;
      pending.set(id, resolve);
      ws.send(JSON.stringify({ id, method, params }));
    });
    await call("Runtime.enable");
    await call("Page.enable");
    await call("Page.navigate", { url: pageUrl });
    await sleep(Number(seconds) * 1000);
    const shot = await call("Page.captureScreenshot", { format: "png" });
    const status = await call("Runtime.evaluate", { expression: "document.getElementById('status').innerText + ' | ' + document.getElementById('connection').innerText", returnByValue: true });
    const png = Buffer.from(shot.result.data, "base64");
    fs.writeFileSync(outPng, png);
    // The legend's swatches are not the map: only pixels outside the text panel count.
    const rect = await call("Runtime.evaluate", { returnByValue: true,
      expression: "JSON.stringify(document.getElementById('panel').getBoundingClientRect())" });
    const panel = JSON.parse(rect.result.result.value);
    const image = PNG.sync.read(png);
    const counts = Object.fromEntries(Object.keys(COLORS).map((k) => [k, 0]));
    for (let i = 0; i < image.data.length; i += 4) {
      const x = (i / 4) % image.width, y = Math.floor(i / 4 / image.width);
      if (x <= panel.right + 1 && y <= panel.bottom + 1) continue;
      const [r, g, b] = [image.data[i], image.data[i + 1], image.data[i + 2]];
      for (const [name, hex] of Object.entries(COLORS)) {
        if (Math.abs(r - (hex >> 16)) <= 3 && Math.abs(g - ((hex >> 8) & 255)) <= 3 && Math.abs(b - (hex & 255)) <= 3) {
          ++counts[name];
        }
      }
    }
    fs.writeFileSync(outJson, JSON.stringify({ counts, width: image.width, height: image.height,
      page_text: status.result?.result?.value || "", console: console_ }, null, 1));
    ws.close();
  } finally {
    browser.kill("SIGTERM");
    await sleep(300);
    fs.rmSync(profile, { recursive: true, force: true });
  }
}
main().then(() => process.exit(0), (e) => { console.error(e.message || e); process.exit(1); });
