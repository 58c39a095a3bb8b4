#include <stdexcept>

#include "tools/driver/dds_sink.hpp"

// Built with -DDAMMLOAM_DRIVER_NO_DDS=ON (no Cyclone DDS): conversion modes still work.
namespace dammloam::driver {

bool DdsAvailable() { return false; }

std::unique_ptr<ScanSink> MakeDdsSink(const DdsOptions&) {
  throw std::runtime_error("this dammloam-driver was built without DDS support (DAMMLOAM_DRIVER_NO_DDS); "
                           "use --to-sequence or --dump-range");
}

}  // namespace dammloam::driver
