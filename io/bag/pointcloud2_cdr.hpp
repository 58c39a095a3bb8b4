#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/cloud/point_cloud2.hpp"

namespace dammloam::io {

// One sensor_msgs/msg/PointCloud2 decoded from CDR: the strings are copied, the point bytes
// stay in the message buffer.
struct DecodedCloud {
  std::string frame_id;
  std::vector<std::string> field_names;  // parallel to cloud.fields
  CloudInput cloud;                      // names and frame_id empty: View() fills them

  // The cloud with its names pointing into this object: valid while it and the message
  // buffer live, unmoved.
  CloudInput View() const;
};

// Decodes the CDR bytes (encapsulation header included). Throws IoError naming `where`, the
// member and the byte offset (message_offset = where the message starts in the file) when the
// message is truncated, has trailing garbage or lengths that do not fit. Points are not
// checked here: CloudToScan does that.
DecodedCloud DecodePointCloud2(const std::uint8_t* data, std::size_t size,
                               std::uint64_t message_offset, const std::string& where);

// The same from the ROS 1 serialisation (sensor_msgs/PointCloud2 in a ROS 1 bag: little-endian,
// no alignment, std_msgs/Header with seq, time as uint32 sec + nsec). Same errors.
DecodedCloud DecodePointCloud2Ros1(const std::uint8_t* data, std::size_t size,
                                   std::uint64_t message_offset, const std::string& where);

}  // namespace dammloam::io
