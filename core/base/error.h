// Errors that reach the user as one line and an exit status (docs/design.md §3).
#pragma once
#include <stdexcept>
#include <string>

namespace gs {

// Bad input or a failed run: unreadable/malformed file, unwritable output. Exit status 1.
// The message already names the file or resource: "FILE: what is wrong".
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A usage error: unknown command, flag, structure name, malformed option value. Exit status 2.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// "FILE: problem" in one place so every loader words it the same way.
[[noreturn]] void fail_input(const std::string& file, const std::string& problem);

}  // namespace gs
