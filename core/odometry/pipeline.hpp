#pragma once

#include "core/geometry/scan.hpp"
#include "core/odometry/odometry.hpp"
#include "core/odometry/odometry_config.hpp"
#include "core/odometry/odometry_result.hpp"
#include "core/preprocess/feature_extractor.hpp"

namespace dammloam {

// The whole front end on one thread: Extract (with the predicted orientation), then Register.
// The daemon runs the same two calls on two threads in lock-step and gets the same results.
class OdometryPipeline {
 public:
  OdometryPipeline(const OdometryConfig& config, const SensorModel& sensor);

  OdometryResult Process(Scan scan);
  // The feature half alone (what the daemon's first thread does); one thread at a time.
  ClassifiedScan Extract(Scan scan);

  const Odometry& odometry() const { return odometry_; }
  Odometry& odometry() { return odometry_; }

 private:
  OdometryConfig config_;
  SensorModel sensor_;
  FeatureExtractor extractor_;
  FeatureWorkspace features_;
  Odometry odometry_;
};

}  // namespace dammloam
