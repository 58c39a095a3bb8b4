#include "tools/bench-latency/sequence_source.hpp"

#include <algorithm>
#include <filesystem>
#include <stdexcept>
#include <string>

namespace dammloam::bench {

SequenceSource::SequenceSource(RecordedScans scans, std::size_t count, double speed,
                               std::size_t read_ahead)
    : scans_(std::move(scans)),
      count_(std::min(count, scans_.times.size())),
      speed_(speed),
      read_ahead_(std::max<std::size_t>(read_ahead, 1)),
      lowest_fill_(read_ahead_),
      reader_([this] { ReadLoop(); }) {}

SequenceSource::~SequenceSource() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  space_.notify_all();
  reader_.join();
}

Clock::duration SequenceSource::DueAfterStart(std::size_t index) const {
  const double seconds = (scans_.times[index] - scans_.times.front()) / speed_;
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

double SequenceSource::Rate() const {
  if (count_ < 2) return 0.0;
  const double span = scans_.times[count_ - 1] - scans_.times.front();
  return span > 0.0 ? speed_ * static_cast<double>(count_ - 1) / span : 0.0;
}

std::optional<dds::CloudMessage> SequenceSource::TryTake(std::size_t index) {
  std::unique_lock lock(mutex_);
  // The tail of the sequence drains the window by design: only count while scans remain unread.
  if (read_ < count_) lowest_fill_ = std::min(lowest_fill_, ready_.size());
  if (ready_.empty()) {
    RethrowReadError();
    return std::nullopt;
  }
  // One consumer taking 0, 1, 2, ...: the front is always `index`.
  if (ready_.front().seq != index) {
    throw std::logic_error("SequenceSource: scans must be taken in order");
  }
  dds::CloudMessage cloud = std::move(ready_.front());
  ready_.pop_front();
  lock.unlock();
  space_.notify_one();
  return cloud;
}

std::size_t SequenceSource::LowestFill() const {
  std::lock_guard lock(mutex_);
  return lowest_fill_;
}

double SequenceSource::MeanReadMs() const {
  std::lock_guard lock(mutex_);
  return read_ == 0 ? 0.0 : 1000.0 * read_seconds_ / static_cast<double>(read_);
}

void SequenceSource::WaitUntilFilled() {
  std::unique_lock lock(mutex_);
  filled_.wait(lock, [&] {
    return read_error_ || ready_.size() >= read_ahead_ || read_ == count_;
  });
  RethrowReadError();  // a broken scan within the first window fails before the run starts
}

void SequenceSource::RethrowReadError() const {
  if (read_error_) std::rethrow_exception(read_error_);
}

void SequenceSource::ReadLoop() {
  for (std::size_t k = 0; k < count_; ++k) {
    if (!WaitForSpace() || !ReadOne(k)) return;
  }
}

bool SequenceSource::WaitForSpace() {
  std::unique_lock lock(mutex_);
  space_.wait(lock, [&] { return stop_ || ready_.size() < read_ahead_; });
  return !stop_;
}

bool SequenceSource::ReadOne(std::size_t index) {
  bool ok = true;
  try {
    const auto start = Clock::now();
    dds::CloudMessage cloud = dds::ScanToCloud(scans_.read(index), "lidar", index);
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    std::lock_guard lock(mutex_);
    ready_.push_back(std::move(cloud));
    read_ = index + 1;
    read_seconds_ += seconds;
  } catch (const std::exception& e) {
    std::lock_guard lock(mutex_);
    read_error_ = std::make_exception_ptr(std::runtime_error(
        "scan " + std::to_string(index) + " of " + scans_.name + ": " + e.what()));
    ok = false;
  }
  filled_.notify_all();
  return ok;
}

RecordedScans SequenceScans(const io::SequenceReader& sequence) {
  return {sequence.dir().string(), sequence.times(),
          [&sequence](std::size_t index) { return sequence.ReadScan(index); }};
}

void CheckScanFileSizes(const io::SequenceReader& sequence, std::size_t count) {
  const std::uintmax_t record = io::FloatsPerPoint(sequence.meta().layout) * sizeof(float);
  for (std::size_t k = 0; k < std::min(count, sequence.size()); ++k) {
    const std::filesystem::path file = sequence.ScanPath(k);
    std::error_code ec;
    const std::uintmax_t bytes = std::filesystem::file_size(file, ec);
    if (ec) throw io::IoError(file.string() + ": cannot read its size: " + ec.message());
    if (bytes % record != 0) {
      throw io::IoError(file.string() + ": " + std::to_string(bytes) +
                        " bytes is not a whole number of " + std::to_string(record) +
                        "-byte points (malformed scan file)");
    }
  }
}

}  // namespace dammloam::bench
