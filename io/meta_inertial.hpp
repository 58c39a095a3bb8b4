#pragma once
#include <filesystem>
#include <nlohmann/json.hpp>

#include "io/sequence_meta.hpp"

// The IMU and wheel keys of meta.json (sequence.md), apart from the sensor's: used only by
// sequence_meta.cpp (nlohmann_json stays a private dependency of dammloam_io).
namespace dammloam::io {

// "imu_extrinsic", "imu", "base_extrinsic" from `root` into `meta`; IoError naming file and key.
void ReadInertialKeys(const nlohmann::json& root, const std::filesystem::path& file, SequenceMeta* meta);
// The same keys, only those `meta` has.
void WriteInertialKeys(const SequenceMeta& meta, nlohmann::json* root);

}  // namespace dammloam::io
