#include "app/view/view.h"

#include <charconv>
#include <memory>
#include <utility>
#include <vector>

#include "app/view/viewer.h"
#include "core/base/error.h"
#include "core/base/files.h"
#include "core/scene/scene.h"

namespace gs::app {

namespace {

constexpr const char* kDefaultScene = "builtin:lumpy";

void check_view_usage(const ViewJob& job) {
  make_accelerator(job.accel, job.params);  // UsageError for an unknown structure
  if (!job.walk_out.empty() && !job.click) throw UsageError("view: --walk-out needs --click X,Y");
  if (!job.walk_out.empty() && job.accel != "grid1d")
    throw UsageError("view: --walk-out needs --accel grid1d ('" + job.accel + "' has no cells)");
}

}  // namespace

std::array<double, 2> parse_click(const std::string& text) {
  const size_t comma = text.find(',');
  const auto part = [&](const std::string& word) {
    double value = 0.0;
    const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value);
    if (comma == std::string::npos || word.empty() || error != std::errc() ||
        end != word.data() + word.size() || !(value >= 0.0 && value <= 1.0))
      throw UsageError("--click '" + text + "': expected X,Y, fractions 0..1 of the viewport");
    return value;
  };
  return {part(text.substr(0, comma)),
          part(comma == std::string::npos ? "" : text.substr(comma + 1))};
}

void run_view(const ViewJob& job) {
  check_view_usage(job);
  std::vector<ScriptStep> steps;
  if (!job.script.empty()) {
    const std::vector<char> text = read_file(job.script);
    steps = parse_script(std::string(text.begin(), text.end()), job.script);
  }
  // The scene is read before the window opens, so a bad file is one line and exit 1.
  auto scene =
      std::make_shared<const Scene>(load_scene(job.scene.empty() ? kDefaultScene : job.scene));
  Viewer viewer(job, std::move(scene), std::move(steps));
  viewer.run();
}

}  // namespace gs::app
