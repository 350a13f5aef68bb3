#include "core/accel/accelerator.h"

#include "core/accel/registry.h"
#include "core/base/check.h"

namespace gs {

void check_params(const std::string& name, const AccelParams& params) {
  const Structure* structure = find_structure(name);
  for (const ParamSpec& spec : param_table()) {
    if (spec.param == Param::max_depth && structure)
      check_param(params, spec, structure->depth_cap, name);
    else
      check_param(params, spec);
  }
}

void TraceCounters::add(const TraceCounters& other) {
  intersection_tests += other.intersection_tests;
  mailbox_rejections += other.mailbox_rejections;
  traversal_steps += other.traversal_steps;
  descents += other.descents;
  leaf_triangles += other.leaf_triangles;
  voxels_built += other.voxels_built;
  lazy_build_seconds += other.lazy_build_seconds;
  packets += other.packets;
  packet_rays += other.packet_rays;
  packet_fallback_rays += other.packet_fallback_rays;
  packet_steps += other.packet_steps;
  packet_step_rays += other.packet_step_rays;
  packet_step_slots += other.packet_step_slots;
}

double TraceCounters::packet_active_fraction() const {
  return packet_step_slots > 0 ? double(packet_step_rays) / double(packet_step_slots) : 0.0;
}

void Accelerator::trace_packet(std::span<const Ray> rays, std::span<const uint64_t> keys,
                               std::span<Hit> hits, bool any_hit, ThreadContext& context) const {
  GRIDSCOPE_CHECK(rays.size() <= kMaxPacketRays && keys.size() == rays.size() &&
                  hits.size() == rays.size());
  for (size_t i = 0; i < rays.size(); ++i) {
    context.ray_index = keys[i];
    hits[i] = any_hit ? this->any_hit(rays[i], context) : intersect(rays[i], context);
  }
}

void Accelerator::sample(std::span<const Ray>, double, const SpawnRays&, int) {}

std::vector<std::string> accelerator_names() {
  std::vector<std::string> names;
  for (const Structure& structure : structures())
    if (structure.available()) names.push_back(structure.name);
  return names;
}

std::unique_ptr<Accelerator> make_accelerator(const std::string& name, const AccelParams& params) {
  const Structure& structure = structure_named(name);
  check_params(name, params);
  return structure.make(params);
}

}  // namespace gs
