#!/usr/bin/python3
"""write_ros1_bag.py SEQUENCE_DIR OUT.bag none|bz2|lz4: writes the scans of a dammloam sequence
directory (scans/*.bin: x y z intensity t ring as float32; times.txt) as a ROS 1 bag with Debian's
python3-rosbag (ROS Noetic's rosbag, not dammloam's code), compressed as asked, in chunks of about
200 kB so that a bag holds several. Topics: /points (sensor_msgs/PointCloud2, fields x y z
intensity t ring as dammloam publishes them, stamped at the scan start) and /chatter
(std_msgs/String) in between; when the sequence has an imu.csv, /imu (sensor_msgs/Imu, frame "imu",
stamped as the csv, covariances unknown) before the scan each sample precedes. A fourth argument
"imu-faults" adds a copy of the third IMU sample (a duplicate stamp) and a sample with a NaN
acceleration. Run with /usr/bin/python3 (Debian's ROS packages).

write_ros1_bag.py --large OUT.bag MESSAGES POINTS: a bag of MESSAGES copies of one synthetic
OS1-128-sized cloud (POINTS points, stored chunks, stamps 0.1 s apart), for the memory
measurement of a bag larger than memory; the message is serialised once and written raw."""
import io
import os
import struct
import sys
from decimal import Decimal

import genpy
import rosbag
from sensor_msgs.msg import Imu, PointCloud2, PointField
from std_msgs.msg import String


def large(out, messages, points):
    import math
    data = bytearray()
    for k in range(points):
        a = 2 * math.pi * (k % 1024) / 1024
        r = 5.0 + (k // 1024) * 0.01
        data += struct.pack("<fffffH2x", r * math.cos(a), r * math.sin(a), 0.001 * (k // 1024), 1.0,
                            0.1 * (k % 1024) / 1024, (k // 1024) % 128)
    msg = PointCloud2()
    msg.header.frame_id = "lidar"
    msg.height, msg.width = 1, points
    msg.fields = [PointField(n, 4 * i, PointField.FLOAT32, 1) for i, n in enumerate(["x", "y", "z", "intensity", "t"])]
    msg.fields.append(PointField("ring", 20, PointField.UINT16, 1))
    msg.point_step, msg.row_step = 24, 24 * points
    msg.data = bytes(data)
    msg.is_dense = True
    with rosbag.Bag(out, "w") as bag:
        for i in range(messages):
            msg.header.seq = i
            msg.header.stamp = genpy.Time(1000 + i // 10, (i % 10) * 100000000)
            buff = io.BytesIO()
            msg.serialize(buff)
            bag.write("/points", (msg._type, buff.getvalue(), msg._md5sum, PointCloud2), msg.header.stamp, raw=True)


def main():
    if sys.argv[1] == "--large":
        large(sys.argv[2], int(sys.argv[3]), int(sys.argv[4]))
        return
    seq, out, compression = sys.argv[1], sys.argv[2], sys.argv[3]
    faults = len(sys.argv) > 4 and sys.argv[4] == "imu-faults"
    times = [line.strip() for line in open(os.path.join(seq, "times.txt")) if line.strip()]
    imu = read_imu(os.path.join(seq, "imu.csv"), faults)
    fields = [PointField("x", 0, PointField.FLOAT32, 1), PointField("y", 4, PointField.FLOAT32, 1),
              PointField("z", 8, PointField.FLOAT32, 1), PointField("intensity", 12, PointField.FLOAT32, 1),
              PointField("t", 16, PointField.FLOAT32, 1), PointField("ring", 20, PointField.UINT16, 1)]
    with rosbag.Bag(out, "w", compression=compression, chunk_threshold=200 * 1024) as bag:
        for i, text in enumerate(times):
            stamp_ns = int(Decimal(text) * 10**9)
            assert Decimal(stamp_ns) == Decimal(text) * 10**9, "time is not whole nanoseconds"
            stamp = genpy.Time(stamp_ns // 10**9, stamp_ns % 10**9)
            raw = open(os.path.join(seq, "scans", "%06d.bin" % i), "rb").read()
            floats = struct.unpack("<%df" % (len(raw) // 4), raw)
            n = len(floats) // 6
            data = bytearray()
            for k in range(n):
                x, y, z, intensity, t, ring = floats[6 * k:6 * k + 6]
                data += struct.pack("<fffffH2x", x, y, z, intensity, t, int(ring))
            msg = PointCloud2()
            msg.header.seq = i
            msg.header.stamp = stamp
            msg.header.frame_id = "lidar"
            msg.height, msg.width = 1, n
            msg.fields = fields
            msg.is_bigendian = False
            msg.point_step, msg.row_step = 24, 24 * n
            msg.data = bytes(data)
            msg.is_dense = True
            while imu and imu[0][0] < stamp:
                t, m = imu.pop(0)
                bag.write("/imu", m, t)
            bag.write("/chatter", String(data="scan %d" % i), stamp + genpy.Duration(0, 1000))
            bag.write("/points", msg, stamp + genpy.Duration(0, 50000000))
        for t, m in imu:
            bag.write("/imu", m, t)


def read_imu(path, faults):
    """[(stamp, Imu)] from a sequence's imu.csv (t,wx,wy,wz,ax,ay,az), with the test's faults."""
    if not os.path.exists(path):
        return []
    out = []
    for k, line in enumerate(open(path).read().split("\n")[1:]):
        if not line.strip():
            continue
        t, wx, wy, wz, ax, ay, az = line.split(",")
        stamp_ns = int(round(Decimal(t) * 10**9))
        m = Imu()
        m.header.seq = k
        m.header.stamp = genpy.Time(stamp_ns // 10**9, stamp_ns % 10**9)
        m.header.frame_id = "imu"
        m.orientation_covariance[0] = -1.0  # no orientation
        m.angular_velocity.x, m.angular_velocity.y, m.angular_velocity.z = float(wx), float(wy), float(wz)
        m.linear_acceleration.x, m.linear_acceleration.y, m.linear_acceleration.z = float(ax), float(ay), float(az)
        out.append((m.header.stamp, m))
    if faults and len(out) > 6:
        out.insert(3, out[2])
        bad = Imu()
        bad.header.stamp = out[6][0] + genpy.Duration(0, 1000)
        bad.header.frame_id = "imu"
        bad.linear_acceleration.x = float("nan")
        out.insert(7, (bad.header.stamp, bad))
    return out


if __name__ == "__main__":
    main()
