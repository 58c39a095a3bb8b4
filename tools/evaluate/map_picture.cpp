#include "tools/evaluate/map_picture.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "io/io_error.hpp"

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_WRITE_NO_STDIO_WRITE_HDR
#include <stb/stb_image_write.h>

namespace dammloam::eval {

namespace {

struct Frame {
  Eigen::Vector2d min;
  double mpp = 0.1;
  int width = 0, height = 0, margin = 0;

  bool Pixel(const Eigen::Vector3d& p, int& x, int& y) const {
    x = margin + static_cast<int>((p.x() - min.x()) / mpp);
    y = height - 1 - margin - static_cast<int>((p.y() - min.y()) / mpp);
    return x >= 0 && y >= 0 && x < width && y < height;
  }
};

void Put(TopView& view, int x, int y, const Rgb& c) {
  if (x < 0 || y < 0 || x >= view.width || y >= view.height) return;
  std::uint8_t* px = &view.rgb[(static_cast<std::size_t>(y) * view.width + x) * 3];
  px[0] = c[0];
  px[1] = c[1];
  px[2] = c[2];
}

Frame FrameFor(const std::vector<Eigen::Vector3d>& points, const TopViewOptions& o) {
  Frame f;
  f.margin = o.margin;
  Eigen::Vector2d lo = points.front().head<2>(), hi = lo;
  for (const Eigen::Vector3d& p : points) {
    lo = lo.cwiseMin(p.head<2>());
    hi = hi.cwiseMax(p.head<2>());
  }
  const Eigen::Vector2d extent = (hi - lo).cwiseMax(Eigen::Vector2d::Constant(1.0));
  f.min = lo;
  f.mpp = o.metres_per_pixel > 0.0 ? o.metres_per_pixel : extent.x() / std::max(1, o.width - 2 * o.margin);
  f.width = static_cast<int>(std::ceil(extent.x() / f.mpp)) + 2 * o.margin + 1;
  f.height = static_cast<int>(std::ceil(extent.y() / f.mpp)) + 2 * o.margin + 1;
  if (static_cast<double>(f.width) * f.height > 1e8) {
    throw std::invalid_argument("the picture would have more than 1e8 pixels: choose a coarser --resolution");
  }
  return f;
}

// The largest 1, 2 or 5 x 10^k metres that fits in a fifth of the picture.
double ScaleBarMetres(double picture_metres) {
  const double target = picture_metres / 5.0;
  const double decade = std::pow(10.0, std::floor(std::log10(target)));
  for (double m : {5.0, 2.0, 1.0}) {
    if (m * decade <= target) return m * decade;
  }
  return decade;
}

void DrawScaleBar(TopView& view, const Frame& f) {
  const double metres = ScaleBarMetres(f.width * f.mpp);
  const int length = static_cast<int>(metres / f.mpp);
  const int y = f.height - f.margin / 2 - 1;
  for (int x = f.margin; x <= f.margin + length; ++x) {
    for (int dy = -1; dy <= 1; ++dy) Put(view, x, y + dy, kTrajectoryColour);
  }
  for (int dy = -3; dy <= 1; ++dy) {  // ticks at both ends
    Put(view, f.margin, y + dy, kTrajectoryColour);
    Put(view, f.margin + length, y + dy, kTrajectoryColour);
  }
}

}  // namespace

Rgb ClassColour(PointClass c) {
  switch (c) {
    case PointClass::Ground: return {205, 205, 205};
    case PointClass::Roof: return {235, 150, 20};
    case PointClass::Wall: return {30, 90, 210};
    case PointClass::Edge: return {210, 30, 40};
    case PointClass::Moving: return kMarkColour;
    case PointClass::Unknown: break;
  }
  return {90, 150, 90};
}

TopView RenderTopView(const std::vector<Eigen::Vector3d>& points, const std::vector<PointClass>& labels,
                      const std::vector<Eigen::Vector3d>& marked,
                      const std::vector<Eigen::Vector3d>& trajectory, const TopViewOptions& options) {
  if (points.empty()) throw std::invalid_argument("the map has no points");
  if (!labels.empty() && labels.size() != points.size()) {
    throw std::invalid_argument("the map has " + std::to_string(labels.size()) + " labels for " +
                                std::to_string(points.size()) + " points");
  }
  const Frame f = FrameFor(points, options);
  TopView view;
  view.width = f.width;
  view.height = f.height;
  view.metres_per_pixel = f.mpp;
  view.rgb.assign(static_cast<std::size_t>(f.width) * f.height * 3, 255);
  // Lowest first, so that the highest point of each pixel is the one seen from above.
  std::vector<std::size_t> order(points.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return points[a].z() < points[b].z(); });
  int x = 0, y = 0;
  for (std::size_t i : order) {
    if (f.Pixel(points[i], x, y)) Put(view, x, y, ClassColour(labels.empty() ? PointClass::Unknown : labels[i]));
  }
  for (std::size_t i = 1; i < trajectory.size(); ++i) {
    const Eigen::Vector3d step = trajectory[i] - trajectory[i - 1];
    const int n = std::max(1, static_cast<int>(step.head<2>().norm() / f.mpp));
    for (int k = 0; k <= n; ++k) {
      if (f.Pixel(trajectory[i - 1] + step * (static_cast<double>(k) / n), x, y)) Put(view, x, y, kTrajectoryColour);
    }
  }
  for (const Eigen::Vector3d& p : marked) {
    if (!f.Pixel(p, x, y)) continue;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) Put(view, x + dx, y + dy, kMarkColour);
    }
  }
  DrawScaleBar(view, f);
  return view;
}

void WritePng(const std::filesystem::path& file, const TopView& view) {
  if (stbi_write_png(file.c_str(), view.width, view.height, 3, view.rgb.data(), view.width * 3) == 0) {
    throw io::IoError(file.string() + ": cannot write the PNG");
  }
}

}  // namespace dammloam::eval
