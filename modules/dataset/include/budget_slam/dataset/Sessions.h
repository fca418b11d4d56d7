#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "budget_slam/core/Ids.h"
#include "budget_slam/core/OptionTable.h"
#include "budget_slam/dataset/Simulator.h"

namespace budget_slam::dataset {

/// A series of sessions in one world that changes between them (budget-simulate --sessions N
/// --change F; docs/DATASETS.md "Sessions in a changing world"). MRPT's options pattern with every
/// key in table(); budget-simulate takes them from its command line, and
/// simulateSessionsToFiles() checks them again (the same ranges) whoever filled them.
struct SessionChangeOptions : public TabledOptions<SessionChangeOptions> {
  static constexpr const char* kSection = "SimulationSessions";
  static constexpr int kMaxSessions = 999;
  int sessions = 1;  ///< N, 1 .. kMaxSessions
  /// F: before each session after the first, round(F x landmarks of the previous session) of them
  /// change, in [0, 1].
  double change = 0.05;
  /// How the changes split into disappearing, moving and appearing landmarks: shares >= 0, not
  /// all 0, normalized (default equal thirds); counts by largest remainder, ties in this order.
  double share_disappear = 1, share_move = 1, share_appear = 1;
  /// A moved landmark keeps its id and goes this far in a random direction; an appearing one
  /// (new id, never reused) is placed this far from a random landmark of the previous session,
  /// in the same region [m], > 0.
  double move_distance = 1.0;
  /// One traversal instead of one rawlog a session: the route is driven once a session, back to
  /// back, and the world changes as the robot starts each session's first lap.
  bool joined = false;

  /// Every key: name, field, check and unit (the defaults are the initializers above).
  static const OptionTable<SessionChangeOptions>& table();
};

/// One change between two sessions (a row of `<stem>_changes.csv`).
struct LandmarkChange {
  enum class Kind { Disappeared, Moved, Appeared };
  int session = 0;  ///< the first session (1-based) that sees the world changed
  Kind kind = Kind::Disappeared;
  LandmarkId id = kNoLandmarkId;
  Eigen::Vector2d before = Eigen::Vector2d::Zero(), after = Eigen::Vector2d::Zero();  ///< [m]
  static const char* name(Kind k);
};

/// `<dir>/<stem>_s<k>.rawlog` for session k (1-based) of n: k with at least 2 digits, as many as
/// n has (my_s01.rawlog .. my_s20.rawlog; my_s001 .. my_s120 for 120 sessions).
std::string sessionRawlogName(const std::string& rawlog, int session, int sessions);
/// `<dir>/<stem>_changes.csv`: every change, session by session.
std::string changesFileFor(const std::string& rawlog);

/// One file written: path and steps (0 for files without steps).
struct WrittenRawlog {
  std::string path;
  std::size_t steps = 0;
};

/// Simulates the sessions to files (one rawlog, ground truth and sidecar a session, or one joined
/// traversal) and the changes file. Before writing anything, refuses with InputError a target
/// file that exists and was not written by budget-simulate (checkNotForeign). ConfigError for a
/// bad option (the lifelong scenario changes between its laps already).
std::vector<WrittenRawlog> simulateSessionsToFiles(const SimulationOptions& options,
                                                   const SessionChangeOptions& sessions,
                                                   const std::string& rawlog);

/// Throws InputError "'<file>': exists and was not written by budget-simulate; not written over"
/// for the first of the files named after `rawlog` (itself, its two ground-truth files, its
/// sidecar ini) that exists while that sidecar does not carry budget-simulate's mark ("# Made by
/// budget-simulate"); the second form for `file` when it exists and its first line is not
/// `first_line`.
void checkNotForeign(const std::string& rawlog);
void checkNotForeign(const std::string& file, const std::string& first_line);

}  // namespace budget_slam::dataset
