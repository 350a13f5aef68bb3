#include "app/view/script.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <optional>
#include <sstream>
#include <utility>

#include "app/compare_spec.h"
#include "app/flags.h"
#include "app/view/compare_view.h"
#include "app/view/output.h"
#include "app/view/panels.h"
#include "app/view/state.h"
#include "app/view/view.h"
#include "core/base/error.h"
#include "core/render/overlay.h"
#include "core/render/render.h"

namespace gs::app {

namespace {

// A scripted click is followed by this many frames before exiting, so that tables that
// size themselves from their content have measured it when the screenshot is taken.
constexpr int kFramesAfterClick = 2;

// `text` without leading and trailing blanks (a Windows line end among them).
std::string trimmed(const std::string& text) {
  const size_t first = text.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  return text.substr(first, text.find_last_not_of(" \t\r") - first + 1);
}

// The blank-separated words of a script line's part.
std::vector<std::string> split_words(const std::string& text) {
  std::vector<std::string> words;
  std::istringstream in(text);
  for (std::string word; in >> word;) words.push_back(word);
  return words;
}

// An integer that is the whole word.
std::optional<int> whole_int(const std::string& word) {
  int value = 0;
  const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value);
  if (error != std::errc() || end != word.data() + word.size()) return std::nullopt;
  return value;
}

// A number that is the whole word.
std::optional<double> whole_number(const std::string& word) {
  double value = 0;
  const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value);
  if (error != std::errc() || end != word.data() + word.size()) return std::nullopt;
  return value;
}

// WxH for `resize`: 0x0 (minimised) or each side 1..kMaxImageSide.
std::optional<std::array<int, 2>> window_size(const std::string& word) {
  const size_t x = word.find('x');
  if (x == std::string::npos) return std::nullopt;
  const std::optional<int> w = whole_int(word.substr(0, x)), h = whole_int(word.substr(x + 1));
  if (!w || !h || (*w == 0) != (*h == 0) || *w < 0 || *h < 0 || *w > kMaxImageSide ||
      *h > kMaxImageSide)
    return std::nullopt;
  return std::array<int, 2>{*w, *h};
}

// `set NAME VALUE`'s value, checked as the command line checks it; throws UsageError.
void check_setting(const std::string& name, const std::string& value) {
  if (name == "overlay") {
    parse_overlays(value, "set overlay");
    return;
  }
  if (name == "compare") {
    if (value != "off") parse_compare(value);
    return;
  }
  if (name == "compare-view") {
    if (!compare_mode_named(value))
      throw UsageError("set compare-view '" + value + "': expected split, a, b or difference");
    return;
  }
  if (name == "packets") {
    if (value != "on" && value != "off")
      throw UsageError("set packets '" + value + "': expected on or off");
    return;
  }
  if (name != "accel") {
    AccelParams checked;
    apply_structure_flag(checked, "--" + name, value);
    return;
  }
  const std::vector<std::string> names = accelerator_names();
  if (std::find(names.begin(), names.end(), value) == names.end())
    throw UsageError("set accel '" + value + "': unknown structure");
}

