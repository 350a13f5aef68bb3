#include "app/bench_job.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>

#include "app/plot.h"
#include "bench/report.h"
#include "core/base/error.h"
#include "core/base/files.h"
#include "core/geometry/ray_io.h"
#include "core/trace/trace_job.h"

namespace gs::app {

namespace {

nlohmann::json read_results(const std::string& path) {
  const std::vector<char> bytes = read_file(path);
  nlohmann::json records = nlohmann::json::parse(bytes.begin(), bytes.end(), nullptr, false);
  if (!records.is_array()) fail_input(path, "is not a bench results.json (a JSON array)");
  return records;
}

}  // namespace

void run_bench_job(const BenchJob& job) {
  check_bench_options(job.options);
  std::error_code error;
  std::filesystem::create_directories(job.out_dir, error);
  if (error || !std::filesystem::is_directory(job.out_dir))
    fail_input(job.out_dir, "cannot create the output directory");
  BenchOptions options = job.options;
  options.image_dir = job.out_dir;
  BenchProgressPrinter printer(isatty(fileno(stderr)) != 0, job.verbose, [](std::string_view text) {
    std::fwrite(text.data(), 1, text.size(), stderr);
    std::fflush(stderr);
  });
  options.progress = [&printer](const BenchStep& step) { printer.step(step); };
  const std::string dir = job.out_dir + "/";
  nlohmann::json records;
  if (job.from_path.empty()) {
    records = run_bench(options);
    printer.finish();
    write_json(dir + "results.json", records);
  } else {
    records = read_results(job.from_path);
  }
  const std::vector<std::string> plots = write_bench_plots(records, job.out_dir);
  const std::string report = bench_report_markdown(records, plots);
  write_file(dir + "report.md", std::vector<char>(report.begin(), report.end()));
  std::printf("%sreport.md\n", dir.c_str());
}

}  // namespace gs::app
