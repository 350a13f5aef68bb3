#include "core/base/files.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

#include "core/base/error.h"

namespace gs {
namespace {

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

std::string errno_text() { return std::strerror(errno); }

}  // namespace

// The whole file in one read when its size is known (a regular file); pipes and other
// streams are read in growing chunks. One byte more than the size is asked for, so a file
// that grew since fstat is still read to its end.
std::vector<char> read_file(const std::string& path) {
  File file(std::fopen(path.c_str(), "rb"));
  if (!file) fail_input(path, "cannot open (" + errno_text() + ")");
  struct stat info {};
  const bool sized = ::fstat(::fileno(file.get()), &info) == 0 && S_ISREG(info.st_mode);
  size_t want = sized ? size_t(info.st_size) + 1 : size_t{1} << 16;
  std::vector<char> data;
  size_t used = 0;
  for (;;) {
    data.resize(used + want);
    const size_t got = std::fread(data.data() + used, 1, want, file.get());
    used += got;
    if (got < want) break;
    want = used;
  }
  if (std::ferror(file.get())) fail_input(path, "cannot read (" + errno_text() + ")");
  data.resize(used);
  return data;
}

// fclose is checked too: buffered data reaches the disk (and can fail) only there.
void write_file(const std::string& path, std::span<const char> bytes) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (!file) fail_input(path, "cannot open for writing (" + errno_text() + ")");
  std::string problem;
  if (!bytes.empty() && std::fwrite(bytes.data(), 1, bytes.size(), file) != bytes.size())
    problem = errno_text();
  if (std::fclose(file) != 0 && problem.empty()) problem = errno_text();
  if (!problem.empty()) fail_input(path, "cannot write (" + problem + ")");
}

void write_json(const std::string& path, const nlohmann::json& json) {
  // Paths in the record need not be UTF-8; replace what is not instead of failing.
  const std::string text =
      json.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
  write_file(path, text);
}

}  // namespace gs
