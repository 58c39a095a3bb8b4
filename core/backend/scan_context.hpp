#pragma once
#include <Eigen/Core>
#include <vector>

namespace dammloam::backend {

// Scan Context (Kim & Kim, IROS 2018), written from the paper's description.
struct ScanContextConfig {
  int rings = 20;              // radial bins
  int sectors = 60;            // azimuthal bins
  double max_range = 80.0;     // metres; use ~20-30 indoors
  double sensor_height = 2.0;  // added to z so that heights are positive (empty bin = 0)

  bool operator==(const ScanContextConfig&) const = default;
};

// rings x sectors matrix of maximum point height per polar bin, plus its ring key.
struct ScanContext {
  Eigen::MatrixXf grid;        // (rings, sectors); column j covers azimuth [j, j+1) * 2pi/sectors
  Eigen::VectorXf ring_key;    // (rings): rotation-invariant summary used for retrieval
  bool empty() const { return grid.size() == 0; }
};

// Builds the descriptor of a cloud given in the sensor frame (x forward, z up).
ScanContext MakeScanContext(const std::vector<Eigen::Vector3d>& points_sensor,
                            const ScanContextConfig& config);

// Ring key: per ring, the fraction of sectors that are occupied (paper: ring occupancy).
// Invariant to yaw because a yaw rotation only shifts the columns.
Eigen::VectorXf RingKey(const Eigen::MatrixXf& grid);

struct ScanContextMatch {
  double distance = 2.0;  // in [0, 1]; 0 = identical (up to the column shift)
  int shift = 0;          // candidate column (j + shift) matches query column j
  double yaw_rad = 0.0;   // rotation about z taking query-frame azimuths to candidate's
};

// Column-shift distance: for every circular shift of the candidate, the mean over columns of
// (1 - cosine similarity), skipping columns empty in either descriptor; the best shift wins.
ScanContextMatch CompareScanContexts(const ScanContext& query, const ScanContext& candidate);

}  // namespace dammloam::backend
