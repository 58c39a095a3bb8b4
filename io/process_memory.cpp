#include "io/process_memory.hpp"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <fstream>
#include <string>
#include <unistd.h>

namespace dammloam::io {
namespace {

// statm's second field: resident pages (VmRSS in /proc/PID/status).
double ResidentMiBFrom(const std::string& statm_path) {
  std::ifstream statm(statm_path);
  long pages_total = 0, pages_resident = 0;
  if (!(statm >> pages_total >> pages_resident)) return 0.0;
  const long page_size = sysconf(_SC_PAGESIZE);
  return static_cast<double>(pages_resident) * static_cast<double>(page_size) / (1024.0 * 1024.0);
}

}  // namespace

double ResidentSetMiB() { return ResidentMiBFrom("/proc/self/statm"); }

double ResidentSetMiB(pid_t pid) {
  return ResidentMiBFrom("/proc/" + std::to_string(pid) + "/statm");
}

void ReturnFreedMemory() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

void ReturnFreedMemoryEagerly(std::size_t keep_free_bytes) {
#if defined(__GLIBC__)
  constexpr int kLargestArenaBlock = 32 << 20;  // glibc's own ceiling for the dynamic threshold
  mallopt(M_MMAP_THRESHOLD, kLargestArenaBlock);
  mallopt(M_TRIM_THRESHOLD, static_cast<int>(keep_free_bytes));
#else
  (void)keep_free_bytes;
#endif
}

}  // namespace dammloam::io
