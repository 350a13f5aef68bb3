// Helpers shared by the test suites: the shared-scenes folder, temporary files, ray sets.
#pragma once
#include <string>
#include <vector>

#include "core/ray.h"
#include "core/scene.h"

namespace gs::test {

// Path of a file under ../shared, or "" when ../shared is absent (callers GTEST_SKIP).
std::string shared_file(const std::string& relative);
// A fresh path under the system temp folder; the file is not created.
std::string temp_path(const std::string& name);

}  // namespace gs::test
