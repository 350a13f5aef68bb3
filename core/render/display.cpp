#include "core/render/display.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <glm/common.hpp>
#include <glm/exponential.hpp>
#include <vector>

namespace gs {

namespace {

// What a linear value's byte is by definition: the path every pixel of a multi-sample image
// takes (its samples' display colours are summed before the byte is taken).
uint8_t byte_by_powf(float linear) {
  return display_byte(std::pow(std::min(linear, 1.0f), 1.0f / 2.2f));
}

// The bytes' steps and, to find a value's step in one or two comparisons, the byte of the
// first float of each bucket of 2^15 consecutive bit patterns from step 1's up to 1.0
// (non-negative floats order as their bits do). The byte rises by at most 80 (255 · ln 2 /
// 2.2) per doubling of the value, which spans 2^23 patterns: a bucket holds one step at most.
struct Table {
  static constexpr int kBucketBits = 15;
  std::array<float, 256> steps{};  // entry k: the first float of [0, 1] whose byte is >= k
  uint32_t first_bits = 0;         // step 1's bit pattern
  std::vector<uint8_t> bucket_bytes;

  Table() {
    // Bisection of the bit patterns for each step. The bytes rise with the value wherever
    // powf's rounding could make them stray, as tests/test_render.cpp checks float by float
    // around every step (docs/design.md §6.10).
    for (int k = 1; k < 256; ++k) {
      uint32_t lo = 0, hi = std::bit_cast<uint32_t>(1.0f);  // byte(lo) < k <= byte(hi)
      while (hi - lo > 1) {
        const uint32_t mid = lo + (hi - lo) / 2;
        (byte_by_powf(std::bit_cast<float>(mid)) >= k ? hi : lo) = mid;
      }
      steps[size_t(k)] = std::bit_cast<float>(hi);
    }
    first_bits = std::bit_cast<uint32_t>(steps[1]);
    const uint32_t buckets = ((std::bit_cast<uint32_t>(1.0f) - first_bits) >> kBucketBits) + 1;
    bucket_bytes.resize(buckets);
    int k = 1;
    for (uint32_t b = 0; b < buckets; ++b) {
      const float start = std::bit_cast<float>(first_bits + (b << kBucketBits));
      while (k < 255 && steps[size_t(k + 1)] <= start) ++k;
      bucket_bytes[b] = uint8_t(k);
    }
  }

  // The byte of a value in (0, 1]: the number of steps at or below it.
  uint8_t byte(float linear) const {
    const uint32_t bits = std::bit_cast<uint32_t>(linear);
    if (bits < first_bits) return 0;
    int k = bucket_bytes[(bits - first_bits) >> kBucketBits];
    while (k < 255 && steps[size_t(k + 1)] <= linear) ++k;
    return uint8_t(k);
  }
};

const Table& table() {
  static const Table built;
  return built;
}

// A linear value's byte by the table where it applies. pow(1, y) is 1: every value from 1 up
// is byte 255. Zero, negative values and NaN take the definition's path.
uint8_t table_byte(const Table& table, float linear) {
  if (linear > 1.0f) return 255;
  if (!(linear > 0.0f)) return byte_by_powf(linear);
  return table.byte(linear);
}

}  // namespace

glm::vec3 display_colour(const glm::vec3& linear) {
  return glm::pow(glm::min(linear, 1.0f), glm::vec3(1.0f / 2.2f));
}

uint8_t display_byte(float display) {
  return uint8_t(std::clamp(display, 0.0f, 1.0f) * 255.0f + 0.5f);
}

std::array<uint8_t, 3> display_bytes(const glm::vec3& display) {
  return {display_byte(display.x), display_byte(display.y), display_byte(display.z)};
}

const std::array<float, 256>& linear_byte_steps() { return table().steps; }

uint8_t linear_byte(float linear) { return table_byte(table(), linear); }

std::array<uint8_t, 3> linear_bytes(const glm::vec3& linear) {
  const Table& bytes = table();
  return {table_byte(bytes, linear.x), table_byte(bytes, linear.y), table_byte(bytes, linear.z)};
}

}  // namespace gs
