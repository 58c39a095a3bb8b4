#include "core/cloud/labelled_cloud2.hpp"

#include <cstring>

namespace dammloam {

Cloud2 LabelledRos2Cloud(const std::vector<Eigen::Vector3d>& points_sensor,
                         const std::vector<Eigen::Vector3f>& normals,
                         const std::vector<PointClass>& labels, const std::string& frame_id) {
  Cloud2 msg;
  msg.frame_id = frame_id;
  msg.width = static_cast<std::uint32_t>(points_sensor.size());
  const char* names[] = {"x", "y", "z", "normal_x", "normal_y", "normal_z"};
  for (std::uint32_t k = 0; k < 6; ++k) {
    msg.fields.push_back({names[k], 4 * k, point_field::kFloat32, 1});
  }
  msg.fields.push_back({"label", 24, point_field::kUint8, 1});
  msg.point_step = 28;
  msg.row_step = msg.point_step * msg.width;
  msg.data.assign(std::size_t{msg.row_step}, 0);
  const bool has_normals = normals.size() == points_sensor.size();
  for (std::size_t i = 0; i < points_sensor.size(); ++i) {
    std::uint8_t* p = msg.data.data() + i * msg.point_step;
    const Eigen::Vector3f xyz = points_sensor[i].cast<float>();
    const Eigen::Vector3f normal = has_normals ? normals[i] : Eigen::Vector3f::Zero();
    const float values[6] = {xyz.x(), xyz.y(), xyz.z(), normal.x(), normal.y(), normal.z()};
    std::memcpy(p, values, sizeof(values));
    p[24] = static_cast<std::uint8_t>(labels[i]);
  }
  return msg;
}

}  // namespace dammloam
