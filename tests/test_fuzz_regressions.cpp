// Replays every seed of tests/fuzz/corpus/NAME/ and every finding kept in
// tests/fuzz/regressions/NAME/ through fuzz target NAME's own entry (tests/fuzz/fuzz_entries.h),
// so the ordinary test run (any compiler, no libFuzzer) checks them all: each input must keep
// every promise the entry checks (loaders load or name the file in an InputError, records
// round-trip, parse_cli returns or throws a usage error, structures answer as brute force).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "tests/fuzz/fuzz_entries.h"
#include "tests/test_util.h"

namespace gs::fuzz {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> files_in(const fs::path& folder) {
  std::vector<fs::path> files;
  if (!fs::is_directory(folder)) return files;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder))
    if (entry.is_regular_file()) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

struct Replay {
  size_t files = 0, accepted = 0, checks = 0;
};

Replay replay(const Target& target, const std::string& collection) {
  Replay totals;
  for (const fs::path& file : files_in(fs::path(GRIDSCOPE_FUZZ_DIR) / collection / target.name)) {
    const std::string bytes = test::slurp(file.string());
    const Outcome outcome =
        target.entry({reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()});
    for (const std::string& problem : outcome.problems) ADD_FAILURE() << file << ": " << problem;
    ++totals.files;
    totals.accepted += outcome.accepted ? 1 : 0;
    totals.checks += outcome.checks;
  }
  return totals;
}

class FuzzReplay : public testing::TestWithParam<Target> {};

// The seeds keep every promise, and they cover what a fuzzer needs to start from: valid input
// whose answers get checked and, where input can be invalid, input that is rejected.
TEST_P(FuzzReplay, CorpusKeepsEveryPromise) {
  const Target& target = GetParam();
  const Replay totals = replay(target, "corpus");
  EXPECT_GT(totals.files, 0u) << "no seeds in tests/fuzz/corpus/" << target.name;
  EXPECT_GT(totals.accepted, 0u) << "no seed is valid input";
  EXPECT_GT(totals.checks, 0u) << "no answer was checked";
  if (std::string(target.name) != "differential") {  // any bytes describe a differential case
    EXPECT_LT(totals.accepted, totals.files) << "no seed is rejected";
  }
}

// Every input a fuzzer ever broke a promise with stays fixed (the folder may be empty).
TEST_P(FuzzReplay, FindingsStayFixed) { replay(GetParam(), "regressions"); }

INSTANTIATE_TEST_SUITE_P(Targets, FuzzReplay, testing::ValuesIn(targets().begin(), targets().end()),
                         [](const testing::TestParamInfo<Target>& info) {
                           return std::string(info.param.name);
                         });

}  // namespace
}  // namespace gs::fuzz
