#pragma once
// Compares decoded Velodyne clouds with the reference clouds other drivers exported from the
// same captures (PCD files in the shared data folder).
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

namespace dammloam::drivers::testing {

// Median distance from each query point to its nearest neighbour in `ref` (grid hash search),
// and the fraction within `within` metres.
struct NnStats {
  double median = 1e9;
  double fraction_within = 0.0;
};
inline NnStats NearestNeighbourStats(const std::vector<Eigen::Vector3d>& query,
                                     const std::vector<Eigen::Vector3d>& ref, double within = 0.03) {
  const double cell = 0.1;
  auto key = [&](const Eigen::Vector3d& p) {
    const long x = std::lround(std::floor(p.x() / cell)), y = std::lround(std::floor(p.y() / cell)),
               z = std::lround(std::floor(p.z() / cell));
    return (x * 73856093) ^ (y * 19349663) ^ (z * 83492791);
  };
  std::unordered_multimap<long, std::size_t> grid;
  for (std::size_t i = 0; i < ref.size(); ++i) grid.emplace(key(ref[i]), i);
  std::vector<double> d;
  std::size_t close = 0;
  for (const auto& q : query) {
    double best = 1.0;  // search radius: one cell around
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const Eigen::Vector3d s = q + Eigen::Vector3d(dx, dy, dz) * cell;
          auto [b, e] = grid.equal_range(key(s));
          for (auto it = b; it != e; ++it) best = std::min(best, (ref[it->second] - q).norm());
        }
    d.push_back(best);
    if (best < within) ++close;
  }
  NnStats s;
  if (d.empty()) return s;
  std::nth_element(d.begin(), d.begin() + static_cast<long>(d.size() / 2), d.end());
  s.median = d[d.size() / 2];
  s.fraction_within = static_cast<double>(close) / static_cast<double>(query.size());
  return s;
}

// x y z of a binary PCD (float32 x, y, z as the first three fields; other fields skipped).
inline std::vector<Eigen::Vector3d> ReadPcdXyz(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::string line;
  std::vector<int> sizes;
  std::size_t points = 0;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string key;
    ls >> key;
    if (key == "SIZE") {
      for (int s; ls >> s;) sizes.push_back(s);
    } else if (key == "POINTS") {
      ls >> points;
    } else if (key == "DATA") {
      break;
    }
  }
  int stride = 0;
  for (int s : sizes) stride += s;
  std::vector<char> buf(static_cast<std::size_t>(stride));
  std::vector<Eigen::Vector3d> out;
  for (std::size_t i = 0; i < points && in.read(buf.data(), stride); ++i) {
    float xyz[3];
    std::memcpy(xyz, buf.data(), sizeof(xyz));
    out.emplace_back(xyz[0], xyz[1], xyz[2]);
  }
  return out;
}

}  // namespace dammloam::drivers::testing
