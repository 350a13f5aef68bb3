#include "core/geometry/ray_io.h"

#include <sys/stat.h>

#include <bit>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

#include "core/base/error.h"

namespace gs {

// The records are copied to and from memory as they are; that is the file format only on a
// little-endian machine, which every platform gridscope targets is.
static_assert(std::endian::native == std::endian::little);

namespace {

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

std::string errno_text() { return std::strerror(errno); }

template <class Record>
std::vector<Record> read_records(const std::string& path) {
  const std::vector<char> data = read_file(path);
  if (data.size() % sizeof(Record) != 0)
    fail_input(path, "size " + std::to_string(data.size()) + " is not a multiple of " +
                         std::to_string(sizeof(Record)) + " bytes");
  std::vector<Record> records(data.size() / sizeof(Record));
  if (!data.empty()) std::memcpy(records.data(), data.data(), data.size());
  return records;
}

template <class Record>
void write_records(const std::string& path, std::span<const Record> records) {
  write_file(path, {reinterpret_cast<const char*>(records.data()), records.size_bytes()});
}

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

std::vector<Ray> read_rays(const std::string& path) { return read_records<Ray>(path); }

void write_rays(const std::string& path, std::span<const Ray> rays) {
  write_records<Ray>(path, rays);
}

std::vector<Hit> read_hits(const std::string& path) { return read_records<Hit>(path); }

void write_hits(const std::string& path, std::span<const Hit> hits) {
  write_records<Hit>(path, hits);
}

}  // namespace gs
