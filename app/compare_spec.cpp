#include "app/compare_spec.h"

#include <algorithm>
#include <sstream>

#include "app/flags.h"
#include "core/accel/registry.h"
#include "core/base/error.h"

namespace gs::app {

namespace {

// The words of SPEC: commas count as blanks.
std::vector<std::string> compare_words(std::string text) {
  std::replace(text.begin(), text.end(), ',', ' ');
  std::istringstream in(text);
  std::vector<std::string> words;
  for (std::string word; in >> word;) words.push_back(word);
  return words;
}

void apply_word(CompareSpec& spec, const std::string& name, const std::string& value) {
  if (name == "accel") {
    const std::vector<std::string> names = accelerator_names();
    if (std::find(names.begin(), names.end(), value) == names.end())
      throw UsageError("unknown structure '" + value + "'");
    spec.accel = value;
  } else if (name == "packets") {
    if (value != "on" && value != "off")
      throw UsageError("packets='" + value + "': expected on or off");
    spec.packets = value == "on";
  } else {
    AccelParams checked;  // the value is checked here; B's parameters get it in side_b
    apply_structure_flag(checked, "--" + name, value);
    spec.structure_flags.emplace_back("--" + name, value);
  }
}

}  // namespace

std::string side_b_label(const CompareSpec& spec, const std::string& accel_a) {
  std::string label = "B: " + spec.accel.value_or(accel_a);
  for (const auto& [flag, value] : spec.structure_flags) {
    label += ' ';
    label.append(flag, 2);  // without its dashes, as SPEC names it
    label += '=';
    label += value;
  }
  if (spec.packets) label += *spec.packets ? " packets=on" : " packets=off";
  return label;
}

CompareSpec parse_compare(const std::string& text) {
  CompareSpec spec;
  spec.text = text;
  const std::vector<std::string> words = compare_words(text);
  if (words.empty())
    throw UsageError("--compare '" + text + "': expected NAME=VALUE, e.g. accel=bvh");
  for (const std::string& word : words) {
    const size_t equals = word.find('=');
    if (equals == std::string::npos || equals == 0 || equals + 1 == word.size())
      throw UsageError("--compare '" + word + "': expected NAME=VALUE, e.g. accel=bvh");
    try {
      apply_word(spec, word.substr(0, equals), word.substr(equals + 1));
    } catch (const UsageError& e) {
      throw UsageError("--compare '" + text + "': " + e.what());
    }
  }
  return spec;
}

CompareSide side_b(const CompareSpec& spec, const std::string& accel_a,
                   const AccelParams& params_a) {
  CompareSide side{spec.accel.value_or(accel_a), params_a};
  // A replay structure answers from another run's hit file, which B's rays have none of.
  if (structure_named(side.accel).needs_oracle)
    throw UsageError("--compare '" + spec.text + "': structure '" + side.accel +
                     "' replays another run's hits and cannot be compared here");
  std::vector<std::string> given;
  for (const auto& [flag, value] : spec.structure_flags) {
    apply_structure_flag(side.params, flag, value);
    given.push_back(flag);
  }
  try {
    check_structure(side.accel, given, side.params);
  } catch (const UsageError& e) {
    throw UsageError("--compare '" + spec.text + "': " + e.what());
  }
  return side;
}

}  // namespace gs::app
