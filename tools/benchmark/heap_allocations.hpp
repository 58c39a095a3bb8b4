#pragma once
// Heap allocations of this process, counted for the benchmark's "allocations per scan" (issue 57:
// no allocation per scan in the steady state). Linking this file replaces malloc, calloc, realloc
// and the aligned allocators with glibc's own behind a counter; operator new and Eigen come
// through malloc. Under a sanitizer (which owns malloc) nothing is replaced or counted.
#include <cstdint>

namespace dammloam::bench {

// False under ASan / TSan / MSan builds: then HeapAllocations() stays 0.
bool HeapAllocationsCounted();
// Calls to malloc, calloc, realloc (to a new size), memalign, posix_memalign and aligned_alloc
// since the process started, over all threads.
std::uint64_t HeapAllocations();

}  // namespace dammloam::bench
