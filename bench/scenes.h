// The benchmark's scenes: the five scene roles of the paper's section 7 played by built-in
// scenes and by real meshes from the assets folder (assets/README.md), each with the view the
// bench renders it from. A scene can also be any SCENE argument (a path or builtin:NAME).
#pragma once
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/scene/camera.h"
#include "core/scene/scene.h"

namespace gs {

struct BenchScene {
  std::string label;  // "pyramid", "lumpy", ... or the SCENE argument as given
  // The paper's scene it stands for ("pyramid", "lumpy", "drum", "trike", "car", "scale"),
  // empty for a user's scene.
  std::string role;
  // Whether it has the varying local complexity the paper's claim is about; unknown for a
  // user's scene.
  std::optional<bool> varying_complexity;
  std::shared_ptr<const Scene> scene;
  std::optional<Camera> camera;  // default: frame_box of the scene at the image's aspect
  std::optional<glm::vec3> light =
      std::nullopt;  // default: the renderer's, above and behind the camera
};

// Where the real meshes are: $GRIDSCOPE_ASSETS when set, else assets/ in the current folder
// (the bench is run from the source tree). Empty when neither is there. No path is compiled
// in: an installed gridscope must not read a build machine's folders.
std::string find_assets_dir();

// The suite's names in order: pyramid, lumpy, dragon, bunny-sibenik, f15, dragon-full.
// --quick runs the first two (built-in, so it needs no meshes).
std::vector<std::string> bench_suite(bool quick);

// Loads one benchmark scene by suite name, builtin:NAME or path. A suite scene whose meshes
// are missing from assets_dir (files at assets_dir/sibenik/sibenik.obj, ...) gives
// std::nullopt and sets `skipped` to why, naming the script that fetches them; a user's
// scene that cannot be read throws InputError.
std::optional<BenchScene> load_bench_scene(const std::string& name, const std::string& assets_dir,
                                           std::string& skipped);

}  // namespace gs
