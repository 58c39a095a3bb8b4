#include "core/preprocess/normal_map.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace dammloam {

NormalMap::NormalMap(const RangeImage& image, const NormalMapConfig& config)
    : NormalMap(config) {
  Build(image);
}

NormalMap::NormalMap(const NormalMapConfig& config)
    : cot_min_incidence_(
          static_cast<float>(1.0 / std::tan(config.min_incidence_deg * std::numbers::pi / 180.0))),
      range_noise_(static_cast<float>(config.range_noise)),
      min_tangent_sine_(static_cast<float>(config.min_tangent_sine)),
      min_baseline_(static_cast<float>(config.min_baseline)),
      max_stencil_(std::max(1, config.max_stencil)) {}

void NormalMap::Build(const RangeImage& image) {
  rows_ = image.rows();
  cols_ = image.cols();
  column_spacing_rad_ = 2.0f * std::numbers::pi_v<float> / static_cast<float>(std::max(1, cols_));
  row_spacing_rad_ = static_cast<float>(image.row_spacing_rad());
  normals_.assign(static_cast<std::size_t>(rows_) * cols_, Eigen::Vector3f::Zero());
  valid_.assign(static_cast<std::size_t>(rows_) * cols_, 0);
  // Rows are independent; grain of a few rows keeps the task overhead negligible.
  tbb::parallel_for(tbb::blocked_range<int>(0, rows_ < 2 ? 0 : rows_, 4),
                    [&](const tbb::blocked_range<int>& range) {
                      for (int r = range.begin(); r < range.end(); ++r) ComputeRow(image, r);
                    });
}

// Same surface if the range jump is no larger than a plane seen at the minimum incidence angle
// would produce between these two rays: |dr| <= r_mean * angle(p, q) * cot(beta_min) + noise.
// The ray angle is taken as the chord between unit directions (exact enough below a few
// degrees), which needs no square root.
[[gnu::always_inline]] inline bool NormalMap::Continuous(const Eigen::Vector3f& p, float rp,
                                                        const Eigen::Vector3f& q,
                                                        float rq) const {
  const float jump = std::abs(rp - rq) - range_noise_;
  if (jump <= 0.0f) return true;
  const float chord2 = (p / rp - q / rq).squaredNorm();  // stable in single precision
  const float scale = 0.5f * (rp + rq) * cot_min_incidence_;
  return jump * jump <= scale * scale * chord2;
}

