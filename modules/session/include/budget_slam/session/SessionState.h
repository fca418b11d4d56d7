#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "budget_slam/core/Estimates.h"
#include "budget_slam/session/SessionSection.h"

namespace budget_slam::session {

/// What wrote a session state and what a resumed run must match (section `[session]` and
/// `[resume_options]` of the file; docs/OUTPUTS.md "Session state").
struct SessionHeader {
  std::string writer;   ///< program and version, e.g. "budget-slam 0.1.0"
  std::string backend;  ///< registry name of the backend that made the state ("ekf", "graph")
  std::string rawlog;   ///< the rawlog the session read, as given on its command line
  /// Sessions in the chain so far, this one included (1 for a first session).
  std::int64_t sessions = 1;
  /// Step index of the session's first step, and the index the next session's first step takes
  /// (the session read next_step - first_step steps). Step indices run on across sessions so that
  /// what the budget remembers by step (refusal waits, first and last sightings) stays valid.
  std::int64_t first_step = 0, next_step = 0;
  /// The options that shaped the map, "Section.key" -> value as in config_used.ini: a resumed run
  /// with other values would not continue the same estimate (resumeMismatches()).
  std::map<std::string, std::string> resume_options;
};

/// The map: every landmark and their joint covariance (section `[landmarks]`).
struct LandmarkBlock {
  /// In the order of `covariance`'s 2x2 blocks. Each view's `cov` is the diagonal block of
  /// `covariance` (filled by the reader; the writer takes `covariance` as the truth).
  std::vector<LandmarkView> landmarks;
  /// Joint covariance of the landmark positions, 2n x 2n, (x, y) of each landmark in turn [m^2]:
  /// the EKF's whole landmark block, or the graph's joint landmark marginal.
  Eigen::MatrixXd covariance;
};

/// The robot where the session stopped (section `[robot]`): present when the next session
/// continues from there, absent when it must wake up anywhere.
struct RobotBlock {
  PoseEstimate pose;                 ///< x, y [m], yaw [rad] and its 3x3 covariance
  Eigen::MatrixXd cross_covariance;  ///< 3 x 2n, robot pose against the landmarks, in their order
};

/// Where the robot of a resumed session starts: told by the run that resumes, never read from the
/// file (a file only knows where its session stopped).
enum class RobotStart {
  /// The robot goes on from where the saved session stopped (`[robot]` as saved): a backend that
  /// saved its whole estimate (the graph's chain) continues it, step for step the one-shot run.
  WhereItStopped,
  /// The robot was placed elsewhere on the saved map (`run --resume --wake-up`: `robot` replaced
  /// by the pose found, uncorrelated with the map): a new chain starts on the saved map.
  Placed,
};

/// Bounds on what a session state file may make the reader allocate (checked before allocating).
struct SessionLimits {
  std::size_t max_landmarks = 2000;  ///< landmarks in `[landmarks]` (the covariance is dense)
  std::size_t max_section_values = std::size_t{1} << 22;  ///< values in one owner's section
  std::size_t max_values = std::size_t{1} << 25;          ///< values in the whole file
  std::size_t max_line_bytes = std::size_t{1} << 20;      ///< bytes in one line
  std::size_t max_sections = 64;                          ///< sections in the file
  std::size_t max_fields = 256;                           ///< fields in one section
};

/// Everything a session hands to the next one: the header, the map, the robot, and one named
/// section for each other owner of memory (the budget manager, each reducer).
///
/// Writing: fill header, map and robot, add owner sections with section(), then
/// writeSessionState(). Reading: readSessionState() checks the file and the blocks; then each
/// owner takes its section (take(), takeIfPresent()) and reads its fields; checkAllRead() at the
/// end refuses a section or a field no owner asked for.
class SessionState {
 public:
  SessionHeader header;
  LandmarkBlock map;
  std::optional<RobotBlock> robot;
  /// How `robot` came to be: WhereItStopped as read; the run's wake-up sets Placed.
  RobotStart robot_start = RobotStart::WhereItStopped;

  /// Names the file and the core blocks use; owners may not take them.
  static const std::vector<std::string>& reservedSections();

  /// The owner section `name`, created empty on first use (std::invalid_argument for a reserved
  /// or malformed name). The reference stays valid while the state lives.
  SessionSection& section(const std::string& name);
  /// Adds a section read from a file (InputError for a second section of the same name).
  void addSection(SessionSection s);

  /// The section of owner `name`. InputError "session state 'F': missing section 'budget'".
  const SessionSection& take(const std::string& name) const;
  /// The section of owner `name`, or nullptr when the file has none.
  const SessionSection* takeIfPresent(const std::string& name) const;
  /// InputError naming the first section no owner took, or the first field of a taken section
  /// no getter read: "session state 'F': line 40: unknown section 'places' (no part of this run
  /// reads it)", "... section 'budget': unknown field 'x'".
  void checkAllRead() const;

  const std::deque<SessionSection>& sections() const { return sections_; }
  /// The file this state was read from ("" when built in memory).
  std::string source;

 private:
  std::deque<SessionSection> sections_;  ///< a deque: section() references stay valid
  mutable std::vector<bool> taken_;
};

/// One line for each option that differs between a saved state and the run about to resume it:
/// "[LandmarkBudget] max_landmarks = 40, the saved session had 50"; an option only one side has
/// counts as a difference ("(unset)"). Empty when they match.
std::vector<std::string> resumeMismatches(const std::map<std::string, std::string>& saved,
                                          const std::map<std::string, std::string>& now);

}  // namespace budget_slam::session
