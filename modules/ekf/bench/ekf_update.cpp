// The EKF backend's sparse update against MRPT's own on one rawlog (docs/PERFORMANCE.md "EKF
// update"): two EkfBackends, [EkfSLAM] update = sparse and = mrpt, take every step side by side
// in one process. Prints the CPU time each spent in its steps, their ratio, and the largest
// difference of their means and covariances over the steps compared.
//
//   bench_ekf_update -i RAWLOG [-c INI] [--max-steps N] [--every K] [--only sparse|mrpt]
//
// Options: INI (default: none), then the rawlog's sidecar ini, as a run reads them. --every K
// compares after every K-th step (default 1; a comparison reads both n x n covariances).
// --only runs one of the two (for a profiler): no comparison.
#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cstdio>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "budget_slam/core/Text.h"
#include "budget_slam/dataset/RawlogReader.h"
#include "budget_slam/dataset/SidecarIni.h"
#include "budget_slam/ekf/EkfBackend.h"

using namespace budget_slam;
namespace fs = std::filesystem;

namespace {

struct Args {
  std::string rawlog, ini, only;
  std::size_t max_steps = 0;  ///< 0: every step
  std::size_t every = 1;
};

[[noreturn]] void usage(const std::string& why) {
  std::cerr << "bench_ekf_update: " << why
            << "\nusage: bench_ekf_update -i RAWLOG [-c INI] [--max-steps N] [--every K] "
               "[--only sparse|mrpt]\n";
  std::exit(2);
}

Args parse(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string k = argv[i];
    if (i + 1 >= argc) usage(k + " needs a value");
    const std::string v = argv[++i];
    if (k == "-i")
      a.rawlog = v;
    else if (k == "-c")
      a.ini = v;
    else if (k == "--max-steps")
      a.max_steps = std::stoul(v);
    else if (k == "--every")
      a.every = std::max<std::size_t>(1, std::stoul(v));
    else if (k == "--only" && (v == "sparse" || v == "mrpt"))
      a.only = v;
    else
      usage("unknown argument " + k + " " + v);
  }
  if (a.rawlog.empty()) usage("-i RAWLOG is required");
  return a;
}

/// Copies every key of the ini file at `path` (when it exists) into `ini`.
void overlay(mrpt::config::CConfigFileMemory& ini, const std::string& path) {
  if (path.empty() || !fs::exists(path)) return;
  mrpt::config::CConfigFile f(path);
  std::vector<std::string> sections;
  f.getAllSections(sections);
  for (const auto& s : sections) {
    std::vector<std::string> keys;
    f.getAllKeys(s, keys);
    for (const auto& k : keys) ini.write(s, k, f.read_string(s, k, ""));
  }
}

double threadCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

struct Filter {
  std::string update;
  std::unique_ptr<ekf::EkfBackend> backend;
  double cpu_s = 0;
};

}  // namespace

int main(int argc, char** argv) {
  try {
    const Args args = parse(argc, argv);
    std::vector<Filter> filters;
    for (const std::string update : {"sparse", "mrpt"}) {
      if (!args.only.empty() && args.only != update) continue;
      mrpt::config::CConfigFileMemory ini;
      overlay(ini, args.ini);
      overlay(ini, dataset::sidecarIniPathFor(args.rawlog));
      ini.write("EkfSLAM", "update", update);
      filters.push_back({update, std::make_unique<ekf::EkfBackend>(ini), 0});
      filters.back().backend->setKeepTrajectory(false);
    }
    double gap_mean = 0, gap_cov = 0;
    std::size_t steps = 0, compared = 0;
    dataset::RawlogReader reader(args.rawlog);
    while (auto s = reader.next()) {
      if (args.max_steps && steps >= args.max_steps) break;
      for (auto& f : filters) {
        const double t0 = threadCpuSeconds();
        f.backend->process(*s);
        f.cpu_s += threadCpuSeconds() - t0;
      }
      ++steps;
      if (filters.size() == 2 && steps % args.every == 0) {
        const auto& a = filters[0].backend->filter();
        const auto& b = filters[1].backend->filter();
        if (a.mean().size() != b.mean().size()) {
          std::cerr << "bench_ekf_update: the state sizes differ after step " << s->index << "\n";
          return 1;
        }
        gap_mean =
            std::max(gap_mean, (a.mean().asEigen() - b.mean().asEigen()).cwiseAbs().maxCoeff());
        gap_cov = std::max(
            gap_cov, (a.covariance().asEigen() - b.covariance().asEigen()).cwiseAbs().maxCoeff());
        ++compared;
      }
    }
    const auto& first = *filters.front().backend;
    std::printf("%s: %zu steps, %zu landmarks at the end (state of %zu)\n", args.rawlog.c_str(),
                steps, first.landmarkCount(), 3 + 2 * first.landmarkCount());
    for (const auto& f : filters)
      std::printf("update %-6s: %.3f s CPU in its steps (%s)\n", f.update.c_str(), f.cpu_s,
                  f.backend->filter().usesSparseUpdate() ? "sparse iteration" : "MRPT's iteration");
    if (filters.size() == 2) {
      std::printf("mrpt / sparse CPU: %.2f\n", filters[1].cpu_s / filters[0].cpu_s);
      std::printf("largest |sparse - mrpt| over %zu compared steps: mean %.3g, covariance %.3g\n",
                  compared, gap_mean, gap_cov);
    }
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "bench_ekf_update: " << failureLine(e) << "\n";
    return 1;
  }
}
