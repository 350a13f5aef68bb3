#include "core/base/error.h"

#include <cstdio>
#include <cstdlib>

#include "core/base/check.h"

namespace gs {

void fail_input(const std::string& file, const std::string& problem) {
  throw InputError(file + ": " + problem);
}

void check_failed(const char* condition, const char* file, int line) {
  std::fprintf(stderr, "%s:%d: invariant broken: %s\n", file, line, condition);
  std::abort();
}

}  // namespace gs
