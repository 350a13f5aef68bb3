// What the trace and render jobs share: tracing items on threads with one structure
// context per thread, and the stats record of a run.
#pragma once
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>

#include "core/accel/accelerator.h"
#include "core/scene/scene.h"

namespace gs {

// body(context, begin, end) handles items [begin, end) with the context of the thread it
// runs on (parallel_chunks, each worker with its own Accelerator::make_context). Returns the
// workers' counters, merged. An exception in any thread stops the loop and is rethrown here.
using TraceChunk = std::function<void(ThreadContext&, size_t, size_t)>;
TraceCounters trace_chunks(const Accelerator& accel, size_t count, size_t chunk, int threads,
                           const TraceChunk& body);

// What a run measured besides the structure's own figures.
struct RunFigures {
  uint64_t rays = 0;
  double build_seconds = 0.0;  // build + sampling pass + eager build; lazy work comes from counters
  double trace_seconds = 0.0;
  TraceCounters counters;
};

// The stats record (docs/design.md §3 `--stats`); `parameters` is echoed as given.
nlohmann::json run_stats(const Scene& scene, const Accelerator& accel, nlohmann::json parameters,
                         const RunFigures& figures);

}  // namespace gs
