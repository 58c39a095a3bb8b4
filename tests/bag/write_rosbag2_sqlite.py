#!/usr/bin/env python3
"""write_rosbag2_sqlite.py SEQUENCE_DIR BAG_DIR [--zstd-messages]: writes the scans of a dammloam sequence
directory (scans/*.bin: x y z intensity t ring as float32; times.txt) as a rosbag2 with storage
sqlite3 (metadata.yaml + BAG_DIR/bag_0.db3, the schema rosbag2 creates), using Python's own
sqlite3 module and a CDR serialiser written here from the ROS 2 rules, not dammloam's code.
Topics: /points (sensor_msgs/msg/PointCloud2, fields x y z intensity t ring as dammloam
publishes them) and /chatter (std_msgs/msg/String) in between. --zstd-messages compresses every
message as a zstd frame (rosbag2's compression_mode MESSAGE) with node/zstd_files.cjs."""
import os
import sqlite3
import struct
import subprocess
import sys
import tempfile
from decimal import Decimal


class Cdr:
    """Plain little-endian CDR: header 00 01 00 00, members aligned from the end of it."""

    def __init__(self):
        self.out = bytearray(b"\x00\x01\x00\x00")

    def align(self, n):
        self.out += b"\x00" * ((n - (len(self.out) - 4) % n) % n)

    def put(self, fmt, value):
        size = struct.calcsize("<" + fmt)
        self.align(size)
        self.out += struct.pack("<" + fmt, value)

    def string(self, text):
        data = text.encode() + b"\x00"
        self.put("I", len(data))
        self.out += data


def point_cloud2(stamp_ns, floats):
    n = len(floats) // 6
    data = bytearray()
    for i in range(n):
        x, y, z, intensity, t, ring = floats[6 * i:6 * i + 6]
        data += struct.pack("<fffffH2x", x, y, z, intensity, t, int(ring))
    c = Cdr()
    c.put("i", stamp_ns // 10**9)
    c.put("I", stamp_ns % 10**9)
    c.string("lidar")
    c.put("I", 1)
    c.put("I", n)
    fields = [("x", 0, 7), ("y", 4, 7), ("z", 8, 7), ("intensity", 12, 7), ("t", 16, 7), ("ring", 20, 4)]
    c.put("I", len(fields))
    for name, offset, datatype in fields:
        c.string(name)
        c.put("I", offset)
        c.put("B", datatype)
        c.put("I", 1)
    c.put("B", 0)        # is_bigendian
    c.put("I", 24)       # point_step
    c.put("I", 24 * n)   # row_step
    c.put("I", len(data))
    c.out += data
    c.put("B", 1)        # is_dense
    return bytes(c.out)


def zstd_frames(blobs):
    """Each blob as a zstd frame, compressed by node (@foxglove/wasm-zstd)."""
    with tempfile.TemporaryDirectory() as tmp:
        files = []
        for i, blob in enumerate(blobs):
            files.append(os.path.join(tmp, str(i)))
            open(files[-1], "wb").write(blob)
        script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "node", "zstd_files.cjs")
        subprocess.run(["node", script] + files, check=True)
        return [open(f, "rb").read() for f in files]


def main():
    seq, bag = sys.argv[1], sys.argv[2]
    zstd = "--zstd-messages" in sys.argv[3:]
    os.makedirs(bag, exist_ok=True)
    times = [line.strip() for line in open(os.path.join(seq, "times.txt")) if line.strip()]
    db = sqlite3.connect(os.path.join(bag, "bag_0.db3"))
    db.executescript("""
        CREATE TABLE schema(schema_version INTEGER PRIMARY KEY, ros_distro TEXT NOT NULL);
        CREATE TABLE metadata(id INTEGER PRIMARY KEY, metadata_version INTEGER NOT NULL,
                              metadata TEXT NOT NULL);
        CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,
                            serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL,
                            type_description_hash TEXT NOT NULL);
        CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL,
                              timestamp INTEGER NOT NULL, data BLOB NOT NULL);
        CREATE INDEX timestamp_idx ON messages (timestamp ASC);
        INSERT INTO schema VALUES (4, 'jazzy');
        INSERT INTO topics VALUES (1, '/chatter', 'std_msgs/msg/String', 'cdr', '', '');
        INSERT INTO topics VALUES (2, '/points', 'sensor_msgs/msg/PointCloud2', 'cdr', '', '');
    """)
    rows = []
    for i, text in enumerate(times):
        stamp_ns = int(Decimal(text) * 10**9)
        assert Decimal(stamp_ns) == Decimal(text) * 10**9, "time is not whole nanoseconds"
        raw = open(os.path.join(seq, "scans", "%06d.bin" % i), "rb").read()
        floats = struct.unpack("<%df" % (len(raw) // 4), raw)
        hello = Cdr()
        hello.string("scan %d" % i)
        rows.append((1, stamp_ns + 1000, bytes(hello.out)))
        rows.append((2, stamp_ns + 50_000_000, point_cloud2(stamp_ns, floats)))
    if zstd:
        rows = [(t, s, b) for (t, s, _), b in zip(rows, zstd_frames([r[2] for r in rows]))]
    db.executemany("INSERT INTO messages(topic_id, timestamp, data) VALUES (?, ?, ?)", rows)
    db.commit()
    db.close()
    n = len(times)
    with open(os.path.join(bag, "metadata.yaml"), "w") as out:
        out.write(f"""rosbag2_bagfile_information:
  version: 9
  storage_identifier: sqlite3
  duration:
    nanoseconds: 0
  starting_time:
    nanoseconds_since_epoch: 0
  message_count: {2 * n}
  topics_with_message_count:
    - topic_metadata:
        name: /chatter
        type: std_msgs/msg/String
        serialization_format: cdr
        offered_qos_profiles: ""
      message_count: {n}
    - topic_metadata:
        name: /points
        type: sensor_msgs/msg/PointCloud2
        serialization_format: cdr
        offered_qos_profiles: ""
      message_count: {n}
  compression_format: "{"zstd" if zstd else ""}"
  compression_mode: "{"MESSAGE" if zstd else ""}"
  relative_file_paths:
    - bag_0.db3
  files:
    - path: bag_0.db3
      message_count: {2 * n}
""")


if __name__ == "__main__":
    main()
