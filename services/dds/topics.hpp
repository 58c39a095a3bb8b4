#pragma once
// Default topic names and the QoS of every dammloam topic (the topic table of docs/topics.md).
#include <string>

#include "services/dds/dds.hpp"

namespace dammloam::dds {

struct TopicNames {
  std::string points = "dammloam_points";                  // PointCloud in
  std::string odometry = "dammloam_odometry";              // Odometry out
  std::string labelled_cloud = "dammloam_labelled_cloud";  // LabelledCloud out
  std::string loop_closure = "dammloam_loop_closure";      // LoopClosure out
  std::string status = "dammloam_status";                  // Status out
  std::string command = "dammloam_command";                // Command in
  std::string command_reply = "dammloam_command_reply";    // CommandReply out
  std::string imu = "dammloam_imu";                        // Imu in (issue 55)
  std::string wheel_odometry = "dammloam_wheel_odometry";  // WheelOdometry in (issue 55)
};

// Reliable everywhere: a reliable writer also serves best-effort readers (not the reverse).
// Keep-last never blocks a writer: under overload old samples are replaced, and the daemon
// counts what it drops itself.
inline TopicQos PointsQos(int depth = 4) { return {true, depth, false}; }
// Odometry is latched too (100 poses) so a recorder that joins late still gets the trajectory.
inline TopicQos OdometryQos(int depth = 100) { return {true, depth, true}; }
inline TopicQos LabelledCloudQos(int depth = 2) { return {true, depth, false}; }
// Loop events and status are latched so a late recorder still sees the last ones.
inline TopicQos LoopClosureQos(int depth = 100) { return {true, depth, true}; }
inline TopicQos StatusQos(int depth = 1) { return {true, depth, true}; }
inline TopicQos CommandQos(int depth = 10) { return {true, depth, false}; }
// IMU at 100-200 Hz: room for a second of samples if the reader falls behind briefly.
inline TopicQos ImuQos(int depth = 200) { return {true, depth, false}; }
inline TopicQos WheelOdometryQos(int depth = 100) { return {true, depth, false}; }
// Replies are latched so a commander whose reader matched late still gets its answer.
inline TopicQos CommandReplyQos(int depth = 10) { return {true, depth, true}; }

}  // namespace dammloam::dds
