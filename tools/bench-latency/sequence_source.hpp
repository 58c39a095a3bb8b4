#pragma once
// The scans of a recording (a sequence directory, a bag, a capture), published at their
// recorded instants.
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "tools/bench-latency/latency_run.hpp"
#include "io/sequence_io.hpp"

namespace dammloam::bench {

// What SequenceSource needs of a recording: the start stamp of every scan it will publish, and
// a reader called with 0, 1, 2, ... in that order (a bag streams; a directory reads any file).
struct RecordedScans {
  std::string name;            // for error messages
  std::vector<double> times;   // scan start stamps, seconds
  std::function<Scan(std::size_t index)> read;
};

// Reads and converts scans on its own thread, at most `read_ahead` publish-ready samples ahead of
// the publisher: a whole OS1-64 sequence would take GBs (2500 x 1.5 MiB as samples, more as
// Scans), the window takes read_ahead x 1.5 MiB however long the sequence is. Reading on another
// thread keeps file I/O and conversion off the publish schedule.
class SequenceSource : public ScanSource {
 public:
  // The first `count` scans of `scans`, due at (times[k] - times[0]) / speed after the start,
  // stamped with times[k].
  SequenceSource(RecordedScans scans, std::size_t count, double speed, std::size_t read_ahead);
  ~SequenceSource() override;  // stops and joins the reading thread
  SequenceSource(const SequenceSource&) = delete;
  SequenceSource& operator=(const SequenceSource&) = delete;

  std::size_t size() const override { return count_; }
  Clock::duration DueAfterStart(std::size_t index) const override;
  // Rethrows a read error (naming the file) once the publisher reaches the broken scan.
  std::optional<dds::CloudMessage> TryTake(std::size_t index) override;

  // Blocks until the window is full or every scan is read, so that a run starts with a full
  // read-ahead; rethrows a read error.
  void WaitUntilFilled();
  // Scans per second of the recorded times, times the speed factor.
  double Rate() const;
  // How the read-ahead kept up: the fewest scans that were waiting when the publisher took one
  // (0: it ran empty at least once), and the mean time to read and convert one scan.
  std::size_t LowestFill() const;
  double MeanReadMs() const;

 private:
  void ReadLoop();
  bool WaitForSpace();              // false once stopping
  bool ReadOne(std::size_t index);  // false after a read error (kept for the publisher)
  void RethrowReadError() const;    // mutex_ held

  const RecordedScans scans_;
  const std::size_t count_;
  const double speed_;
  const std::size_t read_ahead_;

  mutable std::mutex mutex_;
  std::condition_variable space_;   // the publisher took a sample
  std::condition_variable filled_;  // the reader added a sample or failed
  std::deque<dds::CloudMessage> ready_;
  std::size_t read_ = 0;            // scans read so far
  std::size_t lowest_fill_;         // read_ahead_ until the first take
  double read_seconds_ = 0.0;       // spent reading and converting the scans read so far
  std::exception_ptr read_error_;
  bool stop_ = false;
  std::thread reader_;              // last: starts once the members above exist
};

// Throws IoError naming the first of the first `count` scan files whose size is not a whole
// number of points, so that a truncated file fails before the run, not minutes into it.
void CheckScanFileSizes(const io::SequenceReader& sequence, std::size_t count);

// A sequence directory's scans (`sequence` must outlive the result).
RecordedScans SequenceScans(const io::SequenceReader& sequence);

}  // namespace dammloam::bench
