// dammloam-map-picture MAP --out map.png [--mark points.pcd] [--trajectory poses.tum]: a top view
// of a saved map directory (dammloam-odometry --save-map, dammloamd's save_map) or a labelled
// PCD (dammloam-odometry --map), coloured by class.
#include <CLI/CLI.hpp>
#include <filesystem>
#include <iostream>

#include "io/mapstore/map_store.hpp"
#include "io/pcd/labelled_pcd.hpp"
#include "io/tum.hpp"
#include "tools/evaluate/map_picture.hpp"

namespace {

using namespace dammloam;

struct Cloud {
  std::vector<Eigen::Vector3d> points;
  std::vector<PointClass> labels;
};

Cloud ReadMap(const std::filesystem::path& input) {
  if (std::filesystem::is_directory(input)) {
    backend::MapData map = mapstore::LoadMap(input);
    return {std::move(map.global_points), std::move(map.global_labels)};
  }
  io::LabelledCloud cloud = io::ReadLabelledPcd(input);
  return {std::move(cloud.points), std::move(cloud.labels)};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Top view of a labelled map as a PNG: ground light grey, roof orange, wall blue, edge red, "
               "unknown green; marked points magenta; trajectory black; scale bar lower left"};
  std::string input, out, mark, trajectory;
  eval::TopViewOptions options;
  app.add_option("map", input, "saved map directory or labelled .pcd")->required()->check(CLI::ExistingPath);
  app.add_option("--out", out, "PNG to write")->required();
  app.add_option("--width", options.width, "picture width in pixels (with --resolution 0)")
      ->check(CLI::Range(64, 20000))
      ->capture_default_str();
  app.add_option("--resolution", options.metres_per_pixel, "metres per pixel (0: fit --width)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--mark", mark, "points to mark (a .pcd in the map's frame, e.g. dammloam-count-ghosts --ghosts-out)")
      ->check(CLI::ExistingFile);
  app.add_option("--trajectory", trajectory, "a trajectory (TUM) in the map's frame")->check(CLI::ExistingFile);
  CLI11_PARSE(app, argc, argv);
  try {
    const Cloud map = ReadMap(input);
    std::vector<Eigen::Vector3d> marked, path;
    if (!mark.empty()) marked = io::ReadLabelledPcd(mark).points;
    if (!trajectory.empty()) {
      for (const io::StampedPose& pose : io::ReadTum(trajectory)) path.push_back(pose.T.translation());
    }
    const eval::TopView view = eval::RenderTopView(map.points, map.labels, marked, path, options);
    eval::WritePng(out, view);
    std::cout << "wrote " << out << ": " << view.width << " x " << view.height << " pixels, "
              << view.metres_per_pixel << " m per pixel, " << map.points.size() << " points\n";
  } catch (const std::exception& e) {
    std::cerr << "dammloam-map-picture: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
