// The assets folder (assets/README.md): where the tests and the bench look for real scenes,
// and scripts/fetch-assets.sh, which puts the scenes git does not hold there. The script is
// run with --from a temporary folder only (no downloads): it must install a file whose
// SHA-256 is right and refuse, naming it, one whose SHA-256 is wrong.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>

#include "bench/scenes.h"
#include "tests/test_util.h"

namespace gs {
namespace {

namespace fs = std::filesystem;

// The files the script fetches (assets/README.md's table, "fetched").
const std::vector<std::string> kFetched = {
    "bunny/stanford-bunny.obj", "dragon/dragon_vrip_res4.ply", "dragon/dragon_vrip_res3.ply",
    "dragon/dragon_vrip.ply.gz", "sibenik/sibenik.obj"};
// The smallest of them, used for the install and rejection cases.
const std::string kRes4 = "dragon/dragon_vrip_res4.ply";

// An empty folder of its own for each use.
fs::path fresh_dir(const std::string& name) {
  const fs::path dir = test::temp_path(name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

void write_bytes(const fs::path& path, const std::string& bytes) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << bytes;
}

// What is under `dir` but folders of scenes: its files, and the script's work folders
// (.fetch.*), which must not outlive it.
std::vector<fs::path> left_in(const fs::path& dir) {
  std::vector<fs::path> found;
  if (!fs::exists(dir)) return found;
  for (const auto& entry : fs::recursive_directory_iterator(dir))
    if (entry.is_regular_file() || entry.path().filename().string().starts_with(".fetch."))
      found.push_back(entry.path());
  return found;
}

// scripts/fetch-assets.sh ARGS with the assets folder set to `assets`.
test::CommandOutcome fetch(const fs::path& assets, const std::string& args) {
  return test::run_command("env GRIDSCOPE_ASSETS=" + test::quoted(assets.string()) + " sh " +
                           test::quoted(GRIDSCOPE_FETCH_ASSETS) + " " + args);
}

// The real file, or "" (the caller skips) when this checkout has not fetched it.
std::string real_res4() { return test::slurp(test::asset_file(kRes4)); }

TEST(FetchAssets, CopiesACorrectFileAndSkipsItWhenPresent) {
  const std::string real = real_res4();
  if (real.empty()) GTEST_SKIP() << test::missing_asset(kRes4);
  const fs::path from = fresh_dir("fetch-from"), assets = fresh_dir("fetch-good") / "assets";
  write_bytes(from / kRes4, real);

  const test::CommandOutcome first = fetch(assets, "--from " + test::quoted(from) + " " + kRes4);
  EXPECT_EQ(first.status, 0) << first.err;
  EXPECT_NE(first.out.find(kRes4 + ": installed"), std::string::npos) << first.out;
  EXPECT_EQ(test::slurp((assets / kRes4).string()), real);
  EXPECT_EQ(left_in(assets), std::vector<fs::path>{assets / kRes4});  // nothing left over

  fs::remove(from / kRes4);  // a second run must not need the source
  const test::CommandOutcome again = fetch(assets, "--from " + test::quoted(from) + " " + kRes4);
  EXPECT_EQ(again.status, 0) << again.err;
  EXPECT_NE(again.out.find(kRes4 + ": already present"), std::string::npos) << again.out;
  EXPECT_EQ(test::slurp((assets / kRes4).string()), real);
}

// A copy of the file with the wrong bytes: refused with exit status 1 and an error naming
// it, and not installed.
void expect_rejected(const std::string& bytes, const std::string& case_name) {
  const fs::path from = fresh_dir("fetch-from-" + case_name);
  const fs::path assets = fresh_dir("fetch-" + case_name) / "assets";
  write_bytes(from / kRes4, bytes);
  const test::CommandOutcome outcome = fetch(assets, "--from " + test::quoted(from) + " " + kRes4);
  EXPECT_EQ(outcome.status, 1) << case_name;
  EXPECT_NE(outcome.err.find(kRes4 + ": wrong or truncated file"), std::string::npos)
      << case_name << ": " << outcome.err;
  EXPECT_TRUE(left_in(assets).empty()) << case_name;
}

TEST(FetchAssets, RejectsAForeignFile) {
  expect_rejected("ply\nformat ascii 1.0\nelement vertex 0\nend_header\n", "foreign");
}

TEST(FetchAssets, RejectsACorruptedOrTruncatedCopy) {
  const std::string real = real_res4();
  if (real.empty()) GTEST_SKIP() << test::missing_asset(kRes4);
  std::string corrupted = real;
  corrupted[corrupted.size() / 2] ^= 1;  // one bit
  expect_rejected(corrupted, "corrupted");
  expect_rejected(real.substr(0, real.size() - 1), "truncated");
}

TEST(FetchAssets, AWrongInstalledFileIsRemovedWhenNoGoodCopyComes) {
  const fs::path from = fresh_dir("fetch-from-empty");
  const fs::path assets = fresh_dir("fetch-stale") / "assets";
  write_bytes(assets / kRes4, "a stale, wrong copy\n");
  const test::CommandOutcome outcome = fetch(assets, "--from " + test::quoted(from) + " " + kRes4);
  EXPECT_EQ(outcome.status, 1);
  EXPECT_NE(outcome.err.find((from / kRes4).string() + ": no such file"), std::string::npos)
      << outcome.err;
  EXPECT_TRUE(left_in(assets).empty());
}

TEST(FetchAssets, ListNamesEachFileItsSourceAndPlaceAndChangesNothing) {
  const fs::path assets = fresh_dir("fetch-list") / "assets";
  const test::CommandOutcome outcome = fetch(assets, "--list");
  EXPECT_EQ(outcome.status, 0) << outcome.err;
  for (const std::string& file : kFetched)
    EXPECT_NE(outcome.out.find(file + ": would download https://"), std::string::npos)
        << file << " in:\n"
        << outcome.out;
  EXPECT_EQ(outcome.out.find("f15/"), std::string::npos);  // in git: never fetched
  EXPECT_NE(outcome.out.find("to " + (assets / "sibenik/sibenik.obj").string()), std::string::npos);
  EXPECT_FALSE(fs::exists(assets));

  const fs::path from = fresh_dir("fetch-list-from");
  const test::CommandOutcome copy = fetch(assets, "--list --from " + test::quoted(from));
  EXPECT_NE(copy.out.find(kRes4 + ": would copy " + (from / kRes4).string()), std::string::npos)
      << copy.out;
}

TEST(FetchAssets, UsageErrorsExitWithStatus2) {
  const fs::path assets = fresh_dir("fetch-usage") / "assets";
  for (const std::string& args :
       {std::string("--bogus"), std::string("f15/f15.obj"),
        std::string("--from /nonexistent-folder"), std::string("--from")}) {
    const test::CommandOutcome outcome = fetch(assets, args);
    EXPECT_EQ(outcome.status, 2) << args;
    EXPECT_NE(outcome.err.find("usage: scripts/fetch-assets.sh"), std::string::npos) << args;
  }
  EXPECT_FALSE(fs::exists(assets));
}

// Sets an environment variable for one scope and puts the old value back.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    ::setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() {
    if (old_)
      ::setenv(name_, old_->c_str(), 1);
    else
      ::unsetenv(name_);
  }

