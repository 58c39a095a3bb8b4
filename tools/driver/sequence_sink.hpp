#pragma once
#include <filesystem>
#include <memory>

#include "io/sequence_io.hpp"
#include "tools/driver/scan_sink.hpp"

namespace dammloam::driver {

// Conversion mode: every scan becomes the next scans/NNNNNN.bin of a sequence directory.
class SequenceSink : public ScanSink {
 public:
  SequenceSink(const std::filesystem::path& dir, const io::SequenceMeta& meta, bool overwrite)
      : writer_(dir, meta, overwrite), dir_(dir) {}
  void Consume(const Scan& scan) override { writer_.Write(scan); }
  std::string Describe() const override { return "sequence " + dir_.string(); }
  std::size_t size() const { return writer_.size(); }

 private:
  io::SequenceWriter writer_;
  std::filesystem::path dir_;
};

}  // namespace dammloam::driver
