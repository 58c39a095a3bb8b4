#include "io/bag/cloud_folder.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <numbers>

#include "core/cloud/point_cloud2.hpp"
#include "io/io_error.hpp"
#include "io/pcd/labelled_pcd.hpp"
#include "io/ply.hpp"
#include "io/sequence_meta.hpp"

namespace dammloam::io {
namespace {

namespace fs = std::filesystem;

bool IsCloudFile(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".pcd" || ext == ".ply";
}

std::vector<fs::path> CloudFiles(const fs::path& dir) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.is_regular_file() && IsCloudFile(entry.path())) files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

bool AllDigits(const std::string& s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c); });
}

// "123.456" -> the stamp; nullopt when not "digits[.digits]" or too large.
std::optional<CloudStamp> DecimalStamp(const std::string& s) {
  const auto dot = s.find('.');
  const std::string whole = s.substr(0, dot);
  std::string frac = dot == std::string::npos ? "" : s.substr(dot + 1);
  if (!AllDigits(whole) || (dot != std::string::npos && !AllDigits(frac)) || whole.size() > 10 ||
      std::stoll(whole) > 2147483647ll) {
    return std::nullopt;
  }
  if (frac.size() > 9) frac.resize(9);
  frac.resize(9, '0');
  return CloudStamp{static_cast<std::int32_t>(std::stoll(whole)), static_cast<std::uint32_t>(std::stoul(frac))};
}

Scan ReadCloudFile(const fs::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".ply") return ReadPly(file);
  LabelledCloud cloud = ReadLabelledPcd(file);
  Scan scan;
  scan.points.reserve(cloud.size());
  const bool intensities = cloud.intensities.size() == cloud.size();
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3d& p = cloud.points[i];
    if (!p.allFinite() || p.isZero()) continue;  // invalid returns
    scan.points.push_back(p);
    if (intensities) scan.intensities.push_back(cloud.intensities[i]);
  }
  return scan;
}

// The beams of a spinning sensor from a cloud without rings: the elevations of its returns
// between 2 and 60 m, sorted, split where consecutive ones are more than 0.3 deg apart; clusters
// holding at least 0.2 % of the returns are beams, at their median elevation (highest first).
// Separates beams 1 deg or more apart (VLP-16, HDL-32E, HDL-64E's 0.4-0.5 deg only in part);
// nullopt when fewer than 4 or more than 256 beams come out.
std::optional<std::vector<double>> BeamsFromElevations(const Scan& scan) {
  std::vector<double> elevation;
  elevation.reserve(scan.size());
  for (const Eigen::Vector3d& p : scan.points) {
    const double range = p.norm();
    if (range < 2.0 || range > 60.0) continue;
    elevation.push_back(std::atan2(p.z(), p.head<2>().norm()) * 180.0 / std::numbers::pi);
  }
  if (elevation.size() < 1000) return std::nullopt;
  std::sort(elevation.begin(), elevation.end());
  const std::size_t min_points = std::max<std::size_t>(20, elevation.size() / 500);
  std::vector<double> beams;
  std::size_t first = 0;
  for (std::size_t i = 1; i <= elevation.size(); ++i) {
    if (i < elevation.size() && elevation[i] - elevation[i - 1] <= 0.3) continue;
    if (i - first >= min_points) beams.push_back(elevation[first + (i - first) / 2]);
    first = i;
  }
  if (beams.size() < 4 || beams.size() > 256) return std::nullopt;
  std::reverse(beams.begin(), beams.end());
  return beams;
}

