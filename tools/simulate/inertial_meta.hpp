#pragma once
// The meta.json keys of a simulated run's IMU and wheel streams (header-only: dammloam_sim
// itself knows no file formats; the simulate and benchmark executables link dammloam_io).
#include "io/sequence_meta.hpp"
#include "tools/simulate/inertial_streams.hpp"

namespace dammloam::sim {

// Sets meta's imu_extrinsic / imu / base_extrinsic for the streams that were simulated.
inline void DescribeStreams(const InertialStreams& streams, io::SequenceMeta* meta) {
  if (streams.imu) {
    meta->T_sensor_imu = streams.imu_options.description.T_sensor_imu;
    meta->imu_noise = streams.imu_options.description.noise;
    meta->imu_time_offset = streams.imu_options.description.time_offset;
  }
  if (streams.wheel) meta->T_sensor_base = streams.T_sensor_base;
}

}  // namespace dammloam::sim