 private:
  const char* name_;
  std::optional<std::string> old_;
};

// Runs in another current folder for one scope.
class ScopedCurrentDir {
 public:
  explicit ScopedCurrentDir(const fs::path& dir) : old_(fs::current_path()) {
    fs::current_path(dir);
  }
  ~ScopedCurrentDir() { fs::current_path(old_); }

 private:
  fs::path old_;
};

TEST(AssetLookup, TestsReadTheSourceTreeOrGridscopeAssets) {
  {
    ScopedEnv unset("GRIDSCOPE_ASSETS", "");  // empty counts as unset
    EXPECT_EQ(test::asset_file("f15/f15.obj"),
              (fs::path(GRIDSCOPE_SOURCE_ASSETS) / "f15/f15.obj").string());
  }
  const fs::path elsewhere = fresh_dir("assets-elsewhere");
  write_bytes(elsewhere / "f15/f15.obj", "v 0 0 0\n");
  ScopedEnv set("GRIDSCOPE_ASSETS", elsewhere.string());
  EXPECT_EQ(test::asset_file("f15/f15.obj"), (elsewhere / "f15/f15.obj").string());
  EXPECT_EQ(test::asset_file("spd/balls.nff"), "");  // it wins: no falling back
  const std::string why = test::missing_asset("spd/balls.nff");
  EXPECT_NE(why.find((elsewhere / "spd/balls.nff").string()), std::string::npos) << why;
  EXPECT_NE(why.find("scripts/fetch-assets.sh"), std::string::npos) << why;
}

TEST(AssetLookup, BenchReadsGridscopeAssetsElseAssetsInTheCurrentFolder) {
  const fs::path work = fresh_dir("bench-cwd");
  ScopedCurrentDir in(work);
  {
    ScopedEnv unset("GRIDSCOPE_ASSETS", "");
    EXPECT_EQ(find_assets_dir(), "");
    fs::create_directory(work / "assets");
    EXPECT_EQ(fs::path(find_assets_dir()), work / "assets");
  }
  ScopedEnv set("GRIDSCOPE_ASSETS", "/elsewhere/assets");
  EXPECT_EQ(find_assets_dir(), "/elsewhere/assets");
}

TEST(AssetLookup, BenchSceneFromTheAssetsFolder) {
  std::string why;
  const auto f15 = load_bench_scene("f15", GRIDSCOPE_SOURCE_ASSETS, why);
  ASSERT_TRUE(f15) << why;
  EXPECT_EQ(f15->scene->triangle_count(), 9288u + 2u);  // the F-15 and its ground square

  const fs::path empty = fresh_dir("bench-empty-assets");
  EXPECT_FALSE(load_bench_scene("dragon", empty.string(), why));
  EXPECT_NE(why.find((empty / "dragon/dragon_vrip_res3.ply").string() + " is missing"),
            std::string::npos)
      << why;
  EXPECT_NE(why.find("scripts/fetch-assets.sh"), std::string::npos) << why;
  EXPECT_FALSE(load_bench_scene("bunny-sibenik", "", why));
  EXPECT_NE(why.find("no assets folder"), std::string::npos) << why;
  EXPECT_NE(why.find("scripts/fetch-assets.sh"), std::string::npos) << why;
}

}  // namespace
}  // namespace gs
