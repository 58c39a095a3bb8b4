// dammloam-map-picture's top view: pixels where the points are, the highest on top, marks over
// everything, and a PNG that decodes to the same size.
#include <gtest/gtest.h>

#include <fstream>

#include "io/io_error.hpp"
#include "tests/support/temp_dir.hpp"
#include "tools/evaluate/map_picture.hpp"

namespace dammloam::eval {
namespace {

Rgb At(const TopView& view, int x, int y) {
  const std::uint8_t* p = &view.rgb[(static_cast<std::size_t>(y) * view.width + x) * 3];
  return {p[0], p[1], p[2]};
}

TopViewOptions Fixed() {
  TopViewOptions o;
  o.metres_per_pixel = 0.5;
  o.margin = 10;
  return o;
}

TEST(MapPicture, EachPointLandsOnItsPixelAndTheHighestIsSeen) {
  // A 20 x 10 m map: ground at the origin with a wall point 2 m above it, an edge at (20, 10).
  const std::vector<Eigen::Vector3d> points = {{0, 0, 0}, {0, 0, 2}, {20, 10, 0}, {10, 0, -1}};
  const std::vector<PointClass> labels = {PointClass::Ground, PointClass::Wall, PointClass::Edge, PointClass::Roof};
  const TopView view = RenderTopView(points, labels, {}, {}, Fixed());
  EXPECT_EQ(view.width, 20 / 0.5 + 2 * 10 + 1);
  EXPECT_EQ(view.height, 10 / 0.5 + 2 * 10 + 1);
  // x right, y up: the origin is the lower left corner of the map, (20, 10) its upper right.
  EXPECT_EQ(At(view, 10, view.height - 1 - 10), ClassColour(PointClass::Wall));
  EXPECT_EQ(At(view, 10 + 40, 10), ClassColour(PointClass::Edge));
  EXPECT_EQ(At(view, 10 + 20, view.height - 1 - 10), ClassColour(PointClass::Roof));
  EXPECT_EQ(At(view, 10 + 10, view.height - 1 - 20), (Rgb{255, 255, 255}));  // nothing there
}

TEST(MapPicture, MarksAndTheTrajectoryAreDrawnOverTheMap) {
  const std::vector<Eigen::Vector3d> points = {{0, 0, 0}, {20, 10, 0}, {10, 5, 3}};
  const std::vector<PointClass> labels(3, PointClass::Wall);
  const TopView view = RenderTopView(points, labels, {{10, 5, 0}}, {{0, 2, 0}, {20, 2, 0}}, Fixed());
  const int cx = 10 + 20, cy = view.height - 1 - 10 - 10;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) EXPECT_EQ(At(view, cx + dx, cy + dy), kMarkColour);
  }
  const int ty = view.height - 1 - 10 - 4;  // y = 2 m
  for (int x = 10; x <= 50; x += 5) EXPECT_EQ(At(view, x, ty), kTrajectoryColour) << x;
}

TEST(MapPicture, BadInputIsAnErrorNamingIt) {
  EXPECT_THROW(RenderTopView({}, {}, {}, {}, Fixed()), std::invalid_argument);
  EXPECT_THROW(RenderTopView({{0, 0, 0}, {1, 1, 0}}, {PointClass::Wall}, {}, {}, Fixed()), std::invalid_argument);
  TopViewOptions tiny = Fixed();
  tiny.metres_per_pixel = 1e-4;  // 1 km at 0.1 mm a pixel
  EXPECT_THROW(RenderTopView({{0, 0, 0}, {1000, 1000, 0}}, {}, {}, {}, tiny), std::invalid_argument);
}

TEST(MapPicture, ThePngHasItsSignatureAndSize) {
  const test::TempDir dir("map_picture");
  const TopView view = RenderTopView({{0, 0, 0}, {20, 10, 0}}, {}, {}, {}, Fixed());
  const std::filesystem::path file = dir.path() / "map.png";
  WritePng(file, view);
  std::ifstream in(file, std::ios::binary);
  char header[24] = {};
  in.read(header, sizeof(header));
  ASSERT_TRUE(in);
  EXPECT_EQ(std::string(header + 1, 3), "PNG");
  // The IHDR chunk: width and height, big-endian, at bytes 16 and 20.
  auto be32 = [&](int at) {
    return (static_cast<unsigned char>(header[at]) << 24) | (static_cast<unsigned char>(header[at + 1]) << 16) |
           (static_cast<unsigned char>(header[at + 2]) << 8) | static_cast<unsigned char>(header[at + 3]);
  };
  EXPECT_EQ(be32(16), view.width);
  EXPECT_EQ(be32(20), view.height);
  EXPECT_THROW(WritePng(dir.path() / "no" / "such" / "dir.png", view), io::IoError);
}

}  // namespace
}  // namespace dammloam::eval
