#include <algorithm>
#include <cctype>
#include <stdexcept>
#include <string>

#include "io/number_text.hpp"
#include "io/sequence_io.hpp"
#include "io/times_file.hpp"

namespace dammloam::io {
namespace {

namespace fs = std::filesystem;

// Index of a file named exactly NNNNNN.bin (six digits), nullopt for anything else.
std::optional<std::size_t> ScanIndexOf(const fs::path& file) {
  const std::string name = file.filename().string();
  if (name.size() != 10 || name.substr(6) != ".bin") return std::nullopt;
  std::size_t index = 0;
  for (int i = 0; i < 6; ++i) {
    if (!std::isdigit(static_cast<unsigned char>(name[i]))) return std::nullopt;
    index = index * 10 + static_cast<std::size_t>(name[i] - '0');
  }
  return index;
}

// Number of scan files, checked to be consecutive from 000000.bin.
std::size_t CountScanFiles(const fs::path& scan_dir) {
  std::vector<std::size_t> indices;
  for (const auto& entry : fs::directory_iterator(scan_dir)) {
    if (const auto index = ScanIndexOf(entry.path()); index && entry.is_regular_file()) {
      indices.push_back(*index);
    }
  }
  if (indices.empty()) throw IoError(scan_dir.string() + ": no NNNNNN.bin scan files found");
  std::sort(indices.begin(), indices.end());
  for (std::size_t i = 0; i < indices.size(); ++i) {
    if (indices[i] != i) {
      throw IoError((scan_dir / ScanFileName(i)).string() + ": missing scan file (scans must be " +
                    "numbered consecutively from 000000.bin; the highest present is " +
                    ScanFileName(indices.back()) + ")");
    }
  }
  return indices.size();
}

// Metadata from meta.json, or the KITTI defaults for a folder without it.
SequenceMeta MetaFor(const fs::path& dir, const ReadOptions& options) {
  const fs::path meta_json = dir / "meta.json";
  if (fs::exists(meta_json)) {
    SequenceMeta meta = ReadMeta(meta_json);
    if (options.layout) meta.layout = *options.layout;
    return meta;
  }
  if (options.layout == PointLayout::kXYZI || fs::is_directory(dir / "velodyne")) return KittiMeta();
  throw IoError(meta_json.string() +
                ": missing meta.json (a KITTI folder needs a velodyne/ subfolder or layout xyzi)");
}

fs::path ScanDirFor(const fs::path& dir, PointLayout layout) {
  if (fs::is_directory(dir / "scans")) return dir / "scans";
  if (layout == PointLayout::kXYZI) {
    return fs::is_directory(dir / "velodyne") ? dir / "velodyne" : dir;
  }
  throw IoError((dir / "scans").string() + ": missing scans directory");
}

}  // namespace

std::string ScanFileName(std::size_t index) {
  std::string digits = std::to_string(index);
  if (digits.size() < 6) digits.insert(0, 6 - digits.size(), '0');
  return digits + ".bin";
}

SequenceReader SequenceReader::Open(const fs::path& dir, const ReadOptions& options) {
  if (!fs::is_directory(dir)) {
    throw IoError(dir.string() + ": sequence directory does not exist or is not a directory");
  }
  SequenceReader reader;
  reader.dir_ = dir;
  reader.strict_ = options.strict;
  reader.meta_ = MetaFor(dir, options);
  reader.scan_dir_ = ScanDirFor(dir, reader.meta_.layout);
  const std::size_t scan_count = CountScanFiles(reader.scan_dir_);

  const fs::path times_txt = dir / "times.txt";
  if (fs::exists(times_txt)) {
    reader.times_ = ReadTimes(times_txt);
  } else if (reader.meta_.layout == PointLayout::kXYZI) {
    // KITTI folders may come without times: one scan per period, starting at 0.
    for (std::size_t i = 0; i < scan_count; ++i) {
      reader.times_.push_back(static_cast<double>(i) * reader.meta_.model.scan_period);
    }
  } else {
    throw IoError(times_txt.string() + ": missing times.txt");
  }
  if (reader.times_.size() != scan_count) {
    throw IoError(times_txt.string() + ": has " + std::to_string(reader.times_.size()) +
                  " times but " + reader.scan_dir_.string() + " has " + std::to_string(scan_count) +
                  " scan files (they must match one to one)");
  }
  return reader;
}

fs::path SequenceReader::ScanPath(std::size_t index) const { return scan_dir_ / ScanFileName(index); }

Scan SequenceReader::ReadScan(std::size_t index, ScanReadReport* report) const {
  if (index >= size()) {
    throw std::out_of_range("scan index " + std::to_string(index) + " >= sequence size " +
                            std::to_string(size()) + " in " + dir_.string());
  }
  const fs::path file = ScanPath(index);
  if (!fs::exists(file)) throw IoError(file.string() + ": missing scan file");
  Scan scan = ReadScanFile(file, meta_.layout, meta_.model, strict_, report);
  scan.t_start = times_[index];
  return scan;
}

std::optional<std::vector<StampedPose>> SequenceReader::ReadGroundTruth() const {
  const fs::path gt = dir_ / "gt.tum";
  if (!fs::exists(gt)) return std::nullopt;
  return ReadTum(gt);
}

std::optional<std::vector<ImuSample>> SequenceReader::ReadImu(StreamReadReport* report,
                                                              const StreamReadOptions& options) const {
  const fs::path file = dir_ / "imu.csv";
  if (!fs::exists(file)) return std::nullopt;
  return ReadImuCsv(file, report, options);
}

std::optional<std::vector<WheelSample>> SequenceReader::ReadWheel(StreamReadReport* report,
                                                                  const StreamReadOptions& options) const {
  const fs::path file = dir_ / "wheel.csv";
  if (!fs::exists(file)) return std::nullopt;
  return ReadWheelCsv(file, report, options);
}

}  // namespace dammloam::io
