// Waking up place by place (docs/RESULTS.md "Waking up on a saved map"): from a start at each place
// a traversal visits, a fresh GlobalLocalizer gets the traversal's next steps, up to [WakeUp]
// max_steps, and is found (within 0.25 m and 5 deg of the truth brought into the map's frame),
// found at a wrong pose, ambiguous or not found. Prints the shares and the time to be found.
//
//   bench_wakeup_places --map RUN_DIR -i TRAVERSAL.rawlog [-c INI] [--reference TUM]
//                       [--place-size M] [--sectors N] [--found-xy M] [--found-yaw-deg D]
//                       [--csv FILE] [--set WakeUp.key=value ...]
//
// RUN_DIR is a `budget-slam run` output folder (landmarks.csv, and summary.json's
// ground_truth.map_alignment, which brings the traversal's ground truth into the map's frame).
// Without ground truth, --reference gives the poses to compare with, in the map's frame, matched
// to the traversal's steps by timestamp (the trajectory.tum of a run that mapped the traversal
// from the map's own start, e.g. the whole rawlog the map is the first part of).
// The reading noise is [RangeBearingKFSLAM] std_sensor_range / std_sensor_yaw_deg from INI, then
// the traversal's sidecar ini. A place is a cell of --place-size metres (default 2) and one of
// --sectors heading sectors (default 8) of the true pose; its start is the first step there. A pose
// is right within --found-xy metres and --found-yaw-deg degrees (default 0.25, 5).
// A place is in the mapped area when it lies within the traversal's sensor range of a cell the
// mapping run's path (RUN_DIR/trajectory.tum) passed through, on a grid of --place-size metres:
// localize's rule for the steps it scores (metrics::MappedArea, docs/OUTPUTS.md "What is scored").
// Every place is tried and reported; the shares are printed again for the mapped area's places.
// With true landmark positions (the traversal's ground truth), a found pose is also judged against
// where the map itself puts the truth: the kept landmarks within twice the sensor's range fitted
// from their true places onto their map means, that local motion applied to the true pose
// (columns error_on_map_xy, error_on_map_yaw_deg): the wake-up's error apart from the map's own.
#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <tuple>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/Pose2.h"
#include "budget_slam/core/Text.h"
#include "budget_slam/dataset/GroundTruth.h"
#include "budget_slam/dataset/RawlogReader.h"
#include "budget_slam/dataset/SidecarIni.h"
#include "budget_slam/metrics/GroundTruthErrors.h"
#include "budget_slam/metrics/MapAlignment.h"
#include "budget_slam/metrics/MappedArea.h"
#include "budget_slam/report/RunFileReaders.h"
#include "budget_slam/wakeup/GlobalLocalizer.h"
#include "budget_slam/wakeup/PoseFit.h"

using namespace budget_slam;
namespace fs = std::filesystem;

namespace {

struct Args {
  std::string map, rawlog, ini, csv, reference;
  double place_size = 2.0, found_xy = 0.25, found_yaw_deg = 5.0;
  int sectors = 8;
  std::vector<std::pair<std::string, std::string>> sets;  ///< (Section.key, value)
};

Args parse(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string f = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw UsageError(f + ": needs a value");
      return argv[++i];
    };
    if (f == "--map")
      a.map = value();
    else if (f == "-i")
      a.rawlog = value();
    else if (f == "-c")
      a.ini = value();
    else if (f == "--csv")
      a.csv = value();
    else if (f == "--reference")
      a.reference = value();
    else if (f == "--place-size")
      a.place_size = std::stod(value());
    else if (f == "--sectors")
      a.sectors = std::stoi(value());
    else if (f == "--found-xy")
      a.found_xy = std::stod(value());
    else if (f == "--found-yaw-deg")
      a.found_yaw_deg = std::stod(value());
    else if (f == "--set") {
      const std::string s = value();
      const auto eq = s.find('=');
      if (eq == std::string::npos) throw UsageError("--set " + s + ": expected Section.key=value");
      a.sets.emplace_back(s.substr(0, eq), s.substr(eq + 1));
    } else {
      throw UsageError("unknown argument '" + f + "'");
    }
  }
  if (a.map.empty() || a.rawlog.empty()) throw UsageError("--map RUN_DIR and -i RAWLOG are needed");
  if (!(a.place_size > 0) || a.sectors < 1) throw UsageError("--place-size > 0, --sectors >= 1");
  return a;
}

