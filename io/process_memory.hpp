#pragma once

namespace dammloam::io {

// Resident set size of this process in MiB (from /proc/self/statm); 0 where unavailable.
// For tools' statistics only: the core keeps no notion of processes.
double ResidentSetMiB();

}  // namespace dammloam::io
