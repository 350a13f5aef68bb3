#include "core/base/error.h"

namespace gs {

void fail_input(const std::string& file, const std::string& problem) {
  throw InputError(file + ": " + problem);
}

}  // namespace gs