// One step from "ACTION ARGS" (trimmed); throws UsageError describing what is wrong.
ScriptStep parse_action(const std::string& action) {
  const std::vector<std::string> words = split_words(action);
  ScriptStep step;
  const std::string verb = words.empty() ? "" : words[0];
  if (verb == "resize" && words.size() == 2) {
    const std::optional<std::array<int, 2>> size = window_size(words[1]);
    if (!size)
      throw UsageError("resize '" + words[1] + "': expected WxH, 0x0 or sides 1.." +
                       std::to_string(kMaxImageSide));
    step.action = ScriptStep::Action::resize, step.size = *size;
  } else if (verb == "open" && words.size() >= 2) {
    step.action = ScriptStep::Action::open;
    step.name = trimmed(action.substr(verb.size()));  // a path may hold blanks
  } else if (verb == "set" && words.size() == 3) {
    step.action = ScriptStep::Action::set, step.name = words[1], step.value = words[2];
    check_setting(step.name, step.value);
  } else if (verb == "orbit" && words.size() == 2) {
    const std::optional<double> degrees = whole_number(words[1]);
    if (!degrees || !std::isfinite(*degrees) || std::abs(*degrees) > 360.0)
      throw UsageError("orbit '" + words[1] + "': expected degrees in -360..360");
    step.action = ScriptStep::Action::orbit, step.degrees = float(*degrees);
  } else if (verb == "drag-splitter" && words.size() == 3) {
    const std::optional<int> pixels = whole_int(words[2]);
    if ((words[1] != "right" && words[1] != "bottom") || !pixels ||
        std::abs(*pixels) > kMaxImageSide)
      throw UsageError("drag-splitter '" + words[1] + " " + words[2] +
                       "': expected right or bottom and pixels in -" +
                       std::to_string(kMaxImageSide) + ".." + std::to_string(kMaxImageSide));
    step.action = ScriptStep::Action::drag_splitter;
    step.splitter = words[1] == "right" ? Splitter::right : Splitter::bottom;
    step.pixels = *pixels;
  } else if (verb == "key" && words.size() == 2) {
    if (words[1] != "F1" && words[1] != "?")
      throw UsageError("key '" + words[1] + "': expected F1 or ? (the help overlay)");
    step.action = ScriptStep::Action::help_key;
  } else if (verb == "tab" && words.size() == 2) {
    if (std::find(std::begin(kBottomTabs), std::end(kBottomTabs), words[1]) ==
        std::end(kBottomTabs))
      throw UsageError("tab '" + words[1] + "': expected walk, statistics or states");
    step.action = ScriptStep::Action::tab, step.name = words[1];
  } else if (verb == "wait" && words.size() == 1) {
    step.action = ScriptStep::Action::wait;
  } else if (verb == "close" && words.size() == 1) {
    step.action = ScriptStep::Action::close;
  } else {
    throw UsageError("'" + action +
                     "': expected resize WxH, open SCENE, set NAME VALUE, orbit DEG, drag-splitter "
                     "right|bottom PIXELS, key F1, tab NAME, wait or close");
  }
  return step;
}

}  // namespace

std::vector<ScriptStep> parse_script(const std::string& text, const std::string& path) {
  std::vector<ScriptStep> steps;
  std::istringstream lines(text);
  int number = 0;
  for (std::string line; std::getline(lines, line);) {
    ++number;
    line = trimmed(line);
    if (line.empty() || line[0] == '#') continue;
    const std::string where = path + ":" + std::to_string(number) + ": ";
    const size_t colon = line.find(':');
    const std::vector<std::string> head =
        split_words(colon == std::string::npos ? "" : line.substr(0, colon));
    const std::optional<int> frame = head.size() == 2 ? whole_int(head[1]) : std::nullopt;
    if (head.size() != 2 || head[0] != "frame" || !frame || *frame < 1)
      throw InputError(where + "expected 'frame N: ACTION' with N >= 1");
    try {
      steps.push_back(parse_action(trimmed(line.substr(colon + 1))));
    } catch (const UsageError& e) {
      throw InputError(where + e.what());
    }
    steps.back().frame = *frame;
  }
  std::stable_sort(steps.begin(), steps.end(),
                   [](const ScriptStep& a, const ScriptStep& b) { return a.frame < b.frame; });
  return steps;
}

Script::Script(const ViewJob& job, std::vector<ScriptStep> steps)
    : job_(job), steps_(std::move(steps)) {}

bool Script::scripted() const { return job_.frames > 0 || !steps_.empty(); }

const ScriptStep* Script::next_due_step(const ViewState& state) {
  if (next_step_ == steps_.size() || steps_[next_step_].frame > frames_done_ + 1) return nullptr;
  const bool waiting = steps_[next_step_].action == ScriptStep::Action::wait;
  if (waiting && (!state.session.full_pass_current() || state.compare_pending)) return nullptr;
  return &steps_[next_step_++];
}

void Script::check_frame(const ProgressiveFrame& frame) const {
  if (!frame.error.empty() && job_.frames > 0)
    throw InputError("view: rendering failed: " + frame.error);
}

void Script::click(ViewState& state) {
  if (job_.frames == 0 || !job_.click || click_done_ || !state.session.full_pass_current()) return;
  const auto [fx, fy] = *job_.click;
  const ViewSetup& setup = state.session.setup();
  const int x = std::min(int(fx * setup.width), setup.width - 1);
  const int y = std::min(int(fy * setup.height), setup.height - 1);
  state.pick(x, y);
  click_done_ = true;
  click_frame_ = frames_done_;
  if (!job_.walk_out.empty()) write_walk(state.picked, job_.walk_out);
}

bool Script::frame_done(const ViewState& state, bool load_pending) {
  ++frames_done_;
  return job_.frames > 0 && frames_done_ >= job_.frames &&
         (state.session.full_pass_current() || !state.session.started()) &&
         next_step_ == steps_.size() && !load_pending && !state.compare_pending &&
         (!job_.click || (click_done_ && frames_done_ > click_frame_ + kFramesAfterClick));
}

}  // namespace gs::app
