#ifndef FITBASE_CORE_PARALLEL_FOR_H_
#define FITBASE_CORE_PARALLEL_FOR_H_

#include <cstddef>

#include "absl/functional/function_ref.h"

namespace fitbase::core {

// Calls `body(i)` once for every i in [0, count), on up to `threads` threads, the caller's
// among them (fewer than 1 counts as 1; never more threads than items). Indices are handed out
// one at a time from a shared counter, in increasing order, so a slow item never holds up the
// others' threads. Returns when every call has returned. `body` must be safe to call from
// several threads at once on different indices; results that must not depend on the thread
// count belong in per-index slots, combined afterwards in index order. A body that wants to
// stop early (for example after an error) checks its own flag and returns at once.
void ParallelFor(size_t count, int threads, absl::FunctionRef<void(size_t)> body);

}  // namespace fitbase::core

#endif  // FITBASE_CORE_PARALLEL_FOR_H_
