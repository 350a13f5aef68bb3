// An array whose elements never move: address space for the largest size it may reach is
// reserved once (virtual memory, committed page by page as it is touched), so threads can
// read elements while another thread appends (docs/design.md §1.7: storage that grows
// while other threads read it must not move). std::vector reallocates; std::deque's index
// arithmetic costs an indirection on every read of the hot traversal arrays; hence our own.
#pragma once
#include <sys/mman.h>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <new>
#include <type_traits>
#include <utility>

namespace gs {

template <class T>
class StableArray {
 public:
  // The bytes at the start that take ordinary pages (reserve).
  static constexpr size_t kSmallPrefix = size_t{64} << 10;

  explicit StableArray(size_t max_bytes) { reserve(max_bytes); }
  ~StableArray() { release(); }
  // Drops every element and reserves `max_bytes` afresh. Only while no other thread reads
  // the array (an eager build sizing its storage before filling it).
  void reset(size_t max_bytes) {
    release();
    reserve(max_bytes);
  }
  StableArray(const StableArray&) = delete;
  StableArray& operator=(const StableArray&) = delete;
  // Exchanges two arrays' elements (their reservations): a structure taking over what
  // another one built. Only while no other thread reads either.
  void swap(StableArray& other) noexcept {
    std::swap(mapping_, other.mapping_);
    std::swap(mapped_bytes_, other.mapped_bytes_);
    std::swap(data_, other.data_);
    std::swap(capacity_, other.capacity_);
    const size_t size = size_.load(std::memory_order_relaxed);
    size_.store(other.size_.load(std::memory_order_relaxed), std::memory_order_relaxed);
    other.size_.store(size, std::memory_order_relaxed);
  }

  T& operator[](size_t i) { return data_[i]; }
  const T& operator[](size_t i) const { return data_[i]; }
  size_t size() const { return size_.load(std::memory_order_relaxed); }
  // Appends n value-initialised elements and returns the first one's index, or SIZE_MAX
  // when the reservation is full. Thread-safe: each caller gets its own contiguous range
  // and constructs it; publishing the contents to other threads is the caller's business.
  size_t append(size_t n) {
    size_t first = size_.load(std::memory_order_relaxed);
    do {
      if (n > capacity_ - first) return SIZE_MAX;
    } while (!size_.compare_exchange_weak(first, first + n, std::memory_order_relaxed));
    for (size_t i = 0; i < n; ++i) new (&data_[first + i]) T();
    return first;
  }
  // For an array kept parallel to another one (same indices): constructs elements
  // first .. first + n - 1, which the caller owns; false when they exceed the reservation.
  // size() does not count them.
  bool construct(size_t first, size_t n) {
    if (first > capacity_ || n > capacity_ - first) return false;
    for (size_t i = 0; i < n; ++i) new (&data_[first + i]) T();
    return true;
  }

 private:
  void reserve(size_t max_bytes) {
    static_assert(std::is_trivially_destructible_v<T>);
    capacity_ = max_bytes / sizeof(T);
    if (capacity_ == 0) return;
    // Huge pages where the system gives them on request (transparent huge pages in
    // "madvise" mode, Debian's default) past the first 64 KiB, from a huge-page boundary: a
    // structure of tens of megabytes is committed in tens of page faults instead of
    // thousands, which in a virtual machine cost more than the build itself. The first
    // 64 KiB take ordinary pages: a huge page is zeroed whole at its first write, and a
    // grid1d build (with its sampling pass's scout) starts some two dozen arrays, most of a
    // few kilobytes on a small scene (the pyramid's builds in the bench: 40 ms with huge
    // pages from the first byte, 4 ms with the prefix; docs/design.md §1.7).
    mapped_bytes_ = capacity_ * sizeof(T) + kHugePage;
    void* p = ::mmap(nullptr, mapped_bytes_, PROT_READ | PROT_WRITE,
                     MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
    if (p == MAP_FAILED) throw std::bad_alloc();
    mapping_ = p;
    const uintptr_t huge =
        (reinterpret_cast<uintptr_t>(p) + kSmallPrefix + kHugePage - 1) & ~(kHugePage - 1);
    data_ = reinterpret_cast<T*>(huge - kSmallPrefix);
    // Only advice: a refusal is ignored.
    const size_t bytes = capacity_ * sizeof(T);
    ::madvise(data_, std::min(bytes, kSmallPrefix), MADV_NOHUGEPAGE);
    if (bytes > kSmallPrefix)
      ::madvise(reinterpret_cast<void*>(huge), bytes - kSmallPrefix, MADV_HUGEPAGE);
  }
  void release() {
    if (mapping_) ::munmap(mapping_, mapped_bytes_);
    mapping_ = nullptr, data_ = nullptr, capacity_ = 0, mapped_bytes_ = 0;
    size_.store(0, std::memory_order_relaxed);
  }

  static constexpr uintptr_t kHugePage = uintptr_t{2} << 20;
  void* mapping_ = nullptr;
  size_t mapped_bytes_ = 0;
  T* data_ = nullptr;
  size_t capacity_ = 0;
  std::atomic<size_t> size_{0};
};

}  // namespace gs
