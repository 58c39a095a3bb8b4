// Our MCAP writer (zstd chunks; stored ones in bag_odometry_test) and ROS 2 serialisers against
// @mcap/core: a file with every message kind that dammloam-odometry --mcap writes, with known
// values, decoded by node from the schema texts; and the same file read back by our own reader.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "io/bag/mcap_reader.hpp"
#include "io/bag/mcap_writer.hpp"
#include "io/bag/ros2_output.hpp"
#include "io/bag/ros2_schemas.hpp"
#include "tests/bag/bag_fixture.hpp"
#include "tests/support/temp_dir.hpp"

namespace dammloam {
namespace {

TEST(BagWrite, EveryMessageKindDecodesInMcapCoreFromItsSchema) {
  DAMMLOAM_REQUIRE_NODE();
  test::TempDir tmp;
  const auto file = tmp / "out.mcap";
  const CloudStamp stamp{1700000001, 250000000};
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(1.5, -2.0, 0.25);
  T.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  Matrix6d covariance = Matrix6d::Zero();
  for (int i = 0; i < 6; ++i) covariance(i, i) = 0.01 * (i + 1);
  covariance(0, 5) = covariance(5, 0) = 0.002;
  Vector6d twist;
  twist << 1, 2, 3, 0.1, 0.2, 0.3;
  io::LineMarker marker;
  marker.ns = "loop_closures";
  marker.id = 7;
  marker.lines.emplace_back(Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(4, 5, 6));
  const Cloud2 cloud = LabelledRos2Cloud({{1, 2, 3}, {4, 5, 6}, {7, 8, 9}}, {},
                                         {PointClass{}, static_cast<PointClass>(3),
                                          static_cast<PointClass>(5)}, "lidar");
  {
    io::McapWriter writer(file, {"zstd", 256, "ros2"});  // several zstd chunks
    const auto channel = [&](const char* type, const std::string& schema, const char* topic) {
      return writer.AddChannel(writer.AddSchema(type, "ros2msg", schema), topic, "cdr", {});
    };
    const auto odom = channel("nav_msgs/msg/Odometry", io::OdometrySchema(), "/odom");
    const auto tf = channel("tf2_msgs/msg/TFMessage", io::TfMessageSchema(), "/tf");
    const auto points = channel("sensor_msgs/msg/PointCloud2", io::PointCloud2Schema(), "/cloud");
    const auto loops = channel("visualization_msgs/msg/MarkerArray", io::MarkerArraySchema(), "/loops");
    const std::uint64_t t = 1700000001250000000ull;
    writer.Write(odom, t, t, io::OdometryCdr(stamp, "odom", "lidar", T, covariance, twist, covariance));
    writer.Write(tf, t, t, io::TfCdr(stamp, "odom", "lidar", T));
    writer.Write(points, t, t, io::PointCloud2Cdr(cloud));
    writer.Write(loops, t + 1, t + 1, io::LineMarkerArrayCdr(stamp, "odom", marker));
    writer.Close();
  }
  // Our reader: four messages on four channels, all CRCs valid.
  io::McapReader ours(file);
  io::McapMessage m;
  int count = 0;
  while (ours.Next(m)) ++count;
  EXPECT_EQ(count, 4);
  EXPECT_EQ(ours.MessageCount(3), std::optional<std::uint64_t>(1));

  const auto r = test::RunCommand("node " + (test::BagTestDir() / "node" / "read_mcap.cjs").string() +
                                  " " + file.string() + " 2>&1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto json = nlohmann::json::parse(r.output);
  const auto& odometry = json["topics"]["/odom"][0]["value"];
  EXPECT_EQ(odometry["header"]["stamp"]["sec"], 1700000001);
  EXPECT_EQ(odometry["header"]["stamp"]["nanosec"], 250000000);
  EXPECT_EQ(odometry["pose"]["pose"]["position"]["y"], -2.0);
  EXPECT_NEAR(odometry["pose"]["pose"]["orientation"]["z"].get<double>(), std::sin(0.15), 1e-12);
  EXPECT_EQ(odometry["pose"]["covariance"][5], 0.002);  // row-major: (0, 5)
  EXPECT_EQ(odometry["pose"]["covariance"][35], 0.06);
  EXPECT_EQ(odometry["twist"]["twist"]["angular"]["z"], 0.3);
  EXPECT_EQ(json["topics"]["/tf"][0]["value"]["transforms"][0]["transform"]["translation"]["x"], 1.5);
  const auto& c = json["topics"]["/cloud"][0];
  EXPECT_EQ(c["value"]["width"], 3);
  EXPECT_EQ(c["value"]["fields"][6]["name"], "label");
  EXPECT_EQ(c["labels"], (nlohmann::json{{"0", 1}, {"3", 1}, {"5", 1}}));
  EXPECT_EQ(c["first"], (nlohmann::json{1.0, 2.0, 3.0}));
  const auto& mk = json["topics"]["/loops"][0]["value"]["markers"][0];
  EXPECT_EQ(mk["ns"], "loop_closures");
  EXPECT_EQ(mk["id"], 7);
  EXPECT_EQ(mk["type"], 5);  // LINE_LIST
  ASSERT_EQ(mk["points"].size(), 2u);
  EXPECT_EQ(mk["points"][1]["z"], 6.0);
  EXPECT_EQ(mk["color"]["g"], 1.0);
  EXPECT_GE(json["chunkIndexes"].get<int>(), 2);
  EXPECT_EQ(json["streamedMessages"], 4);
}

}  // namespace
}  // namespace dammloam
