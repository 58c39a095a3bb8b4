// Plain CDR (XCDR1) serialisation written for the tests from the ROS 2 / DDS-XTypes rules, so
// that the bag tests do not check our reader against our own writer: a 4-byte encapsulation
// header (00 01 little-endian, 00 00 big-endian), then each member aligned to its size
// counted from the end of that header.
"use strict";

class CdrWriter {
  constructor(littleEndian = true) {
    this.little = littleEndian;
    this.buf = Buffer.alloc(1024);
    this.len = 0;
    this.bytes([0x00, littleEndian ? 0x01 : 0x00, 0x00, 0x00]);
  }
  reserve(n) {
    if (this.len + n <= this.buf.length) return;
    const bigger = Buffer.alloc(Math.max(this.buf.length * 2, this.len + n));
    this.buf.copy(bigger, 0, 0, this.len);
    this.buf = bigger;
  }
  align(n) {
    const pos = this.len - 4;
    const pad = (n - (pos % n)) % n;
    this.reserve(pad);
    this.buf.fill(0, this.len, this.len + pad);
    this.len += pad;
  }
  bytes(array) {
    this.reserve(array.length);
    Buffer.from(array).copy(this.buf, this.len);
    this.len += array.length;
  }
  u8(v) { this.reserve(1); this.buf.writeUInt8(v, this.len); this.len += 1; }
  bool(v) { this.u8(v ? 1 : 0); }
  u16(v) { this.align(2); this.reserve(2); this.little ? this.buf.writeUInt16LE(v, this.len) : this.buf.writeUInt16BE(v, this.len); this.len += 2; }
  u32(v) { this.align(4); this.reserve(4); this.little ? this.buf.writeUInt32LE(v, this.len) : this.buf.writeUInt32BE(v, this.len); this.len += 4; }
  i32(v) { this.align(4); this.reserve(4); this.little ? this.buf.writeInt32LE(v, this.len) : this.buf.writeInt32BE(v, this.len); this.len += 4; }
  f64(v) { this.align(8); this.reserve(8); this.little ? this.buf.writeDoubleLE(v, this.len) : this.buf.writeDoubleBE(v, this.len); this.len += 8; }
  string(s) {
    const text = Buffer.from(s, "utf8");
    this.u32(text.length + 1);
    this.bytes(text);
    this.u8(0);
  }
  data() { return new Uint8Array(this.buf.subarray(0, this.len)); }
}

module.exports = { CdrWriter };
