// The `gridscope` command line (README "Usage"): parses a command and its flags into a job of
// the core library and runs it. Computes nothing of its own. The commands are one list (name,
// synopsis, paragraph, flags), from which the help text is generated.
#pragma once
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace gs::app {

// A parsed command line, ready to run: the command's job bound to its run function.
struct Command {
  // Returns the exit status of a run that did not throw. Throws UsageError and InputError.
  std::function<int()> run;
};

// Parses args (argv without the program name). Reads and writes nothing (but the calibration
// file of --costs), so a command line can be checked, and fuzzed, apart from running it.
// Throws UsageError (exit 2).
Command parse_cli(std::span<const std::string> args);

// parse_cli(args).run(): the exit status of a run that did not throw. Throws UsageError
// (exit 2) and InputError (exit 1).
int run_cli(std::span<const std::string> args);

// A command of the list ("trace", ..., "help", "--version") and every flag it takes, in the
// order help lists them.
struct CommandFlags {
  std::string command;
  std::vector<std::string> flags;
};
std::vector<CommandFlags> command_flags();

// `gridscope help`: every command. `gridscope COMMAND --help`: that command alone, with the
// structure flags it takes, which structures read them and their defaults. UsageError for an
// unknown command.
std::string help_text();
std::string command_help(const std::string& command);

}  // namespace gs::app
