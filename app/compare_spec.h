// `--compare SPEC`: what side B of an A/B comparison changes from side A, the command line's
// own run. SPEC is NAME=VALUE words separated by commas or blanks: `accel=NAME`,
// `packets=on|off`, or a structure flag without its dashes (`max-granularity=8`,
// `vertcost=4`), each checked as the command line checks it.
#pragma once
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/accel/accelerator.h"

namespace gs::app {

struct CompareSpec {
  std::string text;  // as given, for messages
  std::optional<std::string> accel;
  std::optional<bool> packets;
  std::vector<std::pair<std::string, std::string>> structure_flags;  // {"--vertcost", "4"}
};

// Throws UsageError naming the word for an empty SPEC, a word without '=', an unknown
// structure or setting, or a bad value.
CompareSpec parse_compare(const std::string& text);

// "B: grid1d max-granularity=8": B's structure and what the spec changes, for titles and
// the totals table.
std::string side_b_label(const CompareSpec& spec, const std::string& accel_a);

// Side B's structure and parameters: A's with the spec's changes. Throws UsageError when B's
// structure does not read a structure flag the spec sets (as check_structure does) or
// replays another run's hits (zero).
struct CompareSide {
  std::string accel;
  AccelParams params;
};
CompareSide side_b(const CompareSpec& spec, const std::string& accel_a,
                   const AccelParams& params_a);

}  // namespace gs::app
