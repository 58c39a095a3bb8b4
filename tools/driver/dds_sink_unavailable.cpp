#include <stdexcept>

#include "tools/driver/dds_sink.hpp"

// Built when the DDS layer (services/dds) is absent: conversion modes still work.
namespace dammloam::driver {

bool DdsAvailable() { return false; }

std::unique_ptr<ScanSink> MakeDdsSink(const DdsOptions&) {
  throw std::runtime_error("this dammloam-driver was built without DDS support (services/dds missing); "
                           "use --to-sequence or --dump-range");
}

}  // namespace dammloam::driver
