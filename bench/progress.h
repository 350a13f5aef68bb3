// The bench's progress report: one line with the steps done, the step just finished and an
// estimate of the time left, rewritten in place on a terminal and printed at every tenth of
// the run (or every half minute) in a log; with --verbose, one line per step instead.
#pragma once
#include <functional>
#include <optional>
#include <string>
#include <string_view>

namespace gs {

// One finished step of a bench run (bench.h's BenchOptions::progress): a measurement, a
// reference, a calibration, a convergence curve, or a skipped scene's planned steps at once.
struct BenchStep {
  int done = 0;          // steps finished, this one included
  int total = 0;         // steps the run plans (known before it begins)
  double elapsed = 0.0;  // seconds since the run began
  std::string scene;     // the step's scene label, or empty (calibration)
  std::string accel;     // its structure, or empty
  std::string line;      // what the step measured, in full (the --verbose log line)
};

// Seconds left, assuming the steps left take as long on average as those done:
// elapsed * (total - done) / done. Steps differ (a reference with brute takes longer than a
// sweep point), so it is rough early on and sharpens as steps finish. Nothing before the first
// step is done.
std::optional<double> eta_seconds(double elapsed, int done, int total);

// "12/57 steps (21%) | lumpy bvh | 1m02s elapsed | ETA 3m51s"
std::string progress_line(const BenchStep& step);

// Prints a run's progress through `write` (stderr in the app).
class BenchProgressPrinter {
 public:
  // In a log (not a terminal), a line is printed when the run passes another tenth of its
  // steps or this many seconds after the last one.
  static constexpr double kLogInterval = 30.0;

  // `terminal`: rewrite one line in place ('\r'); `verbose`: every step's line instead.
  BenchProgressPrinter(bool terminal, bool verbose, std::function<void(std::string_view)> write);

  void step(const BenchStep& step);
  // Ends the in-place line and says how many steps ran in how long.
  void finish();

 private:
  void print_log_line(const BenchStep& step);

  bool terminal_, verbose_;
  std::function<void(std::string_view)> write_;
  BenchStep last_;
  int last_tenth_ = 0;             // tenths of the run the log has reported
  double last_print_seconds_ = 0;  // when the log last printed
  bool line_open_ = false;         // an in-place line waits for its newline
};

}  // namespace gs
