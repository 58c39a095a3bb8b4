// tools/bridge/bridge_messages: the labelled cloud cut to its budget, the bounded map and the
// loop lines. (The CDR itself is decoded by Foxglove's reader in test_bridge_live.)
#include <gtest/gtest.h>

#include <cstring>
#include <set>
#include <stdexcept>

#include "io/bag/pointcloud2_cdr.hpp"
#include "tools/bridge/bridge_messages.hpp"

namespace dammloam::bridge {
namespace {

// A LabelledCloud sample with fields map_x map_y map_z (float32) and label (uint8), point i at
// (i, 0, 0) with label i % 6. Owns the memory the C sample points into.
struct LabelledSample {
  explicit LabelledSample(std::uint32_t n) {
    names = {"map_x", "map_y", "map_z", "label"};
    for (std::uint32_t i = 0; i < 4; ++i) {
      fields.push_back({names[i].data(), i * 4,
                        static_cast<std::uint8_t>(i < 3 ? point_field::kFloat32 : point_field::kUint8),
                        1});
    }
    data.assign(n * 16, 0);
    for (std::uint32_t i = 0; i < n; ++i) {
      const float x = static_cast<float>(i);
      std::memcpy(&data[i * 16], &x, 4);
      data[i * 16 + 12] = static_cast<std::uint8_t>(i % 6);
    }
    sample.cloud.width = n;
    sample.cloud.height = 1;
    sample.cloud.point_step = 16;
    sample.cloud.fields._buffer = fields.data();
    sample.cloud.fields._length = static_cast<std::uint32_t>(fields.size());
    sample.cloud.data._buffer = data.data();
    sample.cloud.data._length = static_cast<std::uint32_t>(data.size());
  }
  std::vector<std::string> names;
  std::vector<dammloam_msg_PointField> fields;
  std::vector<std::uint8_t> data;
  dammloam_msg_LabelledCloud sample{};
};

TEST(BridgeMessages, EveryChannelHasAUniqueIdAndASchema) {
  const std::vector<Channel> channels = BridgeChannels();
  ASSERT_EQ(channels.size(), 7u);
  std::set<std::uint32_t> ids;
  for (const Channel& c : channels) {
    EXPECT_TRUE(ids.insert(c.id).second) << c.topic;
    EXPECT_FALSE(c.schema.empty()) << c.topic;
    EXPECT_EQ(c.schema_encoding, c.encoding == "cdr" ? "ros2msg" : "jsonschema") << c.topic;
  }
}

TEST(BridgeMessages, LabelledCloudIsCutToItsBudgetKeepingLabels) {
  LabelledSample cloud(1000);
  const std::vector<ClassPoint> all = LabelledMapPoints(cloud.sample, 0);
  ASSERT_EQ(all.size(), 1000u);
  EXPECT_EQ(all[7].label, 1);
  EXPECT_FLOAT_EQ(all[7].position.x(), 7.f);
  const std::vector<ClassPoint> cut = LabelledMapPoints(cloud.sample, 300);
  EXPECT_LE(cut.size(), 300u);
  EXPECT_GE(cut.size(), 250u);
}

TEST(BridgeMessages, BrokenLabelledCloudsAreRefusedWithTheReason) {
  LabelledSample cloud(10);
  cloud.sample.cloud.data._length = 100;  // 10 points need 160 bytes
  EXPECT_THROW(LabelledMapPoints(cloud.sample, 0), std::invalid_argument);
  LabelledSample renamed(10);
  renamed.names[3] = "class";
  renamed.fields[3].name = renamed.names[3].data();
  try {
    LabelledMapPoints(renamed.sample, 0);
    FAIL() << "no label field accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("no field 'label'"), std::string::npos);
  }
}

TEST(BridgeMessages, ClassCloudIsAPointCloud2WithXyzAndLabel) {
  const std::vector<ClassPoint> points = {{Eigen::Vector3f(1, 2, 3), 3}, {Eigen::Vector3f(4, 5, 6), 5}};
  const std::string cdr = ClassCloudCdr(points, {12, 34}, "map");
  const io::DecodedCloud decoded = io::DecodePointCloud2(
      reinterpret_cast<const std::uint8_t*>(cdr.data()), cdr.size(), 0, "test");
  EXPECT_EQ(decoded.frame_id, "map");
  ASSERT_EQ(decoded.field_names, (std::vector<std::string>{"x", "y", "z", "label"}));
  EXPECT_EQ(decoded.cloud.width, 2u);
  EXPECT_EQ(decoded.cloud.data[16 + 12], 5);
}

TEST(BridgeMessages, VoxelMapIsBoundedAndKeepsTheNewestLabel) {
  VoxelMap map({/*voxel_size=*/1.0, /*max_points=*/3});
  map.Add({{Eigen::Vector3f(0.1f, 0, 0), 3}, {Eigen::Vector3f(0.2f, 0, 0), 5}});
  EXPECT_EQ(map.size(), 1u);
  EXPECT_EQ(map.Points()[0].label, 5);
  map.Add({{Eigen::Vector3f(2, 0, 0), 1}, {Eigen::Vector3f(3, 0, 0), 1},
           {Eigen::Vector3f(4, 0, 0), 1}, {Eigen::Vector3f(-5, 0, 0), 1}});
  EXPECT_EQ(map.size(), 3u);
  EXPECT_EQ(map.left_out(), 2u);
}

TEST(BridgeMessages, OnlyAcceptedLoopsBetweenSeenPosesBecomeLines) {
  LoopLines lines;
  lines.AddPose(1'000'000'000ull, Eigen::Vector3d(0, 0, 0));
  lines.AddPose(5'000'000'000ull, Eigen::Vector3d(1, 0, 0));
  dammloam_msg_LoopClosure loop{};
  loop.query_stamp = {5, 0};
  loop.match_stamp = {1, 0};
  EXPECT_FALSE(lines.AddLoop(loop));  // rejected
  loop.accepted = true;
  EXPECT_TRUE(lines.AddLoop(loop));
  loop.match_stamp = {2, 0};
  EXPECT_FALSE(lines.AddLoop(loop));  // no pose at that stamp
  EXPECT_EQ(lines.lines(), 1u);
}

}  // namespace
}  // namespace dammloam::bridge
