#include "tests/test_util.h"

#include <filesystem>
#include <unistd.h>

namespace gs::test {

std::string shared_file(const std::string& relative) {
  const std::filesystem::path path = std::filesystem::path(GRIDSCOPE_SHARED_DIR) / relative;
  return std::filesystem::exists(path) ? path.string() : std::string();
}

std::string temp_path(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("gridscope-test-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

}  // namespace gs::test
