// Ray and hit files (docs/design.md §3): flat arrays of little-endian records, no header.
// Ray: 32 bytes, float32 ox oy oz tmin dx dy dz tmax. Hit: 16 bytes, int32 id, float32 t u v.
#pragma once
#include <span>
#include <string>
#include <vector>

#include "core/geometry/ray.h"

namespace gs {

// An empty file holds zero rays. Throws InputError ("PATH: problem") when the file cannot be
// read or its size is not a multiple of 32 bytes.
std::vector<Ray> read_rays(const std::string& path);
// Throws InputError when the file cannot be written completely.
void write_rays(const std::string& path, std::span<const Ray> rays);

// Same contract as read_rays with 16-byte records.
std::vector<Hit> read_hits(const std::string& path);
void write_hits(const std::string& path, std::span<const Hit> hits);

}  // namespace gs
