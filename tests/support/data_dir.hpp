#pragma once
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

namespace dammloam::test {

// The shared real sensor recordings (never copied into the repository): $DAMMLOAM_DATA_DIR when
// set and not empty, else DAMMLOAM_SHARED_DATA_DIR, which dammloam_add_test defines for every
// test executable (../shared/data beside the source tree). Inline rather than in the support
// library so that the default path stays defined in that one place.
inline std::filesystem::path DataDir() {
  if (const char* env = std::getenv("DAMMLOAM_DATA_DIR"); env != nullptr && *env != '\0') {
    return env;
  }
  return DAMMLOAM_SHARED_DATA_DIR;
}

}  // namespace dammloam::test

// Skips the calling test, naming the missing path, when a data file or folder is absent: a
// machine without the recordings still runs every other test. A macro because GTEST_SKIP has to
// return from the test body itself.
#define DAMMLOAM_REQUIRE_DATA(path)                                                 \
  do {                                                                              \
    if (!std::filesystem::exists(path)) {                                           \
      GTEST_SKIP() << "real sensor data not found: " << (path)                      \
                   << " (set DAMMLOAM_DATA_DIR to the shared data folder)";         \
    }                                                                               \
  } while (0)
