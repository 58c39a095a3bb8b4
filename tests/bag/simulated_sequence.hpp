#pragma once
// The small simulated sequence the bag and input tests convert into other formats and run the
// odometry on: outdoor scene, a VLP-16 turned into 900 columns, scans taken at cruise speed
// (after the simulator's ramp-up), stamps rounded to whole nanoseconds as a recording's are (so
// that a bag stamp and times.txt name the same time).
#include <filesystem>
#include <vector>

#include "core/geometry/scan.hpp"
#include "io/sequence_io.hpp"
#include "tests/bag/bag_fixture.hpp"
#include "tools/simulate/simulator.hpp"

namespace dammloam::test {

// Writes `scans` scans to the sequence directory `dir`.
inline void WriteSimulatedOutdoorSequence(const std::filesystem::path& dir, int scans) {
  constexpr int kFirstScan = 25;  // at cruise speed
  sim::SimOptions options;
  options.num_scans = kFirstScan + scans;
  sim::SensorSpec sensor = sim::Vlp16();
  sensor.columns = 900;
  const sim::Simulator simulator(sim::SceneKind::Outdoor, sensor, options);
  std::vector<Scan> out;
  for (int i = 0; i < scans; ++i) {
    Scan scan = simulator.SimulateScan(kFirstScan + i);
    scan.t_start = StampSeconds(SecondsToStamp(scan.t_start));
    out.push_back(std::move(scan));
  }
  WriteSequence(dir, out,
                io::SequenceMeta{"vlp-16-900", simulator.sensor_model(), io::PointLayout::kXYZITR});
}

}  // namespace dammloam::test
