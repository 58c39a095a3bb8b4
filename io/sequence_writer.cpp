#include <fstream>
#include <string>

#include "io/number_text.hpp"
#include "io/sequence_io.hpp"
#include "io/times_file.hpp"

namespace dammloam::io {
namespace {

namespace fs = std::filesystem;

bool IsScanFile(const fs::directory_entry& entry) {
  return entry.is_regular_file() && entry.path().extension() == ".bin";
}

// Makes dir/scans empty of scan files; existing scans are an error unless overwrite is set.
void PrepareScanDir(const fs::path& dir, bool overwrite) {
  const fs::path scans = dir / "scans";
  std::error_code ec;
  fs::create_directories(scans, ec);
  if (ec) throw IoError(scans.string() + ": cannot create directory (" + ec.message() + ")");
  for (const auto& entry : fs::directory_iterator(scans)) {
    if (!IsScanFile(entry)) continue;
    if (!overwrite) {
      throw IoError(dir.string() + ": already holds a sequence (" + entry.path().string() +
                    "); refusing to overwrite it");
    }
    fs::remove(entry.path());
  }
  for (const char* optional : {"gt.tum", "imu.csv", "wheel.csv"}) fs::remove(dir / optional);
  std::ofstream truncate(dir / "times.txt", std::ios::trunc);
  if (!truncate) throw IoError((dir / "times.txt").string() + ": cannot create");
}

}  // namespace

SequenceWriter::SequenceWriter(const fs::path& dir, const SequenceMeta& meta, bool overwrite)
    : dir_(dir), meta_(meta) {
  PrepareScanDir(dir_, overwrite);
  WriteMeta(dir_ / "meta.json", meta_);
}

void SequenceWriter::Write(const Scan& scan) {
  if (last_time_ && !(scan.t_start > *last_time_)) {
    throw IoError((dir_ / "times.txt").string() + ": scan " + std::to_string(count_) +
                  " starts at " + FormatExact(scan.t_start) + ", not after the previous scan at " +
                  FormatExact(*last_time_));
  }
  WriteScanFile(dir_ / "scans" / ScanFileName(count_), scan, meta_.layout, meta_.model);
  AppendTime(dir_ / "times.txt", scan.t_start);
  last_time_ = scan.t_start;
  ++count_;
}

void SequenceWriter::WriteGroundTruth(const std::vector<StampedPose>& poses) {
  WriteTum(dir_ / "gt.tum", poses);
}

void SequenceWriter::WriteImu(const std::vector<ImuSample>& samples) {
  WriteImuCsv(dir_ / "imu.csv", samples);
}

void SequenceWriter::WriteWheel(const std::vector<WheelSample>& samples) {
  WriteWheelCsv(dir_ / "wheel.csv", samples);
}

}  // namespace dammloam::io
