#pragma once
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "core/geometry/scan.hpp"
#include "tools/simulate/scenes.hpp"
#include "tools/simulate/sensor_spec.hpp"

namespace dammloam::sim {

struct SimOptions {
  std::uint64_t seed = 1;
  double noise_sigma = 0.01;  // Gaussian range noise, metres
  double dropout = 0.0;       // probability that a return is lost
  double speed = 0.0;         // m/s along the path; <= 0: the scene's default
  int num_scans = 600;        // sizes corridor scenes so the whole drive stays inside
  double t0 = 1700000000.0;   // start time of scan 0, seconds
  int threads = 0;            // 1: plain loop; otherwise a TBB parallel_for over columns
};

// Ray-casts a simulated spinning LiDAR moving through an analytic scene. Every column fires at
// its own time t_start + column / columns * scan_period from the sensor pose at that time, so
// scans carry the motion distortion of real ones. No file I/O: see main.cpp for the writer.
class Simulator {
 public:
  Simulator(SceneKind kind, SensorSpec sensor, SimOptions options = {});

  // Scan `index` (0-based): t_start = ScanStartTime(index), points in firing order. The same
  // index and seed always give the same scan, whatever the thread count.
  Scan SimulateScan(int index) const;

  // T_world_sensor at absolute time t (the clock of Scan::t_start). The pose of a point is
  // PoseAt(scan.t_start + scan.times[i]), computed exactly like that by the simulator itself.
  Eigen::Isometry3d PoseAt(double t) const;
  double ScanStartTime(int index) const;

  SensorModel sensor_model() const { return ToSensorModel(sensor_); }
  const SensorSpec& sensor() const { return sensor_; }
  const SimOptions& options() const { return options_; }
  SceneKind kind() const { return kind_; }
  const Scene& scene() const { return world_.scene; }
  const Trajectory& trajectory() const { return trajectory_; }

  static std::vector<std::string> SceneNames();

 private:
  struct Return {
    Eigen::Vector3d point;
    float intensity = 0.0f;
    bool valid = false;
  };
  void SimulateColumn(int index, int column, double t_start, Return* out) const;

  SceneKind kind_;
  SensorSpec sensor_;
  SimOptions options_;
  World world_;
  Trajectory trajectory_;
  std::vector<Eigen::Vector3d> beam_dirs_;  // [column * rings + ring], sensor frame, unit
};

}  // namespace dammloam::sim
