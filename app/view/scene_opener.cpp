#include "app/view/scene_opener.h"

#include <imgui.h>

#include <utility>

#include "app/view/state.h"

namespace gs::app {

SceneOpener::SceneOpener(const std::string& scene_name) { path_.set(scene_name); }

void SceneOpener::open(const std::string& spec) {
  path_.set(spec);
  loader_.load(spec);
}

void SceneOpener::take_loaded(ViewState& state) {
  const ViewSetup& setup = state.session.setup();
  if (setup.width == 0) return;
  std::optional<SceneLoader::Result> loaded = loader_.take();
  if (!loaded) return;
  if (!loaded->scene) {
    state.status.set(loaded->error);  // the previous scene stays
    return;
  }
  state.start_camera = frame_box(loaded->scene->bounds(), float(setup.width) / float(setup.height));
  state.pivot = state.start_camera->target;
  state.session.set_scene(std::move(loaded->scene), *state.start_camera);
  state.structure_replaced();
  state.status.set("");
}

void SceneOpener::controls() {
  path_.input("##scene");
  ImGui::SameLine();
  if (ImGui::Button("Open")) open(path_.c_str());
  if (const std::optional<std::string> loading = loader_.pending())
    ImGui::TextWrapped("loading %s...", loading->c_str());
}

}  // namespace gs::app
