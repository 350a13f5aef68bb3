#include "core/accel/walk.h"

#include <cmath>
#include <nlohmann/json.hpp>

namespace gs {
namespace {

const char* case_name(StateCase c) {
  switch (c) {
    case StateCase::reused:
      return "reused";
    case StateCase::index_only:
      return "index_only";
    case StateCase::reinitialised:
      return "reinitialised";
  }
  return "?";
}

// JSON has no infinity: a miss's t becomes null.
nlohmann::json number(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(); }

}  // namespace

nlohmann::json to_json(const Walk& walk) {
  nlohmann::json cells = nlohmann::json::array();
  for (const WalkCell& cell : walk.cells) {
    nlohmann::json descents = nlohmann::json::array();
    for (const WalkDescent& d : cell.descents)
      descents.push_back({{"voxel", d.voxel},
                          {"depth", d.depth},
                          {"axis", d.axis},
                          {"granularity", d.granularity},
                          {"absolute_granularity", d.absolute_granularity},
                          {"state", d.state},
                          {"cell", d.cell},
                          {"case", case_name(d.state_case)}});
    cells.push_back({{"voxel", cell.voxel},
                     {"depth", cell.depth},
                     {"lo", {cell.lo[0], cell.lo[1], cell.lo[2]}},
                     {"hi", {cell.hi[0], cell.hi[1], cell.hi[2]}},
                     {"t_enter", number(cell.t_enter)},
                     {"entered_axis", cell.entered_axis},
                     {"climbed", cell.climbed},
                     {"descents", std::move(descents)},
                     {"spanning", cell.spanning},
                     {"culled", cell.culled},
                     {"tests", cell.tests},
                     {"mailbox_rejections", cell.rejections},
                     {"hit", cell.hit}});
  }
  const Ray& r = walk.ray;
  return {{"ray",
           {{"origin", {r.origin.x, r.origin.y, r.origin.z}},
            {"dir", {r.dir.x, r.dir.y, r.dir.z}},
            {"tmin", number(r.tmin)},
            {"tmax", number(r.tmax)}}},
          {"hit",
           {{"id", walk.hit.id}, {"t", number(walk.hit.t)}, {"u", walk.hit.u}, {"v", walk.hit.v}}},
          {"t_leave", number(walk.t_leave)},
          {"steps", walk.cells.size()},
          {"cells_crossed", walk.cells_crossed},
          {"cells", std::move(cells)}};
}

}  // namespace gs
