#include "tools/soak/soak_scene.hpp"

#include <algorithm>
#include <limits>

namespace dammloam::soak {

sim::SensorSpec SoakSensor() {
  sim::SensorSpec spec = sim::Vlp16();
  spec.name = "vlp-16-20hz";
  spec.columns = 900;
  spec.scan_period = 0.05;
  return spec;
}

sim::Simulator MakeSoakSimulator(std::uint64_t seed, std::size_t num_scans) {
  sim::SimOptions options;
  options.seed = seed;
  // A closed path: any scan index is defined; num_scans only sizes open corridor scenes.
  options.num_scans = static_cast<int>(
      std::min<std::size_t>(num_scans, std::numeric_limits<int>::max()));
  options.threads = 1;  // one core for the publisher: the daemon and the machine get the rest
  return sim::Simulator(sim::SceneKind::Outdoor, SoakSensor(), options);
}

}  // namespace dammloam::soak
