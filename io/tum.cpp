#include "io/tum.hpp"

#include <array>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "io/io_error.hpp"
#include "io/number_text.hpp"

namespace dammloam::io {
namespace {

[[noreturn]] void FailAtLine(const std::filesystem::path& file, int line, const std::string& what) {
  throw IoError(file.string() + ":" + std::to_string(line) + ": " + what);
}

StampedPose ParseTumLine(const std::string& text, const std::filesystem::path& file, int line) {
  std::istringstream tokens(text);
  std::array<double, 8> v{};
  std::string token;
  std::size_t count = 0;
  while (tokens >> token) {
    if (count == v.size()) FailAtLine(file, line, "more than 8 values (expected t tx ty tz qx qy qz qw)");
    const auto value = ParseDouble(token);
    if (!value || !std::isfinite(*value)) {
      FailAtLine(file, line, "value '" + token + "' is not a finite number");
    }
    v[count++] = *value;
  }
  if (count != v.size()) {
    FailAtLine(file, line, "expected 8 values (t tx ty tz qx qy qz qw), got " + std::to_string(count));
  }
  Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
  if (q.norm() < 1e-6) FailAtLine(file, line, "quaternion has zero norm");
  StampedPose pose;
  pose.t = v[0];
  pose.T.linear() = q.normalized().toRotationMatrix();
  pose.T.translation() = Eigen::Vector3d(v[1], v[2], v[3]);
  return pose;
}

}  // namespace

std::vector<StampedPose> ReadTum(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw IoError(file.string() + ": cannot open TUM trajectory file");
  std::vector<StampedPose> poses;
  std::string text;
  int line = 0;
  while (std::getline(in, text)) {
    ++line;
    const auto first = text.find_first_not_of(" \t\r");
    if (first == std::string::npos || text[first] == '#') continue;
    poses.push_back(ParseTumLine(text, file, line));
  }
  return poses;
}

void WriteTum(const std::filesystem::path& file, const std::vector<StampedPose>& poses) {
  std::ofstream out(file);
  if (!out) throw IoError(file.string() + ": cannot create TUM trajectory file");
  for (const auto& pose : poses) {
    const Eigen::Quaterniond q(pose.T.rotation());
    const Eigen::Vector3d& p = pose.T.translation();
    out << FormatExact(pose.t) << ' ' << FormatExact(p.x()) << ' ' << FormatExact(p.y()) << ' '
        << FormatExact(p.z()) << ' ' << FormatExact(q.x()) << ' ' << FormatExact(q.y()) << ' '
        << FormatExact(q.z()) << ' ' << FormatExact(q.w()) << '\n';
  }
  if (!out) throw IoError(file.string() + ": write failed");
}

}  // namespace dammloam::io
