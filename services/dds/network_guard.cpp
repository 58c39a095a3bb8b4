#include "services/dds/network_guard.hpp"

#include <cstdlib>

namespace dammloam::dds {

std::string NetworkConfigProblem(bool allow_default_network) {
  const char* uri = std::getenv("CYCLONEDDS_URI");
  if ((uri != nullptr && *uri != '\0') || allow_default_network) return {};
  return "CYCLONEDDS_URI is not set: Cyclone DDS would use the default network interface and "
         "multicast discovery beyond this machine. Set it, e.g. "
         "CYCLONEDDS_URI=file://$PWD/deploy/cyclonedds-loopback.xml, or pass "
         "--allow-default-network to use the default network on purpose.";
}

}  // namespace dammloam::dds
