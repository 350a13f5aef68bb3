#include "core/geometry/ray_io.h"

#include <bit>
#include <cstring>

#include "core/base/error.h"
#include "core/base/files.h"

namespace gs {

// The records are copied to and from memory as they are; that is the file format only on a
// little-endian machine, which every platform gridscope targets is.
static_assert(std::endian::native == std::endian::little);

namespace {

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

std::vector<Ray> read_rays(const std::string& path) { return read_records<Ray>(path); }

void write_rays(const std::string& path, std::span<const Ray> rays) {
  write_records<Ray>(path, rays);
}

std::vector<Hit> read_hits(const std::string& path) { return read_records<Hit>(path); }

void write_hits(const std::string& path, std::span<const Hit> hits) {
  write_records<Hit>(path, hits);
}

}  // namespace gs
