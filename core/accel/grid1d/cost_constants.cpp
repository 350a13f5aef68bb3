#include "core/accel/grid1d/cost_constants.h"

#include <cmath>

#include "core/base/error.h"
#include "core/scene/scene.h"

namespace gs {

using json = nlohmann::json;

json to_json(const Calibration& calibration) {
  json out = json::object();
  for (const CostConstant& constant : kCostConstants)
    out[constant.name] = calibration.*constant.calibrated;
  out["nanoseconds_per_unit"] = calibration.nanoseconds_per_unit;
  out["detail"] = calibration.detail;
  return out;
}

Calibration calibration_from_json(const json& in, const std::string& path) {
  if (!in.is_object()) fail_input(path, "a calibration is a JSON object");
  // A finite number >= 0; NaN and infinities are not JSON numbers in files, but may be in
  // a json value built in memory.
  const auto number = [&](const char* key) {
    const json& value = in.at(key);
    if (!value.is_number() || !std::isfinite(value.get<double>()) || value.get<double>() < 0.0) {
      const bool nan = value.is_number() && std::isnan(value.get<double>());
      fail_input(path, std::string("\"") + key + "\" must be a finite number >= 0, not " +
                           (nan ? "NaN" : value.dump()));
    }
    return value.get<double>();
  };
  Calibration calibration;
  for (const CostConstant& constant : kCostConstants) {
    if (!in.contains(constant.name))
      fail_input(path, std::string("\"") + constant.name + "\" is missing");
    calibration.*constant.calibrated = number(constant.name);
  }
  if (in.contains("nanoseconds_per_unit"))
    calibration.nanoseconds_per_unit = number("nanoseconds_per_unit");
  if (in.contains("detail")) calibration.detail = in.at("detail");
  return calibration;
}

Calibration read_calibration(const std::string& path) {
  constexpr uint64_t kMaxBytes = uint64_t{16} << 20;
  const json in = json::parse(detail::read_scene_file(path, kMaxBytes), nullptr, false);
  if (in.is_discarded()) fail_input(path, "is not valid JSON");
  return calibration_from_json(in, path);
}

AccelParams with_calibration(AccelParams params, const Calibration& calibration) {
  for (const CostConstant& constant : kCostConstants)
    params.*constant.parameter = calibration.*constant.calibrated;
  return params;
}

}  // namespace gs
