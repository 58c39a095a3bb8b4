#pragma once
#include <cstddef>
#include <filesystem>
#include <optional>
#include <vector>

#include "core/geometry/scan.hpp"
#include "io/io_error.hpp"
#include "io/motion_csv.hpp"
#include "io/scan_file.hpp"
#include "io/sequence_meta.hpp"
#include "io/tum.hpp"

// Sequence directories (/work/shared/formats/sequence.md):
//   scans/NNNNNN.bin, times.txt, meta.json, optional gt.tum, imu.csv, wheel.csv
// and KITTI odometry folders (velodyne/NNNNNN.bin or NNNNNN.bin directly, xyzi, optional
// times.txt, no meta.json).
namespace dammloam::io {

struct ReadOptions {
  bool strict = false;                // NaN/inf points -> IoError instead of dropped and counted
  std::optional<PointLayout> layout;  // overrides meta.json; kXYZI also selects KITTI folders
};

class SequenceReader {
 public:
  // Validates the whole directory up front (meta, times, scan file names and count) so that a
  // broken sequence fails here with a message naming the file, not halfway through a run.
  static SequenceReader Open(const std::filesystem::path& dir, const ReadOptions& options = {});

  std::size_t size() const { return times_.size(); }
  const SequenceMeta& meta() const { return meta_; }
  const std::vector<double>& times() const { return times_; }
  const std::filesystem::path& dir() const { return dir_; }
  std::filesystem::path ScanPath(std::size_t index) const;

  // Scan `index` with t_start = times()[index]. Throws std::out_of_range for a bad index and
  // IoError for a broken file (see ReadScanFile). Keeps no state: safe to call from several
  // threads at once.
  Scan ReadScan(std::size_t index, ScanReadReport* report = nullptr) const;

  // gt.tum if present, nullopt otherwise; IoError if present but malformed.
  std::optional<std::vector<StampedPose>> ReadGroundTruth() const;

  // imu.csv / wheel.csv if present, nullopt otherwise. A malformed file is an IoError; unusable
  // samples (NaN/inf, repeated or backward stamps) are dropped and counted in `report` unless
  // options.strict (motion_csv.hpp). Stamps as in the file (meta().imu_time_offset not applied).
  std::optional<std::vector<ImuSample>> ReadImu(StreamReadReport* report = nullptr,
                                                const StreamReadOptions& options = {}) const;
  std::optional<std::vector<WheelSample>> ReadWheel(StreamReadReport* report = nullptr,
                                                    const StreamReadOptions& options = {}) const;

 private:
  SequenceReader() = default;

  std::filesystem::path dir_;
  std::filesystem::path scan_dir_;
  SequenceMeta meta_;
  std::vector<double> times_;
  bool strict_ = false;
};

class SequenceWriter {
 public:
  // Creates dir/scans and writes dir/meta.json. Refuses (IoError) to write into a directory that
  // already holds scans unless overwrite is set, in which case the old scans, times.txt, gt.tum,
  // imu.csv and wheel.csv are removed first.
  SequenceWriter(const std::filesystem::path& dir, const SequenceMeta& meta,
                 bool overwrite = false);

  // Writes scans/<next index>.bin and appends scan.t_start to times.txt (must be increasing).
  void Write(const Scan& scan);
  void WriteGroundTruth(const std::vector<StampedPose>& poses);
  // imu.csv / wheel.csv (meta.json's extrinsics come with the SequenceMeta given above).
  void WriteImu(const std::vector<ImuSample>& samples);
  void WriteWheel(const std::vector<WheelSample>& samples);
  std::size_t size() const { return count_; }
  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
  SequenceMeta meta_;
  std::size_t count_ = 0;
  std::optional<double> last_time_;
};

// "000042.bin"
std::string ScanFileName(std::size_t index);

}  // namespace dammloam::io
