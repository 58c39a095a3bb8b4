#pragma once
#include <string>

namespace dammloam::dds {

// Empty when this process may create DDS participants. Without CYCLONEDDS_URI Cyclone picks the
// external interface and multicasts discovery off the machine, so every dammloam process refuses
// to start unless the user asked for that explicitly (allow_default_network).
std::string NetworkConfigProblem(bool allow_default_network);

}  // namespace dammloam::dds
