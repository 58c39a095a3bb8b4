#pragma once
#include <sys/types.h>

#include <cstddef>

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

// For a process that runs for days. glibc raises its mmap and trim thresholds after the first
// large block is freed (up to 32 and 64 MiB), and from then on every thread's arena keeps the
// pages of a burst of freed memory resident for good. Fixed thresholds: blocks up to 32 MiB
// still come from the arenas (no page faults per scan), and an arena gives back its free top
// beyond `keep_free_bytes` as soon as it is freed. glibc only; elsewhere a no-op.
void ReturnFreedMemoryEagerly(std::size_t keep_free_bytes);

// dammloamd's setting: 8 MiB free per arena absorbs one scan's buffers. The offline runner and
// the odometry benchmark use it too, so that their per-scan times are the daemon's.
inline constexpr std::size_t kDaemonKeepFreeBytes = std::size_t{8} << 20;

}  // namespace dammloam::io
