// Deterministic fork-join (issue 18, `--threads N`): tasks 0..n-1 run on up to `threads` threads
// and each task writes only its own output slot, so results do not depend on the thread count or
// on scheduling; callers merge the slots in task order. threads <= 1 runs the tasks in order on
// the calling thread. An exception of a task is rethrown after every thread has joined (the
// lowest task index wins, so the error does not depend on scheduling either).
#pragma once
#include <algorithm>
#include <atomic>
#include <exception>
#include <functional>
#include <thread>
#include <vector>

namespace dynref {

inline void ParallelFor(int n_tasks, int threads, const std::function<void(int)>& task) {
  if (threads <= 1 || n_tasks <= 1) {
    for (int i = 0; i < n_tasks; ++i) task(i);
    return;
  }
  std::atomic<int> next{0};
  std::vector<std::exception_ptr> errors(static_cast<size_t>(n_tasks));
  const auto worker = [&] {
    for (int i = next++; i < n_tasks; i = next++) {
      try {
        task(i);
      } catch (...) {
        errors[static_cast<size_t>(i)] = std::current_exception();
      }
    }
  };
  std::vector<std::thread> pool;
  const int n = std::min(threads, n_tasks);
  for (int t = 1; t < n; ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& th : pool) th.join();
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
}

// Items 0..n-1 in fixed chunks of `chunk` (one task each) on up to `threads` threads; `item(i)`
// must write only item i's own output, so the result is the same for any thread count.
inline void ParallelForEach(size_t n, int threads, const std::function<void(size_t)>& item, size_t chunk = 64) {
  if (threads <= 1 || n <= chunk) {
    for (size_t i = 0; i < n; ++i) item(i);
    return;
  }
  ParallelFor(static_cast<int>((n + chunk - 1) / chunk), threads, [&](int c) {
    const size_t end = std::min(n, (static_cast<size_t>(c) + 1) * chunk);
    for (size_t i = static_cast<size_t>(c) * chunk; i < end; ++i) item(i);
  });
}

}  // namespace dynref
