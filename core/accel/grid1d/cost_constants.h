// The five code timings of Jevans 1990, section 6.2 (Intcost, Repcost, Travcost, Vertcost,
// Subcost) as a set: what `gridscope calibrate` measures (bench/calibrate.h) and what
// `--costs FILE.json` applies to the structure parameters.
#pragma once
#include <nlohmann/json.hpp>
#include <string>

#include "core/accel/accelerator.h"

namespace gs {

struct Calibration {
  // Relative to intcost; a constant the measurements could not pin down keeps its default
  // (AccelParams) and detail["unidentified"] says why.
  double intcost = AccelParams{}.intcost, repcost = AccelParams{}.repcost,
         travcost = AccelParams{}.travcost, vertcost = AccelParams{}.vertcost,
         subcost = AccelParams{}.subcost;
  double nanoseconds_per_unit = 0.0;  // one intcost in ns; 0 when unknown
  // Per constant its time and standard error, the fit's rows and residual, the build
  // figures, the out-of-sample check on built-in scenes.
  nlohmann::json detail = nlohmann::json::object();
};

// One of the five constants: its name in files and flags, and where it lives in a
// calibration and in the structure parameters.
struct CostConstant {
  const char* name;
  double Calibration::*calibrated;
  double AccelParams::*parameter;
};
inline constexpr CostConstant kCostConstants[] = {
    {"intcost", &Calibration::intcost, &AccelParams::intcost},
    {"repcost", &Calibration::repcost, &AccelParams::repcost},
    {"travcost", &Calibration::travcost, &AccelParams::travcost},
    {"vertcost", &Calibration::vertcost, &AccelParams::vertcost},
    {"subcost", &Calibration::subcost, &AccelParams::subcost},
};

// {"intcost", "repcost", "travcost", "vertcost", "subcost", "nanoseconds_per_unit", "detail"}.
nlohmann::json to_json(const Calibration& calibration);
// The five constants are required, finite and >= 0; nanoseconds_per_unit and detail are
// optional. Throws InputError naming `path` otherwise.
Calibration calibration_from_json(const nlohmann::json& json, const std::string& path);
// Throws InputError naming the file when it cannot be read, is not JSON or is not a
// calibration.
Calibration read_calibration(const std::string& path);

// The parameters with the five constants replaced by the calibration's; nothing else changes.
AccelParams with_calibration(AccelParams params, const Calibration& calibration);

}  // namespace gs
