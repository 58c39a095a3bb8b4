#include "io/bag/bag_scans.hpp"

#include <algorithm>

#include "io/bag/pointcloud2_cdr.hpp"
#include "io/bag/ros1_bag.hpp"
#include "io/io_error.hpp"

namespace dammloam::io {
namespace {

BagTopic PickTopic(const std::vector<BagTopic>& topics, const std::string& wanted,
                   const std::filesystem::path& path) {
  if (!wanted.empty()) {
    const auto it = std::find_if(topics.begin(), topics.end(),
                                 [&](const BagTopic& t) { return t.name == wanted; });
    if (it == topics.end()) {
      throw IoError(path.string() + ": no topic " + wanted + " (topics: " + TopicList(topics) + ")");
    }
    if (it->type != kPointCloud2Type) {
      throw IoError(path.string() + ": topic " + wanted + " is " +
                    (it->type.empty() ? "untyped" : it->type) + ", not " + kPointCloud2Type);
    }
    return *it;
  }
  std::vector<BagTopic> clouds;
  std::copy_if(topics.begin(), topics.end(), std::back_inserter(clouds),
               [](const BagTopic& t) { return t.type == kPointCloud2Type; });
  if (clouds.size() == 1) return clouds.front();
  throw IoError(path.string() + ": " +
                (clouds.empty() ? std::string("no ") + kPointCloud2Type + " topic"
                                : std::to_string(clouds.size()) + " " + kPointCloud2Type +
                                      " topics: pick one with --topic") +
                " (topics: " + TopicList(topics) + ")");
}

}  // namespace

CloudLimits RecordedCloudLimits() {
  CloudLimits limits;
  limits.max_bytes = 1ull << 30;
  limits.max_points = 1ull << 26;
  limits.point_times = PointTimes::kOptional;
  limits.stamp_may_end_scan = true;
  return limits;
}

BagScans::BagScans(const std::filesystem::path& path, const BagScanOptions& options)
    : path_(path), options_(options), bag_(OpenBag(path)) {
  topic_ = PickTopic(bag_->topics(), options_.topic, path_);
  ros1_ = topic_.serialization_format == kRos1Serialization;
  if (!topic_.serialization_format.empty() && topic_.serialization_format != "cdr" && !ros1_) {
    throw IoError(path_.string() + ": topic " + topic_.name + " is serialised as '" +
                  topic_.serialization_format + "', only cdr (and ROS 1 bags) are read");
  }
  bag_->Select(topic_.name);
}

std::optional<Scan> BagScans::Next() {
  while (bag_->Next(message_)) {
    const DecodedCloud decoded =
        ros1_ ? DecodePointCloud2Ros1(message_.data, message_.size, message_.data_offset, message_.where)
              : DecodePointCloud2(message_.data, message_.size, message_.data_offset, message_.where);
    const CloudInput cloud = decoded.View();
    last_cloud_points_ = std::uint64_t{cloud.height} * cloud.width;
    last_cloud_height_ = cloud.height;
    CloudConversion conversion = CloudToScan(cloud, options_.limits);
    if (!conversion.scan) {
      if (conversion.code == "zero_points" || conversion.code == "no_valid_points") {
        ++skipped_;
        continue;
      }
      throw IoError(message_.where + ": " + kPointCloud2Type + " on " + topic_.name + ": " +
                    conversion.error);
    }
    // The stamp to the nanosecond as the same decimal in times.txt would give it.
    conversion.scan->t_start = StampSeconds(cloud.stamp) + conversion.start_offset;
    return std::move(conversion.scan);
  }
  return std::nullopt;
}

}  // namespace dammloam::io
