#include "budget_slam/ekf/MrptIniCheck.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/IniSection.h"

namespace budget_slam::ekf {
namespace {

constexpr const char* kSlam = "RangeBearingKFSLAM";
constexpr const char* kKalman = "RangeBearingKFSLAM_KalmanFilter";

[[noreturn]] void fail(const std::string& section, const std::string& key, const std::string& value,
                       const std::string& why) {
  throw KeyError::ofValue(section, key, value, why);
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

/// MRPT's read_enum: a name of the enum, or its numeric value.
void checkEnum(const IniSection& s, const std::string& key, const std::vector<std::string>& names) {
  if (!s.has(key)) return;
  const std::string v = s.readString(key, "");
  if (v.empty()) return;  // MRPT keeps the default
  if (std::find(names.begin(), names.end(), v) != names.end()) return;
  const bool digits =
      std::all_of(v.begin(), v.end(), [](unsigned char c) { return std::isdigit(c); });
  if (digits && v.size() <= 2 && std::stoul(v) < names.size()) return;
  fail(s.name(), key, "'" + v + "'", "must be one of " + joined(names));
}

/// MRPT's read_bool takes true, false, yes, no, or an integer (anything else reads as false).
void checkBool(const IniSection& s, const std::string& key) {
  if (!s.has(key)) return;
  std::string v = s.readString(key, "");
  std::transform(v.begin(), v.end(), v.begin(), [](unsigned char c) { return std::tolower(c); });
  for (const char* ok : {"true", "false", "yes", "no", "1", "0"})
    if (v == ok) return;
  fail(s.name(), key, "'" + s.readString(key, "") + "'", "not a boolean (true or false)");
}

/// stds_Q_no_odo: MRPT's read_vector splits on "[], \t" and asserts exactly 3 values.
void checkStdsQ(const IniSection& s) {
  const std::string key = "stds_Q_no_odo";
  if (!s.has(key)) return;
  const std::string v = s.readString(key, "");
  std::vector<std::string> tokens;
  std::string cur;
  for (const char c : v + " ") {
    if (c == '[' || c == ']' || c == ',' || c == ' ' || c == '\t') {
      if (!cur.empty()) tokens.push_back(cur), cur.clear();
    } else {
      cur += c;
    }
  }
  if (tokens.empty()) return;  // MRPT keeps the default
  const std::string why =
      "must be 3 values (x [m], y [m], yaw [deg]), each finite and >= 0 (the motion noise of a "
      "step "
      "without odometry)";
  if (tokens.size() != 3) fail(s.name(), key, "'" + v + "'", why);
  for (const auto& t : tokens) {
    char* end = nullptr;
    const double x = std::strtod(t.c_str(), &end);
    if (end != t.c_str() + t.size() || !std::isfinite(x) || x < 0 || x > IniSection::kMaxStd)
      fail(s.name(), key, "'" + v + "'", why);
  }
}

}  // namespace

void checkMrptKfSlamOptions(const mrpt::config::CConfigFileBase& ini) {
  const IniSection slam(ini, kSlam);
  checkStdsQ(slam);
  slam.readStd("std_sensor_range", 0.1);
  slam.readStd("std_sensor_yaw_deg", 0.5);
  slam.readDouble("quantiles_3D_representation", 3, 1e-6, 1e6);
  checkBool(slam, "create_simplemap");
  checkEnum(slam, "data_assoc_method", {"assocNN", "assocJCBB"});
  checkEnum(slam, "data_assoc_metric", {"metricMaha", "metricML"});
  checkEnum(slam, "data_assoc_IC_metric", {"metricMaha", "metricML"});
  // A chi-squared confidence level: MRPT takes its inverse CDF.
  const double chi2 = slam.readDouble("data_assoc_IC_chi2_thres", 0.99);
  if (slam.has("data_assoc_IC_chi2_thres") && (chi2 <= 0 || chi2 >= 1))
    fail(kSlam, "data_assoc_IC_chi2_thres", slam.readString("data_assoc_IC_chi2_thres", ""),
         "must be in (0, 1) (a confidence level)");
  slam.readDouble("data_assoc_IC_ml_threshold", 0);

  const IniSection kf(ini, kKalman);
  if (kf.has("method") &&
      (kf.readString("method", "") == "kfIKF" || kf.readString("method", "") == "3"))
    fail(kKalman, "method", "'" + kf.readString("method", "") + "'",
         "MRPT 2.5 does not implement kfIKF; use kfEKFNaive, kfEKFAlaDavison or kfIKFFull");
  checkEnum(kf, "method", {"kfEKFNaive", "kfEKFAlaDavison", "kfIKFFull"});
  checkEnum(kf, "verbosity_level", {"LVL_DEBUG", "LVL_INFO", "LVL_WARN", "LVL_ERROR"});
  kf.readInt("IKF_iterations", 5, 1, 1000);
  for (const char* b : {"enable_profiler", "use_analytic_transition_jacobian",
                        "use_analytic_observation_jacobian", "debug_verify_analytic_jacobians"})
    checkBool(kf, b);
  const double thr = kf.readDouble("debug_verify_analytic_jacobians_threshold", 1e-2);
  if (kf.has("debug_verify_analytic_jacobians_threshold") && thr <= 0)
    fail(kKalman, "debug_verify_analytic_jacobians_threshold",
         kf.readString("debug_verify_analytic_jacobians_threshold", ""), "must be > 0");
}

}  // namespace budget_slam::ekf
