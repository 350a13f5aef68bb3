// The benchmark's scenes (issue 4): the five scene roles of the paper's section 7 played by
// built-in scenes and by real meshes from ../shared/scenes, each with the view the bench
// renders it from. A scene can also be any SCENE argument (a path or builtin:NAME).
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

// Where the shared meshes are: $GRIDSCOPE_SHARED when set, else ../shared beside the source
// tree the binary was built from. Empty when neither holds scenes/.
std::string find_shared_dir();

// The suite's names in order: pyramid, lumpy, dragon, bunny-sibenik, f15, dragon-full.
// --quick runs the first two (built-in, so it needs no shared meshes).
std::vector<std::string> bench_suite(bool quick);

// Loads one benchmark scene by suite name, builtin:NAME or path. A suite scene whose meshes
// are missing from shared_dir gives std::nullopt and sets `skipped` to why; a user's scene
// that cannot be read throws InputError.
std::optional<BenchScene> load_bench_scene(const std::string& name, const std::string& shared_dir,
                                           std::string& skipped);

}  // namespace gs
