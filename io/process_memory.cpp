#include "io/process_memory.hpp"

#include <fstream>
#include <unistd.h>

namespace dammloam::io {

double ResidentSetMiB() {
  std::ifstream statm("/proc/self/statm");
  long pages_total = 0, pages_resident = 0;
  if (!(statm >> pages_total >> pages_resident)) return 0.0;
  const long page_size = sysconf(_SC_PAGESIZE);
  return static_cast<double>(pages_resident) * static_cast<double>(page_size) / (1024.0 * 1024.0);
}

}  // namespace dammloam::io
