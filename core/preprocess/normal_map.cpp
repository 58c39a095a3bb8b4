#include "core/preprocess/normal_map.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace dammloam {

NormalMap::NormalMap(const RangeImage& image, const NormalMapConfig& config)
    : rows_(image.rows()),
      cols_(image.cols()),
      cot_min_incidence_(1.0 / std::tan(config.min_incidence_deg * std::numbers::pi / 180.0)),
      range_noise_(config.range_noise),
      min_tangent_sine_(config.min_tangent_sine),
      normals_(static_cast<std::size_t>(rows_) * cols_, Eigen::Vector3f::Zero()),
      valid_(static_cast<std::size_t>(rows_) * cols_, 0) {
  // Rows are independent; grain of a few rows keeps the task overhead negligible.
  tbb::parallel_for(tbb::blocked_range<int>(0, rows_ < 2 ? 0 : rows_, 4),
                    [&](const tbb::blocked_range<int>& range) {
                      for (int r = range.begin(); r < range.end(); ++r) ComputeRow(image, r);
                    });
}

// Same surface if the range jump is no larger than a plane seen at the minimum incidence angle
// would produce between these two rays: |dr| <= r_mean * angle(p, q) * cot(beta_min) + noise.
// The ray angle is taken as the chord between unit directions, 2 - 2 cos (exact enough below a
// few degrees), which needs no square root.
bool NormalMap::Continuous(const Eigen::Vector3d& p, double rp, const Eigen::Vector3d& q,
                           double rq) const {
  const double jump = std::abs(rp - rq) - range_noise_;
  if (jump <= 0.0) return true;
  const double chord2 = 2.0 - 2.0 * p.dot(q) / (rp * rq);
  const double scale = 0.5 * (rp + rq) * cot_min_incidence_;
  return jump * jump <= scale * scale * chord2;
}

void NormalMap::ComputeRow(const RangeImage& image, int r) {
  // The first and last rows have no neighbour outside the image: they use a one-sided
  // difference along the rows instead of losing a whole beam (1/8 of a VLP-16).
  const int above = r > 0 ? r - 1 : r;
  const int below = r + 1 < rows_ ? r + 1 : r;
  for (int c = 0; c < cols_; ++c) {
    if (image.empty(r, c)) continue;
    const int left = c == 0 ? cols_ - 1 : c - 1;
    const int right = c + 1 == cols_ ? 0 : c + 1;
    if (image.empty(r, left) || image.empty(r, right) || image.empty(above, c) ||
        image.empty(below, c)) {
      continue;
    }
    const Eigen::Vector3d& p = image.point(r, c);
    const Eigen::Vector3d& pl = image.point(r, left);
    const Eigen::Vector3d& pr = image.point(r, right);
    const Eigen::Vector3d& pu = image.point(above, c);
    const Eigen::Vector3d& pd = image.point(below, c);
    const double rp = image.range(r, c);
    if (!Continuous(p, rp, pl, image.range(r, left)) ||
        !Continuous(p, rp, pr, image.range(r, right)) ||
        !Continuous(p, rp, pu, image.range(above, c)) ||
        !Continuous(p, rp, pd, image.range(below, c))) {
      continue;
    }
    // Paper eqs. (surface tangents, normal vector).
    const Eigen::Vector3d t_u = pr - pl;
    const Eigen::Vector3d t_v = pd - pu;
    Eigen::Vector3d n = t_u.cross(t_v);
    const double norm = n.norm();
    if (!(norm > min_tangent_sine_ * t_u.norm() * t_v.norm())) continue;
    n /= norm;
    if (n.dot(p) > 0.0) n = -n;  // paper eq. (normal flipping): face the sensor
    const std::size_t pixel = static_cast<std::size_t>(r) * cols_ + c;
    normals_[pixel] = n.cast<float>();
    valid_[pixel] = 1;
  }
}

}  // namespace dammloam