/// summary.json's ground_truth.map_alignment of the mapping run.
metrics::MapAlignment alignmentOf(const std::string& dir) {
  std::ifstream in(fs::path(dir) / "summary.json");
  if (!in) throw InputError(dir + "/summary.json: cannot open");
  const auto j = nlohmann::json::parse(in);
  const auto& a = j.at("ground_truth").at("map_alignment");
  return metrics::MapAlignment::fromPose(a.at("x").get<double>(), a.at("y").get<double>(),
                                         a.at("yaw").get<double>(), "summary.json", 0);
}

double median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(p * static_cast<double>(v.size())))];
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Args args = parse(argc, argv);
    // Options: -c, then the traversal's sidecar, then --set.
    mrpt::config::CConfigFileMemory ini;
    const auto overlay = [&](const std::string& file) {
      if (file.empty() || !fs::exists(file)) return;
      mrpt::config::CConfigFile f(file);
      std::vector<std::string> sections;
      f.getAllSections(sections);
      for (const auto& s : sections) {
        std::vector<std::string> keys;
        f.getAllKeys(s, keys);
        for (const auto& k : keys) ini.write(s, k, f.read_string(s, k, ""));
      }
    };
    overlay(args.ini);
    overlay(dataset::sidecarIniPathFor(args.rawlog));
    for (const auto& [key, v] : args.sets)
      ini.write(key.substr(0, key.find('.')), key.substr(key.find('.') + 1), v);
    wakeup::WakeUpOptions options;
    options.loadFromConfigFile(ini, wakeup::WakeUpOptions::kSection);
    wakeup::ReadingNoise noise;
    noise.std_range = ini.read_double("RangeBearingKFSLAM", "std_sensor_range", 0.1);
    noise.std_bearing =
        ini.read_double("RangeBearingKFSLAM", "std_sensor_yaw_deg", 0.5) * M_PI / 180;

    const auto map =
        report::readLandmarksCsv((fs::path(args.map) / "landmarks.csv").string(), 100000);
    const auto steps = dataset::readAllSteps(args.rawlog);
    std::function<Pose2(StepIndex)> trueAt;
    std::map<double, Pose2> by_time;
    dataset::GroundTruth truth;
    metrics::MapAlignment alignment;
    if (!args.reference.empty()) {
      for (const auto& p : report::readTrajectoryTum(args.reference, 10000000))
        by_time[p.t] = p.pose;
      trueAt = [&](StepIndex s) {
        const auto it = by_time.lower_bound(steps.at(s).t - 1e-6);
        if (it == by_time.end() || std::abs(it->first - steps[s].t) > 1e-6)
          throw InputError(args.reference + ": no pose at t = " + std::to_string(steps[s].t));
        return it->second;
      };
    } else {
      alignment = alignmentOf(args.map);
      truth = dataset::loadGroundTruth(args.rawlog);
      if (truth.path.empty()) throw InputError(args.rawlog + ": no ground-truth path");
      trueAt = [&](StepIndex s) {
        const auto row = metrics::groundTruthRow(s, truth.path.size(), steps.size());
        return alignment.apply(truth.path.at(row));
      };
    }

    // The mapped area: the mapping run's path, the traversal's sensor range.
    metrics::MappedArea area;
    double reach = 0;
    const fs::path tum = fs::path(args.map) / "trajectory.tum";
    if (fs::exists(tum)) {
      std::vector<Pose2> mapping_path;
      for (const auto& p : report::readTrajectoryTum(tum.string(), 10000000))
        mapping_path.push_back(p.pose);
      const auto scan =
          std::find_if(steps.begin(), steps.end(), [](const Step& st) { return st.scan; });
      reach = scan != steps.end() ? scan->scan->max_range : 0.0;
      if (mapping_path.size() >= 2)
        area = metrics::MappedArea(mapping_path, args.place_size, reach);
    }

    // Places: the first step at each (cell, heading sector) of the true path.
    std::set<std::tuple<long, long, int>> seen;
    std::vector<StepIndex> starts;
    for (const auto& s : steps) {
      const auto p = trueAt(s.index);
      const double sector = std::floor((wrapAngle(p.phi) + M_PI) / (2 * M_PI) * args.sectors);
      const auto key = std::make_tuple(static_cast<long>(std::floor(p.x / args.place_size)),
                                       static_cast<long>(std::floor(p.y / args.place_size)),
                                       std::min(args.sectors - 1, static_cast<int>(sector)));
      if (seen.insert(key).second) starts.push_back(s.index);
    }

    // Where the map itself puts a true pose: the kept landmarks within twice the sensor's range
    // of it, their true places (brought into the map's frame) fitted onto their map means
    // (fitRigid), that local motion applied to the pose. A found pose is judged against this too:
    // its error relative to the map as drawn, which is the wake-up's, apart from the map's own
    // error against the world. None without true landmarks or with fewer than two near.
    std::map<LandmarkId, Eigen::Vector2d> true_landmarks;
    for (const auto& [id, p] : truth.landmarks) {
      const auto a = alignment.apply(Pose2(p.x(), p.y(), 0));
      true_landmarks[id] = Eigen::Vector2d(a.x, a.y);
    }
    const auto onTheMap = [&](const Pose2& t) -> std::optional<Pose2> {
      if (true_landmarks.empty() || !(reach > 0)) return std::nullopt;
      std::vector<Eigen::Vector2d> from, to;
      for (const auto& l : map) {
        const auto it = true_landmarks.find(l.id);
        if (it == true_landmarks.end() ||
            std::hypot(it->second.x() - t.x, it->second.y() - t.y) > 2 * reach)
          continue;
        from.push_back(it->second);
        to.push_back(l.mean);
      }
      if (from.size() < 2) return std::nullopt;
      const auto m = wakeup::fitRigid(from, to, std::vector<double>(from.size(), 1.0));
      if (!m) return std::nullopt;
      return compose(*m, t);
    };

    struct Tally {
      std::size_t places = 0, found = 0, wrong = 0, ambiguous = 0, not_found = 0;
      std::size_t found_on_map = 0;  ///< found within the bounds of where the map puts the truth
      std::map<std::string, std::size_t> reasons;
      std::vector<double> found_ms, found_steps, all_ms;
    };
    Tally all, mapped;
    std::ofstream csv;
    if (!args.csv.empty()) {
      csv.open(args.csv);
      csv << "start_step,x,y,yaw,status,reason,steps_used,landmarks,inliers,runner_up,"
             "hypotheses,score,runner_up_score,error_xy,error_yaw_deg,ms,in_mapped_area,"
             "error_on_map_xy,error_on_map_yaw_deg\n";
    }
    for (const StepIndex s0 : starts) {
      wakeup::GlobalLocalizer g(map, options, noise);
      const auto t0 = std::chrono::steady_clock::now();
      for (StepIndex s = s0; s < steps.size() && !g.finished(); ++s) g.add(steps[s]);
      const double ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      const auto& r = g.result();
      const auto t = trueAt(r.step);
      const double exy = std::hypot(r.pose.mean.x - t.x, r.pose.mean.y - t.y);
      const double eyaw = std::abs(wrapAngle(r.pose.mean.phi - t.phi)) * 180 / M_PI;
      const auto p0 = trueAt(s0);
      const auto on_map = r.status == wakeup::WakeUpStatus::Found ? onTheMap(t) : std::nullopt;
      const double on_map_xy =
          on_map ? std::hypot(r.pose.mean.x - on_map->x, r.pose.mean.y - on_map->y) : 0;
      const double on_map_yaw =
          on_map ? std::abs(wrapAngle(r.pose.mean.phi - on_map->phi)) * 180 / M_PI : 0;
      const bool in_area = area.contains(p0.x, p0.y);
      for (Tally* tally : {&all, in_area ? &mapped : nullptr}) {
        if (!tally) continue;
        ++tally->places;
        tally->all_ms.push_back(ms);
        if (r.status == wakeup::WakeUpStatus::Found) {
          if (exy <= args.found_xy && eyaw <= args.found_yaw_deg) {
            ++tally->found;
            tally->found_ms.push_back(ms);
            tally->found_steps.push_back(static_cast<double>(r.steps_used));
          } else {
            ++tally->wrong;
          }
          if (on_map && on_map_xy <= args.found_xy && on_map_yaw <= args.found_yaw_deg)
            ++tally->found_on_map;
        } else if (r.status == wakeup::WakeUpStatus::Ambiguous) {
          ++tally->ambiguous;
        } else {
          ++tally->not_found;
          ++tally->reasons[wakeup::reasonName(r.reason)];
        }
      }
      if (csv) {
        csv << s0 << ',' << p0.x << ',' << p0.y << ',' << p0.phi << ','
            << wakeup::statusName(r.status) << ',' << wakeup::reasonName(r.reason) << ','
            << r.steps_used << ',' << r.landmarks << ',' << r.inliers << ',' << r.runner_up << ','
            << r.hypotheses << ',' << r.score << ',' << r.runner_up_score << ',';
        if (r.status == wakeup::WakeUpStatus::Found)
          csv << exy << ',' << eyaw;
        else
          csv << ',';
        csv << ',' << ms << ',' << (in_area ? 1 : 0) << ',';
        if (on_map)
          csv << on_map_xy << ',' << on_map_yaw;
        else
          csv << ',';
        csv << '\n';
      }
    }
    std::printf("map %s (%zu landmarks), traversal %s (%zu steps), %zu places\n", args.map.c_str(),
                map.size(), args.rawlog.c_str(), steps.size(), starts.size());
    const auto print = [&](const Tally& t, const char* which) {
      const double n = static_cast<double>(std::max<std::size_t>(1, t.places));
      std::printf(
          "%s%zu places: found within %zu steps (%g m, %g deg): %zu (%.1f%%); found wrong: %zu "
          "(%.1f%%); ambiguous: %zu (%.1f%%); not found: %zu (%.1f%%)",
          which, t.places, options.max_steps, args.found_xy, args.found_yaw_deg, t.found,
          100 * t.found / n, t.wrong, 100 * t.wrong / n, t.ambiguous, 100 * t.ambiguous / n,
          t.not_found, 100 * t.not_found / n);
      for (const auto& [why, k] : t.reasons) std::printf(" [%s %zu]", why.c_str(), k);
      if (!true_landmarks.empty())
        std::printf("; found within the bounds of where the map puts the truth: %zu (%.1f%%)",
                    t.found_on_map, 100 * t.found_on_map / n);
      std::printf(
          "\n%swhen found: median %.0f steps, median %.2f ms, 95th percentile %.2f ms; every "
          "place: median %.2f ms, max %.2f ms\n",
          which, median(t.found_steps), median(t.found_ms), percentile(t.found_ms, 0.95),
          median(t.all_ms),
          t.all_ms.empty() ? 0.0 : *std::max_element(t.all_ms.begin(), t.all_ms.end()));
    };
    print(all, "");
    if (!area.everywhere()) print(mapped, "in the mapped area: ");
    return 0;
  } catch (const UsageError& e) {
    std::fprintf(stderr, "bench_wakeup_places: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_wakeup_places: %s\n", exceptionLine(e).c_str());
    return 1;
  }
}
