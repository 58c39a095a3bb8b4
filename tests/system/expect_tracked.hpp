#pragma once
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <vector>

#include "tests/system/dds_test_client.hpp"
#include "tools/simulate/simulator.hpp"

namespace dammloam::test {

// Every one of the first `scans` poses registered and not lost, and every step within 3 cm and
// 0.01 rad of the simulator's (no jump where an input dropped out or came back).
inline void ExpectTrackedAsSimulated(const std::vector<ReceivedPose>& poses,
                                     const sim::Simulator& simulator, int scans) {
  ASSERT_GE(poses.size(), static_cast<std::size_t>(scans));
  for (int i = 0; i < scans; ++i) {
    const ReceivedPose& p = poses[static_cast<std::size_t>(i)];
    EXPECT_TRUE(p.registered) << "scan " << i << ": " << p.status;
    EXPECT_NE(p.tracking, "lost") << "scan " << i;
    if (i == 0) continue;
    const Eigen::Isometry3d step = poses[static_cast<std::size_t>(i - 1)].T.inverse() * p.T;
    const Eigen::Isometry3d truth = simulator.PoseAt(simulator.ScanStartTime(i - 1)).inverse() *
                                    simulator.PoseAt(simulator.ScanStartTime(i));
    EXPECT_LT((step.translation() - truth.translation()).norm(), 0.03) << "scan " << i;
    EXPECT_LT(Eigen::AngleAxisd(step.linear().transpose() * truth.linear()).angle(), 0.01)
        << "scan " << i;
  }
}

}  // namespace dammloam::test