class CloudFolderSource : public ScanSource {
 public:
  CloudFolderSource(const fs::path& dir, const ScanSourceOptions& options)
      : dir_(dir), files_(CloudFiles(dir)) {
    if (files_.empty()) throw IoError(dir.string() + ": no .pcd or .ply files");
    std::vector<std::string> stems;
    for (const fs::path& f : files_) stems.push_back(f.stem().string());
    std::string unit;
    const auto named = options.scan_period > 0.0 ? std::nullopt : StampsFromNames(stems, &unit);
    if (named) {
      // Numeric names sort as numbers, not as text (9.pcd before 10.pcd).
      std::vector<std::size_t> order(files_.size());
      for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
      std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return (*named)[a] < (*named)[b]; });
      std::vector<fs::path> files;
      for (std::size_t i : order) {
        files.push_back(files_[i]);
        stamps_.push_back((*named)[i]);
      }
      files_ = std::move(files);
      stamp_origin_ = "file names (" + unit + ")";
    } else {
      const double period = options.scan_period > 0.0 ? options.scan_period : 0.1;
      for (std::size_t i = 0; i < files_.size(); ++i) stamps_.push_back(static_cast<double>(i) * period);
      stamp_origin_ = "file index x " + std::to_string(period) + " s (" +
                      (options.scan_period > 0.0 ? "--scan-period" : "the names are not stamps; --scan-period sets it") + ")";
    }
    first_ = Read(0);
    if (options.sensor_meta.empty()) {
      std::optional<Scan> second;
      if (files_.size() > 1) second = Read(1);
      model_ = GuessSensorModel(*first_, first_->size(), 1, second ? &*second : nullptr);
      if (!first_->has_rings()) {
        if (const auto beams = BeamsFromElevations(*first_)) {
          model_.rings = static_cast<int>(beams->size());
          model_.vertical_angles_deg = *beams;
          model_.columns = static_cast<int>((first_->size() + beams->size() - 1) / beams->size());
          model_origin_ = ", " + std::to_string(beams->size()) + " beams from the elevations of the first cloud";
        } else {
          model_origin_ = ", no beams found in the elevations of the first cloud";
        }
      }
    } else {
      model_ = ReadMeta(options.sensor_meta).model;
    }
  }
  std::string kind() const override { return "cloud folder"; }
  const SensorModel& model() const override { return model_; }
  std::optional<std::size_t> size() const override { return files_.size(); }
  std::optional<Scan> Next() override {
    if (next_ >= files_.size()) return std::nullopt;
    Scan scan = next_ == 0 && first_ ? std::move(*first_) : Read(next_);
    first_.reset();
    ++next_;
    return scan;
  }
  std::optional<std::vector<StampedPose>> ReadGroundTruth() const override { return std::nullopt; }
  std::string Describe() const override {
    return std::to_string(files_.size()) + " cloud files, stamps from the " + stamp_origin_ + model_origin_;
  }

 private:
  Scan Read(std::size_t i) const {
    Scan scan = ReadCloudFile(files_[i]);
    if (scan.empty()) throw IoError(files_[i].string() + ": no valid point");
    scan.t_start = stamps_[i];
    return scan;
  }

  fs::path dir_;
  std::vector<fs::path> files_;
  std::vector<double> stamps_;
  std::string stamp_origin_;
  std::string model_origin_;
  std::optional<Scan> first_;
  SensorModel model_;
  std::size_t next_ = 0;
};

}  // namespace

bool IsCloudFolder(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec) || fs::exists(dir / "meta.json") || fs::exists(dir / "metadata.yaml") ||
      fs::is_directory(dir / "velodyne") || fs::is_directory(dir / "scans")) {
    return false;
  }
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    if (entry.is_regular_file() && IsCloudFile(entry.path())) return true;
  }
  return false;
}

std::optional<std::vector<double>> StampsFromNames(const std::vector<std::string>& stems, std::string* unit) {
  if (stems.empty()) return std::nullopt;
  const bool integers = std::all_of(stems.begin(), stems.end(), AllDigits);
  if (!integers) {
    std::vector<double> stamps;
    for (const std::string& s : stems) {
      const auto stamp = DecimalStamp(s);
      if (!stamp) return std::nullopt;
      stamps.push_back(StampSeconds(*stamp));
    }
    if (unit != nullptr) *unit = "s";
    return stamps;
  }
  std::vector<std::uint64_t> values;
  for (const std::string& s : stems) {
    if (s.size() > 19) return std::nullopt;
    values.push_back(std::stoull(s));
  }
  if (values.size() < 2) return std::nullopt;
  std::vector<std::uint64_t> sorted = values;
  std::sort(sorted.begin(), sorted.end());
  std::vector<std::uint64_t> steps;
  for (std::size_t i = 1; i < sorted.size(); ++i) steps.push_back(sorted[i] - sorted[i - 1]);
  std::nth_element(steps.begin(), steps.begin() + static_cast<long>(steps.size() / 2), steps.end());
  const double step = static_cast<double>(steps[steps.size() / 2]);
  struct Unit {
    const char* name;
    std::uint64_t per_second;
  };
  for (const Unit u : {Unit{"s", 1}, Unit{"ms", 1000}, Unit{"us", 1000000}, Unit{"ns", 1000000000}}) {
    const double seconds = step / static_cast<double>(u.per_second);
    if (seconds < 0.02 || seconds > 0.5) continue;
    std::vector<double> stamps;
    for (std::uint64_t v : values) {
      const std::uint64_t sec = v / u.per_second;
      if (sec > 2147483647ull) return std::nullopt;
      const std::uint64_t nanosec = (v % u.per_second) * (1000000000ull / u.per_second);
      stamps.push_back(StampSeconds({static_cast<std::int32_t>(sec), static_cast<std::uint32_t>(nanosec)}));
    }
    if (unit != nullptr) *unit = u.name;
    return stamps;
  }
  return std::nullopt;
}

std::unique_ptr<ScanSource> OpenCloudFolder(const fs::path& dir, const ScanSourceOptions& options) {
  return std::make_unique<CloudFolderSource>(dir, options);
}

}  // namespace dammloam::io
