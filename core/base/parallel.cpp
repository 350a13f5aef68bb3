#include "core/base/parallel.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <string>
#include <thread>
#include <vector>

#include "core/base/error.h"

namespace gs {

int default_thread_count() {
  return int(std::clamp(std::thread::hardware_concurrency(), 1u, unsigned(kMaxThreads)));
}

void check_thread_count(int threads) {
  if (threads < 1 || threads > kMaxThreads)
    throw UsageError("--threads " + std::to_string(threads) + ": must be between 1 and " +
                     std::to_string(kMaxThreads));
}

size_t chunk_workers(size_t count, size_t chunk, int threads) {
  const size_t chunks = (count + chunk - 1) / chunk;
  return std::min(size_t(std::max(threads, 1)), chunks);
}

size_t parallel_chunks(size_t count, size_t chunk, int threads, const ChunkWork& body) {
  const size_t chunks = (count + chunk - 1) / chunk;
  const size_t workers = chunk_workers(count, chunk, threads);
  std::vector<std::exception_ptr> errors(workers);
  std::atomic<size_t> next{0};
  auto work = [&](size_t worker) {
    try {
      for (size_t c; (c = next.fetch_add(1, std::memory_order_relaxed)) < chunks;)
        body(worker, c * chunk, std::min(count, (c + 1) * chunk));
    } catch (...) {
      errors[worker] = std::current_exception();
      next.store(chunks);  // the others stop after their current chunk
    }
  };
  {
    // jthreads join on destruction, also when starting one of them throws.
    std::vector<std::jthread> pool;
    for (size_t w = 1; w < workers; ++w) pool.emplace_back(work, w);
    if (workers > 0) work(0);
  }
  for (const std::exception_ptr& error : errors)
    if (error) std::rethrow_exception(error);
  return workers;
}

}  // namespace gs
