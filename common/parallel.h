// Work spread over threads, the one pool of the project: run_experiment's jobs and the
// renderer's frames. Each task writes its own result slot, so results do not depend on the
// number of threads or the order in which tasks finish.
#pragma once

#include <cstddef>
#include <functional>

namespace slt {

// Calls work(i) for every i in [0, count) on max(1, threads) threads (the calling one among
// them, never more than count), each index once, handed out in increasing order. The first
// exception thrown by a call stops the others at their next index; it is rethrown here once
// every thread has stopped.
void ParallelFor(size_t count, int threads, const std::function<void(size_t)>& work);

}  // namespace slt
