// The controls panel's structure section: the structure, its cost constants, maximum
// granularity, axis rule and memory budget, edited on copies and applied together ("Apply"),
// since each change rebuilds the structure. The script's `set NAME VALUE` edits the same copies.
#pragma once
#include <cstdint>
#include <string>

#include "app/view/text_field.h"
#include "core/accel/accelerator.h"

namespace gs::app {

struct ViewState;

// A byte count as --memory-budget takes it back: the largest suffix that divides it.
std::string byte_text(uint64_t bytes);

class StructureEditor {
 public:
  StructureEditor(const std::string& accel, const AccelParams& params);

  void controls(ViewState& state);
  // A checked script step (parse_script): the edit fields take the value, then Apply.
  void set(ViewState& state, const std::string& name, const std::string& value);

 private:
  // The edited structure and parameters replace the current ones: a new structure.
  void apply(ViewState& state);

  int accel_ = 0;  // an index into accelerator_names()
  AccelParams params_;
  TextField<32> budget_text_;
};

}  // namespace gs::app
