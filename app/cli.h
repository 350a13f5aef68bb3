// The `gridscope` command line (DESIGN.md §3): parses a command and its flags into a job of
// the core library and runs it. Computes nothing of its own.
#pragma once
#include <functional>
#include <span>
#include <string>

namespace gs {
struct AccelParams;
}

namespace gs::app {

// A parsed command line, ready to run: the command's job bound to its run function.
struct Command {
  // Returns the exit status of a run that did not throw. Throws UsageError and InputError.
  std::function<int()> run;
};

// Parses args (argv without the program name). Reads and writes nothing, so a command line
// can be checked, and fuzzed, apart from running it. Throws UsageError (exit 2).
Command parse_cli(std::span<const std::string> args);

// parse_cli(args).run(): the exit status of a run that did not throw. Throws UsageError
// (exit 2) and InputError (exit 1).
int run_cli(std::span<const std::string> args);

// Sets one structure parameter from its flag and text (e.g. "--max-granularity", "8") as the
// command line does, for the viewer's panel and --script. UsageError for an unknown flag or
// a bad value.
void apply_structure_flag(AccelParams& params, const std::string& flag, const std::string& value);

}  // namespace gs::app
