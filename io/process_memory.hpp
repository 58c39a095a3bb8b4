#pragma once
#include <sys/types.h>

namespace dammloam::io {

// Resident set size of this process in MiB (from /proc/self/statm); 0 where unavailable.
// For tools' statistics only: the core keeps no notion of processes.
double ResidentSetMiB();
// The same for another process (/proc/PID/statm: VmRSS); 0 once it is gone.
double ResidentSetMiB(pid_t pid);

}  // namespace dammloam::io
