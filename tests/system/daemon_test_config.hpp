#pragma once
// The in-process daemon set-up the pipeline suites share.
#include <cstdint>

#include "services/dammloamd/daemon_config.hpp"
#include "tools/simulate/simulator.hpp"

namespace dammloam::test {

// A daemon on its own domain for `simulator`'s sensor: no loop closure (the suites check the
// odometry path), a labelled cloud for every scan and a fast status period, so that a test sees
// every output within seconds.
inline daemon::DaemonConfig PipelineTestConfig(std::uint32_t domain,
                                               const sim::Simulator& simulator) {
  daemon::DaemonConfig config;
  config.domain = domain;
  config.sensor = simulator.sensor_model();
  config.loop_closure = false;
  config.labelled_cloud_every = 1;
  config.status_period = 0.2;
  return config;
}

}  // namespace dammloam::test
