#pragma once
#include <string>

#include "core/backend/loop_event.hpp"

namespace dammloam::tools {

// One LoopEvent as a single-line JSON object (no trailing newline), for `--events` files:
// keyframe ids, scan indices, stamps, Scan Context score, yaw guess, inlier ratio, residual,
// the registered relative pose [tx ty tz qx qy qz qw], accepted and the reason.
std::string LoopEventJsonLine(const backend::LoopEvent& event);

}  // namespace dammloam::tools
