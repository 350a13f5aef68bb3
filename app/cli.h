// The `gridscope` command line (DESIGN.md §3): parses a command and its flags into a job of
// the core library and runs it. Computes nothing of its own.
#pragma once
#include <span>
#include <string>

namespace gs::app {

// Runs the command in args (argv without the program name) and returns the exit status for
// a run that did not throw. Throws UsageError (exit 2) and InputError (exit 1).
int run_cli(std::span<const std::string> args);

}  // namespace gs::app
