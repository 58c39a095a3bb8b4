#pragma once
#include <Eigen/Core>
#include <filesystem>
#include <vector>

#include "core/geometry/point_class.hpp"

// Labelled point clouds as PCD files (fields x y z intensity label normal_x normal_y normal_z),
// written and read with PCL. Link `dammloam_pcd`; PCL headers never leak out of this library.
namespace dammloam::io {

struct LabelledCloud {
  std::vector<Eigen::Vector3d> points;   // metres
  std::vector<float> intensities;        // empty = all 0
  std::vector<PointClass> labels;        // empty = all Unknown
  std::vector<Eigen::Vector3d> normals;  // empty = all 0 (unknown)

  std::size_t size() const { return points.size(); }
};

enum class PcdEncoding { kBinary, kBinaryCompressed, kAscii };

// Throws IoError naming the file when it cannot be written or a per-point vector has the wrong
// length.
void WriteLabelledPcd(const std::filesystem::path& file, const LabelledCloud& cloud,
                      PcdEncoding encoding = PcdEncoding::kBinary);

// Reads any PCD with at least x y z (any numeric field types). intensity, label and normal_*
// are filled when present, otherwise left empty. A label outside the five classes is an IoError
// naming the file and point index.
LabelledCloud ReadLabelledPcd(const std::filesystem::path& file);

}  // namespace dammloam::io
