#pragma once
// Short simulated sequences for the DDS tests (VLP-16 with fewer columns: fast under sanitizers).
#include <filesystem>
#include <string>

#include "io/sequence_io.hpp"
#include "tools/simulate/simulator.hpp"

namespace dammloam::test {

inline sim::Simulator SmallSimulator(int num_scans) {
  sim::SensorSpec spec = sim::Vlp16();
  spec.columns = 900;
  sim::SimOptions options;
  options.num_scans = num_scans;
  return sim::Simulator(sim::SceneKind::Zigzag, spec, options);
}

// Writes the simulator's first num_scans scans as a sequence directory under dir.
inline void WriteSequence(const sim::Simulator& simulator, int num_scans,
                          const std::filesystem::path& dir) {
  io::SequenceMeta meta;
  meta.sensor = "vlp-16-900";
  meta.model = simulator.sensor_model();
  io::SequenceWriter writer(dir, meta, /*overwrite=*/true);
  for (int i = 0; i < num_scans; ++i) writer.Write(simulator.SimulateScan(i));
}

}  // namespace dammloam::test
