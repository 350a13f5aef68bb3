// Every acceleration structure, described once: its name, how it is made, what it is, which
// parameters it reads and its defaults for them, its deepest tree, how the bench sweeps it,
// its colour in plots, and whether this build has it. make_accelerator, the command line and
// its help, the bench, its report and plots all read this list. Adding a structure is its
// file pair, one entry in registry.cpp and its test suite.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/accel/params.h"

namespace gs {

class Accelerator;

enum class StructureGroup {
  paper,      // the 1D grid and the structures the paper compared it with (§7)
  modern,     // the structures people use today
  reference,  // brute force's answers and the zero-overhead method's time
};

// A parameter a structure reads and its default there, as the flag takes it; empty: the
// AccelParams value, the same for every structure.
struct ParamUse {
  Param param;
  std::string default_text;
};

// One parameter and the values the bench's sweep gives it, one at a time with the others at
// their defaults: the same treatment for every structure, so that no baseline is left at a
// weak setting.
struct SweepAxis {
  Param param;
  std::vector<double> values;
};

struct Structure {
  using Factory = std::unique_ptr<Accelerator> (*)(const AccelParams&);

  std::string name;
  std::string description;  // one line, for help
  StructureGroup group;
  Factory make;               // nullptr when this build does not have the structure
  std::string missing = {};   // why not, when make is nullptr
  int depth_cap = kMaxDepth;  // the deepest --max-depth it accepts
  std::vector<ParamUse> params = {};
  std::vector<SweepAxis> sweep = {};
  std::array<uint8_t, 3> colour;  // RGB in the bench's plots
  // zero: answers from --oracle, an earlier run's hit file. It is the floor the bench divides
  // every time by, not a structure its tables and plots compare.
  bool needs_oracle = false;
  // brute, the reference, takes every structure flag and ignores it, so that any command
  // line can be run again against the reference by changing --accel alone.
  bool takes_any_flag = false;
  // Walks packets of rays together (Accelerator::traces_packets): the bench measures it
  // with packets too.
  bool traces_packets = false;

  bool available() const { return make != nullptr; }
  // Its use of `param`, or nullptr when it does not read it.
  const ParamUse* use(Param param) const;
};

// Every structure, this build's or not, in the order help, tables and plots list them: the
// paper's four in its Figure 12's order, the modern ones, the references.
const std::vector<Structure>& structures();
// The structure called `name`, or nullptr.
const Structure* find_structure(std::string_view name);
// The structure called `name`; UsageError naming the known ones when there is none, or why
// not when this build does not have it.
const Structure& structure_named(std::string_view name);
// The names of a group's structures, in list order, this build's or not.
std::vector<std::string_view> structure_names(StructureGroup group);
// The name of a group ("paper", "modern", "reference").
std::string_view group_name(StructureGroup group);

}  // namespace gs
