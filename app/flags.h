// The flags of the `gridscope` commands, each defined once and shared by the commands that
// take it: its name, the value it takes, its help line and what it does to the job being
// assembled. The structure flags come from the parameter table (core/accel/params.h), which
// structures read each one from the registry (core/accel/registry.h).
#pragma once
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/accel/params.h"
#include "core/render/overlay.h"
#include "core/scene/camera.h"

namespace gs::app {

struct Flag {
  std::string name;                               // "--size"
  std::string value_name;                         // "WxH"; empty for a switch
  std::string help;                               // one line (help wraps it)
  std::function<void(const std::string&)> apply;  // gets "" for a switch
  // One of the structure flags trace, render, shot and view share (help lists them apart).
  bool structure = false;
};
using Flags = std::vector<Flag>;

// A command line's words once its flags are applied.
struct Words {
  std::vector<std::string> positionals;
  std::vector<std::string> flags;  // the names of the flags met, in order
};

// Applies the flags met in words (--name VALUE, --name=VALUE or a --switch, in any order).
// Any word starting with '-' is a flag, so a value that starts with '-' must follow its flag.
// Throws UsageError naming `command` for an unknown flag.
Words parse_words(const std::string& command, std::span<const std::string> words,
                  const Flags& flags);

// The whole text as an integer, or nothing.
std::optional<long long> to_integer(const std::string& text);
[[noreturn]] void bad_value(const std::string& flag, const std::string& text,
                            const std::string& expected);
int parse_int(const std::string& flag, const std::string& text, int lo, int hi);

Flag string_flag(std::string name, std::string value_name, std::string help, std::string& field);
Flag switch_flag(std::string name, std::string help, bool& field);
Flag int_flag(std::string name, std::string help, int lo, int hi, int& field);
// The flags below name their field's value when they are made as its default.
Flag seed_flag(uint64_t& seed);
// WxH, each side 1..kMaxImageSide.
Flag size_flag(std::string name, std::string help, int& width, int& height);
Flag camera_flag(std::optional<Camera>& camera);
Flag spp_flag(int& spp);
Flag bounces_flag(int& bounces);
Flag packets_flag(bool& packets);
Flag threads_flag(int& threads);
Flag accel_flag(std::string& accel);
Flag overlay_flag(OverlaySelection& overlays);

// Every row of the parameter table that is a structure flag, and --costs FILE.json (the five
// cost constants of a `calibrate --out` file; flags after it override them).
Flags structure_flags(AccelParams& params);
// --oracle FILE.hits (trace and render).
Flag oracle_flag(AccelParams& params);

// Once every flag is applied: throws UsageError for an unknown structure or one this build
// lacks, a structure flag among `given` that structure `accel` does not read ("--density:
// structure 'grid1d' does not use it"; --costs counts as the five cost constants), or a
// parameter outside its range for that structure (check_params).
void check_structure(const std::string& accel, const std::vector<std::string>& given,
                     const AccelParams& params);

// Sets one structure parameter from its flag and text (e.g. "--max-granularity", "8") as the
// command line does, for the viewer's panel and --script. UsageError for an unknown flag or
// a bad value. Parameters set so are not flags: no structure refuses them.
void apply_structure_flag(AccelParams& params, const std::string& flag, const std::string& value);

}  // namespace gs::app
