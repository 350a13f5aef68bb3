#include "core/trace/run.h"

#include <memory>
#include <vector>

#include "core/base/files.h"
#include "core/base/parallel.h"

namespace gs {

TraceCounters trace_chunks(const Accelerator& accel, size_t count, size_t chunk, int threads,
                           const TraceChunk& body) {
  std::vector<std::unique_ptr<ThreadContext>> contexts;
  for (size_t w = 0; w < chunk_workers(count, chunk, threads); ++w)
    contexts.push_back(accel.make_context());
  parallel_chunks(count, chunk, threads, [&](size_t worker, size_t begin, size_t end) {
    body(*contexts[worker], begin, end);
  });
  TraceCounters merged;
  for (const auto& context : contexts) merged.add(context->counters);
  return merged;
}

nlohmann::json run_stats(const Scene& scene, const Accelerator& accel, nlohmann::json parameters,
                         const RunFigures& figures) {
  const StructureStats structure = accel.stats();
  const TraceCounters& counters = figures.counters;
  nlohmann::json stats;
  stats["accel"] = accel.name();
  stats["parameters"] = std::move(parameters);
  stats["scene"] = scene.name;
  stats["triangles"] = scene.triangle_count();
  stats["degenerate_triangles"] = scene.degenerate_count();
  stats["rays"] = figures.rays;
  stats["build_seconds"] = figures.build_seconds + counters.lazy_build_seconds;
  stats["lazy_build_seconds"] = counters.lazy_build_seconds;
  stats["trace_seconds"] = figures.trace_seconds;
  stats["rays_per_second"] =
      figures.trace_seconds > 0.0 ? double(figures.rays) / figures.trace_seconds : 0.0;
  stats["nodes"] = value_or_null(structure.nodes);
  stats["voxels_subdivided"] = value_or_null(structure.voxels_subdivided);
  stats["leaves"] = value_or_null(structure.leaves);
  stats["traversal_states"] = value_or_null(structure.traversal_states);
  stats["depth"] = value_or_null(structure.depth);
  // A counter the structure cannot measure (embree) is null, never a made-up 0.
  const auto counted = [](bool measured, uint64_t value) {
    return measured ? nlohmann::json(value) : nlohmann::json(nullptr);
  };
  stats["intersection_tests"] = counted(structure.counts_tests, counters.intersection_tests);
  stats["mailbox_rejections"] = counted(structure.counts_tests, counters.mailbox_rejections);
  stats["traversal_steps"] = counted(structure.counts_steps, counters.traversal_steps);
  stats["descents"] = counted(structure.counts_descents, counters.descents);
  // Packets: null unless the run traced rays in packets.
  const bool packets = counters.packet_rays + counters.packet_fallback_rays > 0;
  const auto packet_figure = [&](nlohmann::json value) {
    return packets ? std::move(value) : nlohmann::json(nullptr);
  };
  stats["packets"] = packet_figure(counters.packets);
  stats["packet_fallback_rays"] = packet_figure(counters.packet_fallback_rays);
  stats["packet_steps"] = packet_figure(counters.packet_steps);
  stats["packet_active_fraction"] = packet_figure(counters.packet_active_fraction());
  stats["memory_bytes"] = structure.memory_bytes;
  stats["voxels_over_budget"] = structure.voxels_over_budget;
  return stats;
}

}  // namespace gs
