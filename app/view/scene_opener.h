// Opening another scene while the window runs: the file is read on the loader's thread, so a
// huge file does not freeze the window, and a newer open supersedes an older one. The
// finished load replaces the scene (framed anew) or, when it failed, leaves the scene as it
// was and names the problem in the status line. Also the controls panel's scene section.
#pragma once
#include <optional>
#include <string>

#include "app/view/text_field.h"
#include "core/render/progressive.h"

namespace gs::app {

struct ViewState;

class SceneOpener {
 public:
  explicit SceneOpener(const std::string& scene_name);

  // Starts loading SCENE (a path or builtin:NAME) and returns at once.
  void open(const std::string& spec);
  // A load not yet taken: its SCENE.
  std::optional<std::string> pending() const { return loader_.pending(); }
  // A finished load into the view. Framing needs the viewport's aspect: waits for the layout.
  void take_loaded(ViewState& state);
  void controls();

 private:
  TextField<1024> path_;
  SceneLoader loader_;  // its destructor waits for a load in progress
};

}  // namespace gs::app
