#pragma once
#include <gtest/gtest.h>

#include <string>

#include "tests/support/run_command.hpp"
#include "tests/support/temp_dir.hpp"

namespace dammloam::sim {

// Runs the dammloam-simulate executable in a fresh directory per test (parallel ctest runs never
// share files) and keeps what it printed.
class SimulateCliTest : public ::testing::Test {
 protected:
  // Runs dammloam-simulate, returns its exit code and keeps what it printed for Log().
  int Run(const std::string& args) {
    // Appended piecewise: GCC 12 warns falsely (-Warray-bounds) about chained operator+ here.
    std::string command = DAMMLOAM_BIN_DIR;
    command += "/dammloam-simulate ";
    command += args;
    command += " 2>&1";
    last_ = test::RunCommand(command);
    return last_.exit_code;
  }
  // stdout and stderr of the last Run.
  const std::string& Log() const { return last_.output; }

  const test::TempDir dir_;
  test::CommandResult last_;
};

}  // namespace dammloam::sim
