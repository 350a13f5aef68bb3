// What `gridscope --version` prints: the project's version (CMake's project VERSION) and the
// git commit the binary was built from, captured at every build (app/version.cmake).
#pragma once
#include <string>

namespace gs::app {

// "gridscope 0.9.0 (commit 40-HEX-DIGITS)", or "(commit unknown)" outside a git checkout.
std::string version_text();

}  // namespace gs::app
