#pragma once
#include <Eigen/Core>
#include <filesystem>
#include <vector>

namespace dammloam::eval {

// Top view (x right, y up) of a ground-truth and an estimated trajectory, equal scale on both
// axes, with axes, tick labels and a scale bar in metres, a legend and start/end markers.
// Hand-written SVG, no dependencies. Throws io::IoError when the file cannot be written.
void WriteTopViewSvg(const std::filesystem::path& file, const std::vector<Eigen::Vector3d>& gt,
                     const std::vector<Eigen::Vector3d>& est);

}  // namespace dammloam::eval
