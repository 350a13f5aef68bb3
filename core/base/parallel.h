// The one thread pool pattern of gridscope: items [0, count) handed out in chunks to a
// fixed number of workers, the caller's thread among them.
#pragma once
#include <cstddef>
#include <functional>

namespace gs {

inline constexpr int kMaxThreads = 1024;
// std::thread::hardware_concurrency(), or 1 where it is unknown.
int default_thread_count();
// Throws UsageError unless 1 <= threads <= kMaxThreads.
void check_thread_count(int threads);

// body(worker, begin, end) handles items [begin, end) on worker `worker` (0 .. workers - 1,
// each worker one thread; worker 0 is the caller's). Chunks of `chunk` items are handed out
// dynamically, so threads finish together when some items take longer. Returns the number
// of workers used (at most `threads`, at most the number of chunks). An exception in any
// worker stops the others after their current chunk and is rethrown here.
using ChunkWork = std::function<void(size_t worker, size_t begin, size_t end)>;
size_t parallel_chunks(size_t count, size_t chunk, int threads, const ChunkWork& body);
// The number of workers parallel_chunks(count, chunk, threads, ...) uses.
size_t chunk_workers(size_t count, size_t chunk, int threads);

}  // namespace gs
