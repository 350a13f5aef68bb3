// Small lock-free helpers for figures that several building threads update.
#pragma once
#include <atomic>
#include <cstdint>

namespace gs {

// Raises `target` to at least `value`.
inline void raise_to(std::atomic<uint64_t>& target, uint64_t value) {
  uint64_t seen = target.load(std::memory_order_relaxed);
  while (seen < value && !target.compare_exchange_weak(seen, value, std::memory_order_relaxed)) {
  }
}

}  // namespace gs