// Paper eq. (surface tangents) takes the immediate neighbours. At 0.35 deg column spacing and
// centimetre range noise those are only a few centimetres apart, so the normal's noise would
// exceed the 15 deg edge threshold on a flat floor. The stencil therefore widens, one pixel at a
// time and only while the surface stays continuous, until the tangent spans 2 * min_baseline
// (a sensor-independent length). Empty pixels (no return, or azimuth aliasing between firing
// angles and image columns) are stepped over rather than voiding the normal.
// Returns the tangent, or nothing if no continuous neighbour exists on both sides.
template <bool kAlongRow>
std::optional<Eigen::Vector3f> NormalMap::Tangent(const RangeImage& image, int r, int c) const {
  const Eigen::Vector3f& p = image.point(r, c);
  struct Side {
    const Eigen::Vector3f* point = nullptr;
    float range = 0.0f;
    bool blocked = false;  // a discontinuity: nothing farther on this side is the same surface
  };
  const float rp = image.range(r, c);
  const float noise_sq = range_noise_ * range_noise_;
  const float baseline_sq = 4.0f * min_baseline_ * min_baseline_;
  Side sides[2];
  std::optional<Eigen::Vector3f> tangent;
  // Pixels are dense (0.35 deg at 1024 columns): past the immediate neighbour (the paper's
  // discontinuity test) the walk takes strides, so that reaching the baseline costs about two
  // steps at any range instead of up to max_stencil.
  const int stride = Stride(rp, kAlongRow ? column_spacing_rad_ : row_spacing_rad_);
  for (int k = 1; k <= max_stencil_; k = k == 1 ? 1 + stride : k + stride) {
    for (int s = 0; s < 2; ++s) {
      Side& side = sides[s];
      if (side.blocked) continue;
      const int step = s == 0 ? -k : k;
      int rr = r, cc = c;
      if constexpr (kAlongRow) {
        cc += step;
        cc = cc < 0 ? cc + cols_ : (cc >= cols_ ? cc - cols_ : cc);  // 360 deg wrap
      } else {
        rr += step;
        if (rr < 0 || rr >= rows_) {  // image top/bottom: keep the nearest row found
          side.blocked = true;
          continue;
        }
      }
      const float rq = image.range(rr, cc);
      if (rq <= 0.0f) continue;  // empty pixel
      const Eigen::Vector3f& q = image.point(rr, cc);
      // Continuity is judged against the previous pixel of the chain (a wide stencil would
      // otherwise tolerate a jump to another surface), and a widened tangent must stay on the
      // line it started (so it stops at a corner instead of mixing two planes). That line is
      // only known to the noise of its short first segment: the tolerance grows as
      // noise * (1 + |q - p| / |prev - p|), or the first noisy neighbour would end every
      // chain and leave centimetre tangents (noisy walls classified as edges).
      const Eigen::Vector3f& prev = side.point ? *side.point : p;
      const float r_prev = side.point ? side.range : rp;
      if (!Continuous(prev, r_prev, q, rq) ||
          (side.point && (q - p).cross(prev - p).squaredNorm() >
                             2.0f * noise_sq * ((prev - p).squaredNorm() + (q - p).squaredNorm()))) {
        // Paper: a pixel next to a range discontinuity has no normal.
        if (!side.point) return std::nullopt;
        side.blocked = true;
        continue;
      }
      side.point = &q;
      side.range = rq;
    }
    // One-sided differences at the image border or next to a discontinuity use the centre.
    if (!sides[0].point && !sides[1].point) continue;
    const Eigen::Vector3f& a = sides[0].point ? *sides[0].point : p;
    const Eigen::Vector3f& b = sides[1].point ? *sides[1].point : p;
    tangent = b - a;
    // Neither side can grow any more: a wider stencil would only repeat this tangent.
    if (sides[0].blocked && sides[1].blocked) break;
    if (sides[0].point && sides[1].point && tangent->squaredNorm() >= baseline_sq) break;
  }
  return tangent;
}

inline int NormalMap::Stride(float range, float pixel_angle) const {
  if (!(pixel_angle > 0.0f)) return 1;
  const float pixels_to_baseline = min_baseline_ / std::max(range * pixel_angle, 1e-6f);
  return std::clamp(static_cast<int>(pixels_to_baseline / 2.0f), 1, std::max(1, max_stencil_ / 2));
}

void NormalMap::ComputeRow(const RangeImage& image, int r) {
  for (int c = 0; c < cols_; ++c) {
    if (image.empty(r, c)) continue;
    const std::optional<Eigen::Vector3f> t_u = Tangent<true>(image, r, c);
    if (!t_u) continue;
    const std::optional<Eigen::Vector3f> t_v = Tangent<false>(image, r, c);
    if (!t_v) continue;
    // Paper eq. (normal vector).
    Eigen::Vector3f n = t_u->cross(*t_v);
    const float norm = n.norm();
    if (!(norm > min_tangent_sine_ * t_u->norm() * t_v->norm())) continue;
    n /= norm;
    if (n.dot(image.point(r, c)) > 0.0f) n = -n;  // paper eq. (normal flipping): face the sensor
    const std::size_t pixel = static_cast<std::size_t>(r) * cols_ + c;
    normals_[pixel] = n;
    valid_[pixel] = 1;
  }
}

}  // namespace dammloam
