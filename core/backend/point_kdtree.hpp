#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

namespace dammloam::backend {

// Static 3-D k-d tree (nanoflann) over a copy of the points; nanoflann stays in the .cpp.
class PointKdTree {
 public:
  explicit PointKdTree(std::vector<Eigen::Vector3d> points);
  ~PointKdTree();
  PointKdTree(PointKdTree&&) noexcept;
  PointKdTree& operator=(PointKdTree&&) noexcept;

  const std::vector<Eigen::Vector3d>& points() const;
  std::size_t size() const { return points().size(); }
  // Nearest point: false when the tree is empty.
  bool Nearest(const Eigen::Vector3d& query, std::uint32_t& index, double& squared) const;
  // Up to k nearest indices, closest first.
  std::vector<std::uint32_t> Knn(const Eigen::Vector3d& query, std::size_t k) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dammloam::backend
