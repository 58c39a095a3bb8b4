#pragma once
#include <string>

#include "core/geometry/scan.hpp"

namespace dammloam::driver {

// Where decoded scans go (a sequence directory, a DDS topic, ...). The decoders know nothing
// of these; the driver loop hands every complete scan to each sink.
class ScanSink {
 public:
  virtual ~ScanSink() = default;
  virtual void Consume(const Scan& scan) = 0;
  virtual std::string Describe() const = 0;
};

}  // namespace dammloam::driver
