#pragma once
#include <string>

namespace dammloam::test {

struct CommandResult {
  int exit_code = -1;  // -1 when the shell could not be started or the command was killed
  std::string output;  // what it wrote on stdout (stderr only if the command says "2>&1")
};

// Runs `command` through /bin/sh (popen), so it may quote, redirect and pipe, and waits for it.
CommandResult RunCommand(const std::string& command);

}  // namespace dammloam::test
