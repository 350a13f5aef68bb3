// Invariant checks that debug and sanitizer builds make and release builds compile away:
// GRIDSCOPE_CHECK(condition) prints the condition with its file and line and aborts when it
// is false. For what the code itself guarantees (an index in range, a published record);
// bad input is reported with InputError or UsageError instead (core/base/error.h).
#pragma once

namespace gs {
[[noreturn]] void check_failed(const char* condition, const char* file, int line);
}  // namespace gs

#ifdef NDEBUG
#define GRIDSCOPE_CHECK(condition) static_cast<void>(0)
#else
#define GRIDSCOPE_CHECK(condition) \
  ((condition) ? static_cast<void>(0) : ::gs::check_failed(#condition, __FILE__, __LINE__))
#endif
