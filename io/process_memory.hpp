#pragma once
#include <sys/types.h>

namespace dammloam::io {

// Resident set size of this process in MiB (from /proc/self/statm); 0 where unavailable.
// For tools' statistics only: the core keeps no notion of processes.
double ResidentSetMiB();
// The same for another process (/proc/PID/statm: VmRSS); 0 once it is gone.
double ResidentSetMiB(pid_t pid);

// Hands memory the allocator holds free back to the system (glibc: malloc_trim; elsewhere a
// no-op). For after a burst of large temporary buffers, such as a map save: glibc keeps such
// freed heap pages resident, so each burst would leave the process tens of MiB larger.
void ReturnFreedMemory();

}  // namespace dammloam::io
