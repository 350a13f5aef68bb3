// The controls panel's structure section: the structure and the parameters it reads, both
// listed from the registry and the parameter table (core/accel/registry.h, params.h), so a new
// structure or parameter shows here without touching the viewer. Edits go to copies and are
// applied together ("Apply"), since each change rebuilds the structure. The script's
// `set NAME VALUE` edits the same copies.
#pragma once
#include <string>

#include "app/view/text_field.h"
#include "core/accel/accelerator.h"

namespace gs {
struct Structure;
}

namespace gs::app {

struct ViewState;

class StructureEditor {
 public:
  StructureEditor(const std::string& accel, const AccelParams& params);

  void controls(ViewState& state);
  // A checked script step (parse_script): the edit fields take the value, then Apply.
  void set(ViewState& state, const std::string& name, const std::string& value);

 private:
  // The section's widgets for the structure being edited (null: none is chosen).
  void section(ViewState& state, const Structure* edited);
  // The widget of one parameter the edited structure reads.
  void param_control(const ParamSpec& spec, const std::string& default_text);
  // The edited structure and parameters replace the current ones: a new structure.
  void apply(ViewState& state);

  std::string accel_;
  AccelParams params_;
  TextField<32> budget_text_;  // bytes are typed ("512M"), parsed on Apply
};

}  // namespace gs::app
