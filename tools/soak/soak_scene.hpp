#pragma once
// What the soak drives: a VLP-16 spinning at 20 Hz (1200 rpm: 16 x 900, 0.4 deg columns,
// 0.05 s per scan, 337 KiB samples; the CPU stays low) on the `outdoor` scene, a closed ~130 m
// loop between buildings driven at a constant 1.5 m/s for as long as asked (a lap is ~1740
// scans). The whole loop stays within 40 m of every point on it, so the odometry's local map
// (max_distance 100 m) is full after the first lap and then only sees the same places again.
// Scans are simulated one at a time as they are published; at --rate 20 their stamps advance
// with the wall clock.
#include <cstddef>
#include <cstdint>

#include "core/geometry/scan.hpp"
#include "tools/simulate/simulator.hpp"

namespace dammloam::soak {

inline constexpr const char* kSensorName = "vlp-16 at 20 Hz";
inline constexpr const char* kSceneName = "outdoor";

sim::SensorSpec SoakSensor();

// The same scans in every process for the same seed: a restarted publisher continues the drive,
// and the soak's parent knows the true pose of every scan.
sim::Simulator MakeSoakSimulator(std::uint64_t seed, std::size_t num_scans);

}  // namespace dammloam::soak
