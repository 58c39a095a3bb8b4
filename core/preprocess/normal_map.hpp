#pragma once
#include <optional>
#include <Eigen/Core>
#include <Eigen/Geometry>  // cross product
#include <cstdint>
#include <vector>

#include "core/preprocess/preprocess_config.hpp"
#include "core/preprocess/range_image.hpp"

namespace dammloam {

// Per-pixel surface normals of a range image (paper Sec. III-A.2):
//   t_u = p(r, c+1) - p(r, c-1)   (columns wrap around 360 deg)
//   t_v = p(r+1, c) - p(r-1, c)   (rows do not wrap; the top and bottom rows use p(r, c)
//                                  for their missing neighbour: a one-sided difference)
//   n   = (t_u x t_v) / |t_u x t_v|, flipped so that n . p <= 0 (facing the sensor).
// A normal is invalid when one of the four neighbours is empty, when a neighbour lies across a
// depth discontinuity (see NormalMapConfig), or when the tangents are (nearly) parallel.
class NormalMap {
 public:
  NormalMap(const RangeImage& image, const NormalMapConfig& config);
  // Empty until Build: for a map kept between scans (FeatureWorkspace).
  explicit NormalMap(const NormalMapConfig& config);

  // The normals of `image`, replacing the last ones; no allocation once an image as large
  // has been seen.
  void Build(const RangeImage& image);

  int rows() const { return rows_; }
  int cols() const { return cols_; }
  bool valid(int r, int c) const { return valid_[r * cols_ + c] != 0; }
  // Unit normal in the sensor frame; zero where invalid.
  const Eigen::Vector3f& normal(int r, int c) const { return normals_[r * cols_ + c]; }
  // Flat (row-major) views for the classifier.
  const std::vector<Eigen::Vector3f>& normals() const { return normals_; }
  const std::vector<std::uint8_t>& validity() const { return valid_; }

 private:
  void ComputeRow(const RangeImage& image, int r);
  // Single precision: centimetre geometry within 100 m loses nothing, and it halves the
  // memory traffic of the stencil walk that dominates this stage.
  // kAlongRow: t_u (columns, wrapping around), else t_v (rows, clipped at the image edges).
  template <bool kAlongRow>
  std::optional<Eigen::Vector3f> Tangent(const RangeImage& image, int r, int c) const;
  int Stride(float range, float pixel_angle) const;
  bool Continuous(const Eigen::Vector3f& p, float rp, const Eigen::Vector3f& q, float rq) const;

  int rows_ = 0;
  int cols_ = 0;
  float cot_min_incidence_;
  float range_noise_;
  float min_tangent_sine_;
  float min_baseline_;
  int max_stencil_;
  float column_spacing_rad_ = 0.0f;
  float row_spacing_rad_ = 0.0f;  // 0 when the sensor's vertical angles are unknown: no strides
  std::vector<Eigen::Vector3f> normals_;
  std::vector<std::uint8_t> valid_;
};

}  // namespace dammloam
