#include "io/bag/scan_source.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <map>
#include <numbers>

#include "io/bag/bag_reader.hpp"
#include "io/bag/bag_scans.hpp"
#include "io/bag/cloud_folder.hpp"
#include "io/sequence_io.hpp"

namespace dammloam::io {
namespace {

class SequenceSource : public ScanSource {
 public:
  explicit SequenceSource(const std::filesystem::path& dir) : reader_(SequenceReader::Open(dir)) {}
  std::string kind() const override { return "sequence"; }
  const SensorModel& model() const override { return reader_.meta().model; }
  std::optional<std::size_t> size() const override { return reader_.size(); }
  std::optional<Scan> Next() override {
    if (next_ >= reader_.size()) return std::nullopt;
    Scan scan = reader_.ReadScan(next_);
    scan.t_start = reader_.times()[next_];
    ++next_;
    return scan;
  }
  std::optional<std::vector<StampedPose>> ReadGroundTruth() const override {
    return reader_.ReadGroundTruth();
  }

 private:
  SequenceReader reader_;
  std::size_t next_ = 0;
};

class BagSource : public ScanSource {
 public:
  BagSource(const std::filesystem::path& path, const ScanSourceOptions& options)
      : kind_(std::filesystem::is_directory(path)  ? "rosbag2"
              : path.extension() == ".bag"         ? "ros1 bag"
                                                   : "mcap"),
        scans_(path, BagScanOptions{options.topic, RecordedCloudLimits()}) {
    // Two scans ahead, so the model can be guessed from them; they are handed out first.
    for (int i = 0; i < 2; ++i) {
      if (auto scan = scans_.Next()) {
        if (i == 0) {
          first_points_ = scans_.last_cloud_points();
          first_height_ = scans_.last_cloud_height();
        }
        pending_.push_back(std::move(*scan));
      }
    }
    if (pending_.empty()) {
      throw IoError(path.string() + ": topic " + scans_.topic().name + " has no point cloud " +
                    "with a valid point");
    }
    model_ = options.sensor_meta.empty()
                 ? GuessSensorModel(pending_[0], first_points_, first_height_,
                                    pending_.size() > 1 ? &pending_[1] : nullptr)
                 : ReadMeta(options.sensor_meta).model;
    if (const auto& count = scans_.topic().message_count) size_ = static_cast<std::size_t>(*count);
  }
  std::string kind() const override { return kind_; }
  const SensorModel& model() const override { return model_; }
  std::optional<std::size_t> size() const override { return size_; }
  std::optional<Scan> Next() override {
    if (!pending_.empty()) {
      Scan scan = std::move(pending_.front());
      pending_.pop_front();
      return scan;
    }
    return scans_.Next();
  }
  std::optional<std::vector<StampedPose>> ReadGroundTruth() const override { return std::nullopt; }

 private:
  std::string kind_;
  BagScans scans_;
  std::deque<Scan> pending_;
  std::uint64_t first_points_ = 0;
  std::uint32_t first_height_ = 0;
  SensorModel model_;
  std::optional<std::size_t> size_;
};

}  // namespace

namespace {

// Columns of an unorganised cloud from its firing order: within a ring, consecutive returns are
// one azimuth step apart (or a few, where returns are missing), so the median step is the
// column width. Nullopt with too few steps to tell.
std::optional<int> ColumnsFromAzimuthSteps(const Scan& scan) {
  std::map<int, double> last_azimuth;
  std::vector<double> steps;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const double azimuth = std::atan2(scan.points[i].y(), scan.points[i].x());
    const auto [it, first] = last_azimuth.try_emplace(scan.rings[i], azimuth);
    if (first) continue;
    const double step = std::abs(std::remainder(azimuth - it->second, 2.0 * std::numbers::pi));
    it->second = azimuth;
    if (step > 1e-6 && step < 0.2) steps.push_back(step);  // not a second return, not a gap
  }
  if (steps.size() < 100) return std::nullopt;
  std::nth_element(steps.begin(), steps.begin() + static_cast<long>(steps.size() / 2), steps.end());
  return static_cast<int>(std::lround(2.0 * std::numbers::pi / steps[steps.size() / 2]));
}

}  // namespace

SensorModel GuessSensorModel(const Scan& first, std::uint64_t cloud_points,
                             std::uint32_t cloud_height, const Scan* second) {
  SensorModel model;
  if (cloud_height > 1) {
    model.rings = static_cast<int>(cloud_height);
  } else if (first.has_rings()) {
    model.rings = *std::max_element(first.rings.begin(), first.rings.end()) + 1;
  }
  model.rings = std::max(model.rings, 1);
  const std::uint64_t points = std::max<std::uint64_t>(cloud_points, first.size());
  model.columns = static_cast<int>(std::max<std::uint64_t>(
      1, (points + static_cast<std::uint64_t>(model.rings) - 1) / static_cast<std::uint64_t>(model.rings)));
  if (cloud_height <= 1 && first.has_rings()) {
    if (const auto columns = ColumnsFromAzimuthSteps(first)) model.columns = *columns;
  }
  if (second != nullptr) {
    const double period = second->t_start - first.t_start;
    if (period >= 0.02 && period <= 1.0) model.scan_period = period;
  }
  return model;
}

std::unique_ptr<ScanSource> OpenScanSource(const std::filesystem::path& path,
                                           const ScanSourceOptions& options) {
  if (IsBagPath(path)) return std::make_unique<BagSource>(path, options);
  if (IsCloudFolder(path)) return OpenCloudFolder(path, options);
  return std::make_unique<SequenceSource>(path);
}

}  // namespace dammloam::io
