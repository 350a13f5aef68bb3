// The libFuzzer executable of one entry of fuzz_entries.h: tests/fuzz/CMakeLists.txt compiles
// this file once per target with GRIDSCOPE_FUZZ_TARGET set to the target's name. A broken
// promise aborts, which libFuzzer reports as a crash, saving the input.
#include <cstdio>
#include <cstdlib>

#include "tests/fuzz/fuzz_entries.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const gs::fuzz::Entry entry = gs::fuzz::entry_named(GRIDSCOPE_FUZZ_TARGET);
  if (entry == nullptr) {
    std::fprintf(stderr, "no fuzz entry named '%s'\n", GRIDSCOPE_FUZZ_TARGET);
    std::abort();
  }
  const gs::fuzz::Outcome outcome = entry({data, size});
  for (const std::string& problem : outcome.problems)
    std::fprintf(stderr, "fuzz_%s: %s\n", GRIDSCOPE_FUZZ_TARGET, problem.c_str());
  if (!outcome.problems.empty()) std::abort();
  return 0;
}
