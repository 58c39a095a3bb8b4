#pragma once
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "core/geometry/point_class.hpp"

namespace dammloam::eval {

// A top view of a labelled map (x right, y up), each point a pixel coloured by its class, the
// highest point of a pixel on top; optional marked points (drawn larger, on top of everything)
// and a trajectory. White background, a scale bar of a round length in the lower left corner.
struct TopViewOptions {
  int width = 1600;          // pixels; the height follows the map's extent
  double metres_per_pixel = 0.0;  // 0: fit the map into `width`
  int margin = 20;           // pixels around the map
};

struct TopView {
  int width = 0, height = 0;
  double metres_per_pixel = 0.0;
  std::vector<std::uint8_t> rgb;  // width * height * 3, row 0 at the top
};

using Rgb = std::array<std::uint8_t, 3>;
Rgb ClassColour(PointClass c);
inline constexpr Rgb kMarkColour{230, 0, 200};
inline constexpr Rgb kTrajectoryColour{0, 0, 0};

// Throws std::invalid_argument for an empty map or labels of another length than the points.
TopView RenderTopView(const std::vector<Eigen::Vector3d>& points, const std::vector<PointClass>& labels,
                      const std::vector<Eigen::Vector3d>& marked,
                      const std::vector<Eigen::Vector3d>& trajectory, const TopViewOptions& options);

// PNG (stb_image_write). Throws io::IoError naming the file when it cannot be written.
void WritePng(const std::filesystem::path& file, const TopView& view);

}  // namespace dammloam::eval
