// Linked into test executables of the ThreadSanitizer build only.
// libtbb is not built with TSan, so the synchronisation inside its worker pool is invisible to
// it and every parallel_for shows up as a data race. Limiting TBB to one thread makes its loops
// run inline on the calling thread; the threads the project starts itself (daemon stages,
// back-end) still run concurrently, and those are what the TSan suites are there to check.
#include <tbb/global_control.h>

namespace {
const tbb::global_control kTbbInline(tbb::global_control::max_allowed_parallelism, 1);
}  // namespace
