#include "bench/progress.h"

#include <cstdio>

namespace gs {

namespace {

// "42s", "3m07s", "2h05m".
std::string duration(double seconds) {
  const auto s = static_cast<long long>(seconds + 0.5);
  char text[32];
  if (s < 60)
    std::snprintf(text, sizeof text, "%llds", s);
  else if (s < 3600)
    std::snprintf(text, sizeof text, "%lldm%02llds", s / 60, s % 60);
  else
    std::snprintf(text, sizeof text, "%lldh%02lldm", s / 3600, s % 3600 / 60);
  return text;
}

}  // namespace

std::optional<double> eta_seconds(double elapsed, int done, int total) {
  if (done <= 0) return std::nullopt;
  return done >= total ? 0.0 : elapsed * double(total - done) / double(done);
}

std::string progress_line(const BenchStep& step) {
  const int percent = step.total > 0 ? 100 * step.done / step.total : 100;
  std::string line = std::to_string(step.done) + "/" + std::to_string(step.total) + " steps (" +
                     std::to_string(percent) + "%)";
  std::string what = step.scene;
  if (!step.accel.empty()) what += (what.empty() ? "" : " ") + step.accel;
  if (!what.empty()) line += " | " + what;
  line += " | " + duration(step.elapsed) + " elapsed";
  if (const std::optional<double> eta = eta_seconds(step.elapsed, step.done, step.total))
    line += " | ETA " + duration(*eta);
  return line;
}

BenchProgressPrinter::BenchProgressPrinter(bool terminal, bool verbose,
                                           std::function<void(std::string_view)> write)
    : terminal_(terminal), verbose_(verbose), write_(std::move(write)) {}

void BenchProgressPrinter::step(const BenchStep& step) {
  last_ = step;
  if (verbose_) {
    write_("bench: " + step.line + "\n");
  } else if (terminal_) {
    // Clear to the end of the line: the new line may be shorter than the old.
    write_("\rbench: " + progress_line(step) + "\033[K");
    line_open_ = true;
  } else {
    print_log_line(step);
  }
}

void BenchProgressPrinter::print_log_line(const BenchStep& step) {
  const int tenth = step.total > 0 ? 10 * step.done / step.total : 10;
  if (tenth <= last_tenth_ && step.elapsed - last_print_seconds_ < kLogInterval) return;
  last_tenth_ = tenth;
  last_print_seconds_ = step.elapsed;
  write_("bench: " + progress_line(step) + "\n");
}

void BenchProgressPrinter::finish() {
  if (line_open_) write_("\n");
  line_open_ = false;
  write_("bench: " + std::to_string(last_.done) + " of " + std::to_string(last_.total) +
         " steps in " + duration(last_.elapsed) + "\n");
}

}  // namespace gs
