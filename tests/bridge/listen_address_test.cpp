// tools/bridge/listen_address: --listen ADDR:PORT, and what a wrong one is told.
#include <gtest/gtest.h>

#include <stdexcept>

#include "tools/bridge/listen_address.hpp"

namespace dammloam::bridge {
namespace {

std::string ListenError(const std::string& text) {
  try {
    ParseListenAddress(text);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(ListenAddress, HostAndPortAreSplit) {
  const ListenAddress v4 = ParseListenAddress("0.0.0.0:9000");
  EXPECT_EQ(v4.host, "0.0.0.0");
  EXPECT_EQ(v4.port, 9000);
  const ListenAddress v6 = ParseListenAddress("[::1]:0");
  EXPECT_EQ(v6.host, "::1");
  EXPECT_EQ(v6.port, 0);
}

TEST(ListenAddress, BadValuesNameTheProblem) {
  EXPECT_NE(ListenError("8765").find("expected ADDR:PORT"), std::string::npos);
  EXPECT_NE(ListenError("127.0.0.1:").find("expected ADDR:PORT"), std::string::npos);
  EXPECT_NE(ListenError("127.0.0.1:65536").find("port '65536' is not a number from 0 to 65535"),
            std::string::npos);
  EXPECT_NE(ListenError("127.0.0.1:80a").find("port '80a'"), std::string::npos);
  EXPECT_NE(ListenError("127.0.0.1:-1").find("port '-1'"), std::string::npos);
}

}  // namespace
}  // namespace dammloam::bridge
