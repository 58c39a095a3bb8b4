#pragma once
#include <string>

#include "tools/evaluate/trajectory_metrics.hpp"

namespace dammloam::eval {

// Human-readable table (APE, RPE, drift, alignment).
std::string FormatTable(const TrajectoryMetrics& metrics);

// {"ape":{...},"rpe":{...},"drift_percent":..,"end_drift_m":..,"path_length_m":..,"pairs":N,
//  "unmatched_gt":..,"unmatched_est":..,"alignment":{"translation":[3],"quaternion_xyzw":[4]}}.
// NaN values become null.
std::string FormatJson(const TrajectoryMetrics& metrics);

}  // namespace dammloam::eval
