// The benchmark's PNG plots, made from the same records as report.md. They are
// drawn with Dear ImGui's draw lists (its font gives the text) into an OSMesa headless
// context through our ImGui renderer and read back, so they need no display and no plotting
// library. Each structure keeps one colour in every plot.
#pragma once
#include <array>
#include <cstdint>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace gs::app {

// Every plot is this wide; the bar plots are this high, the panel plots grow by rows.
inline constexpr int kPlotWidth = 1200;
inline constexpr int kBarPlotHeight = 600;

// A structure's colour in every plot (RGB), the registry's; a packet column ("grid1d packets")
// its structure's, lighter; grey for a name it does not know.
std::array<uint8_t, 3> structure_colour(std::string_view accel);

// Writes into the existing folder `out_dir` each plot the records hold data for, and
// returns the file names written:
//   relative_to_zero.png  1 thread, primary and shadow rays, default settings: time relative
//                         to the zero-overhead method, bars per scene and structure, log scale
//   speedup.png           2-thread speed-up over 1 thread per scene and structure, with the
//                         ideal 2x and the 1.85x target
//   rmse_vs_time.png      convergence: image RMSE against wall time, one panel per scene,
//                         one line per structure, log RMSE
//   sweep.png             per structure and swept parameter: trace time (top) and memory
//                         (bottom) against the parameter's value, one marker shape per scene
// Throws InputError when a PNG cannot be written or OSMesa gives no OpenGL context.
std::vector<std::string> write_bench_plots(const nlohmann::json& records,
                                           const std::string& out_dir);

}  // namespace gs::app
