// Decodes CDR messages generically from their ros2msg schema text, as Foxglove does: parse the
// concatenated .msg definitions, then walk the bytes by the parsed field list. Written for the
// tests from the ROS 2 interface and CDR rules, independent of dammloam's C++ writer, so a
// schema that does not match the bytes shows as an error or leftover bytes.
"use strict";

const PRIMITIVES = {
  bool: 1, byte: 1, char: 1, int8: 1, uint8: 1, int16: 2, uint16: 2, int32: 4, uint32: 4,
  int64: 8, uint64: 8, float32: 4, float64: 8, string: 4,
};

function parseSchema(topName, text) {
  const blocks = text.split(/^={80}\s*$/m);
  const types = {};
  blocks.forEach((block, i) => {
    let lines = block.split("\n");
    let name = topName;
    if (i > 0) {
      while (lines.length && !lines[0].trim()) lines.shift();
      const m = /^MSG: (\S+)$/.exec(lines.shift().trim());
      if (!m) throw new Error(`block ${i}: no MSG: line`);
      // "MSG: pkg/Type" (rosbag2's spelling) or "pkg/msg/Type": both name pkg/msg/Type.
      const parts = m[1].split("/");
      name = parts.length === 2 ? `${parts[0]}/msg/${parts[1]}` : m[1];
    }
    const pkg = name.split("/")[0];
    const fields = [];
    for (let line of lines) {
      line = line.replace(/#.*/, "").trim();
      if (!line) continue;
      const m = /^(\S+)\s+([A-Za-z_][A-Za-z0-9_]*)(\s*=.*|\s+.*)?$/.exec(line);
      if (!m) throw new Error(`${name}: cannot parse '${line}'`);
      if (m[3] && m[3].trim().startsWith("=")) continue;  // constant
      const t = /^([^\[]+)(\[(\d*)\])?$/.exec(m[1]);
      let base = t[1];
      if (!PRIMITIVES[base]) {
        const parts = base.split("/");
        base = parts.length === 1 ? `${pkg}/msg/${parts[0]}` : parts.length === 2 ? `${parts[0]}/msg/${parts[1]}` : base;
      }
      fields.push({ name: m[2], type: base, array: !!t[2], length: t[3] ? parseInt(t[3], 10) : null });
    }
    types[name] = fields;
  });
  return types;
}

class CdrReader {
  constructor(data) {
    this.view = new DataView(data.buffer, data.byteOffset, data.byteLength);
    this.data = data;
    if (data[0] !== 0 || data[1] > 1) throw new Error(`encapsulation ${data[0]} ${data[1]}`);
    this.little = data[1] === 1;
    this.pos = 4;
  }
  align(n) { this.pos += (n - ((this.pos - 4) % n)) % n; }
  need(n) { if (this.pos + n > this.data.length) throw new Error(`truncated at ${this.pos} (+${n} of ${this.data.length})`); }
  primitive(type) {
    const size = PRIMITIVES[type];
    if (type !== "string") this.align(size);
    const v = this.view, p = this.pos, le = this.little;
    let value;
    switch (type) {
      case "string": {
        const n = this.primitive("uint32");
        this.need(n);
        value = Buffer.from(this.data.subarray(this.pos, this.pos + Math.max(0, n - 1))).toString("utf8");
        this.pos += n;
        return value;
      }
      case "bool": this.need(1); value = v.getUint8(p) !== 0; break;
      case "byte": case "char": case "uint8": this.need(1); value = v.getUint8(p); break;
      case "int8": this.need(1); value = v.getInt8(p); break;
      case "int16": this.need(2); value = v.getInt16(p, le); break;
      case "uint16": this.need(2); value = v.getUint16(p, le); break;
      case "int32": this.need(4); value = v.getInt32(p, le); break;
      case "uint32": this.need(4); value = v.getUint32(p, le); break;
      case "int64": this.need(8); value = v.getBigInt64(p, le); break;
      case "uint64": this.need(8); value = v.getBigUint64(p, le); break;
      case "float32": this.need(4); value = v.getFloat32(p, le); break;
      case "float64": this.need(8); value = v.getFloat64(p, le); break;
    }
    this.pos += size;
    return value;
  }
}

function decodeType(types, type, r) {
  if (PRIMITIVES[type]) return r.primitive(type);
  const fields = types[type];
  if (!fields) throw new Error(`no definition for ${type}`);
  const out = {};
  for (const f of fields) {
    if (!f.array) { out[f.name] = decodeType(types, f.type, r); continue; }
    const n = f.length !== null ? f.length : r.primitive("uint32");
    if (f.type === "uint8" || f.type === "byte") {
      r.need(n);
      out[f.name] = Buffer.from(r.data.subarray(r.pos, r.pos + n));
      r.pos += n;
      continue;
    }
    out[f.name] = [];
    for (let i = 0; i < n; i++) out[f.name].push(decodeType(types, f.type, r));
  }
  return out;
}

// Decodes one message; throws when the bytes run out or more than alignment padding is left.
function decode(types, topName, data) {
  const r = new CdrReader(data);
  const value = decodeType(types, topName, r);
  if (data.length - r.pos >= 4) throw new Error(`${data.length - r.pos} bytes left after ${topName}`);
  return value;
}

module.exports = { parseSchema, decode };
