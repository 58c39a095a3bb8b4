#include "core/backend/point_kdtree.hpp"

#include <nanoflann.hpp>

namespace dammloam::backend {

struct PointKdTree::Impl {
  struct Cloud {
    std::vector<Eigen::Vector3d> points;
    std::size_t kdtree_get_point_count() const { return points.size(); }
    double kdtree_get_pt(std::size_t i, std::size_t d) const { return points[i][static_cast<Eigen::Index>(d)]; }
    template <class BBox>
    bool kdtree_get_bbox(BBox&) const { return false; }
  };
  using Index = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Cloud>,
                                                    Cloud, 3, std::uint32_t>;
  Cloud cloud;
  std::unique_ptr<Index> index;
};

PointKdTree::PointKdTree(std::vector<Eigen::Vector3d> points) : impl_(std::make_unique<Impl>()) {
  impl_->cloud.points = std::move(points);
  impl_->index = std::make_unique<Impl::Index>(3, impl_->cloud,
                                               nanoflann::KDTreeSingleIndexAdaptorParams(16));
}

PointKdTree::~PointKdTree() = default;
PointKdTree::PointKdTree(PointKdTree&&) noexcept = default;
PointKdTree& PointKdTree::operator=(PointKdTree&&) noexcept = default;

const std::vector<Eigen::Vector3d>& PointKdTree::points() const { return impl_->cloud.points; }

bool PointKdTree::Nearest(const Eigen::Vector3d& query, std::uint32_t& index,
                          double& squared) const {
  if (impl_->cloud.points.empty()) return false;
  return impl_->index->knnSearch(query.data(), 1, &index, &squared) == 1;
}

std::vector<std::uint32_t> PointKdTree::Knn(const Eigen::Vector3d& query, std::size_t k) const {
  std::vector<std::uint32_t> indices(k);
  std::vector<double> squared(k);
  const std::size_t found = impl_->index->knnSearch(query.data(), k, indices.data(),
                                                    squared.data());
  indices.resize(found);
  return indices;
}

}  // namespace dammloam::backend
