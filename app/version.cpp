#include "app/version.h"

#include "app/build_version.h"  // generated at every build by app/version.cmake

namespace gs::app {

std::string version_text() {
  return std::string("gridscope ") + GRIDSCOPE_VERSION + " (commit " + GRIDSCOPE_COMMIT + ")";
}

}  // namespace gs::app
