#include "core/odometry/pipeline.hpp"

#include "core/odometry/unclassified_scan.hpp"

namespace dammloam {

OdometryPipeline::OdometryPipeline(const OdometryConfig& config, const SensorModel& sensor)
    : config_(config),
      sensor_(sensor),
      extractor_(config.preprocess, sensor),
      odometry_(config, sensor) {}

ClassifiedScan OdometryPipeline::Extract(Scan scan) {
  // The KISS-ICP-like ablation has no use for classes: skipping the feature stage keeps its
  // timing honest.
  if (config_.registration.mode == RegistrationMode::kPointToPoint) {
    return UnclassifiedScan(std::move(scan), config_.preprocess, sensor_);
  }
  return extractor_.Extract(std::move(scan), odometry_.PredictedOrientation(), features_);
}

OdometryResult OdometryPipeline::Process(Scan scan) {
  return odometry_.Register(Extract(std::move(scan)));
}

}  // namespace dammloam
