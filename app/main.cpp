// Maps the outcome of a command to the exit status and the one stderr line README "Usage"
// promises: 0 success, 1 bad input or a failed run, 2 a usage error. Nothing escapes main.
#include <algorithm>
#include <cstdio>
#include <exception>
#include <new>
#include <string>
#include <vector>

#include "app/cli.h"
#include "core/base/error.h"

namespace {

// One line even when a file name holds a line break.
int report(const std::string& message, int status) {
  std::string line = message;
  std::replace_if(
      line.begin(), line.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
  std::fprintf(stderr, "gridscope: %s\n", line.c_str());
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  try {
    const int status = gs::app::run_cli(args);
    // A full disk or closed pipe on stdout must not pass for success.
    if (std::fflush(stdout) != 0) return report("stdout: cannot write", 1);
    return status;
  } catch (const gs::UsageError& e) {
    return report(e.what(), 2);
  } catch (const gs::InputError& e) {
    return report(e.what(), 1);
  } catch (const std::bad_alloc&) {
    return report("out of memory", 1);
  } catch (const std::exception& e) {
    return report(std::string("error: ") + e.what(), 1);
  } catch (...) {
    return report("unknown error", 1);
  }
}
