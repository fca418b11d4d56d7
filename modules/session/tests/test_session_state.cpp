// The session state file: what is written reads back bit for bit, owners get their sections and
// nothing else passes unread, the writer refuses a state the reader would refuse and never
// replaces a file it did not write.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "SessionTestUtil.h"

using namespace budget_slam;
using namespace budget_slam::session;
using namespace budget_slam::session::test;
namespace fs = std::filesystem;

namespace {

fs::path tempDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("budget_slam_session_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// Bit-for-bit equality of two doubles (tells -0 from +0).
bool same(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

bool sameMatrix(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) return false;
  for (Eigen::Index i = 0; i < a.size(); ++i)
    if (!same(a.data()[i], b.data()[i])) return false;
  return true;
}

/// Takes and reads every section of the sample's owners, as the budget and a reducer would.
void readOwners(const SessionState& s) {
  const auto& b = s.take("budget");
  b.integers("refused_ids");
  b.integers("refused_at");
  b.integer("next_id");
  b.reals("scores");
  b.text("reducer");
  const auto& p = s.take("place-coverage");
  p.matrix("places");
  p.real("place_size");
}

}  // namespace

TEST(SessionState, RoundTripIsExactToTheBit) {
  const SessionState a = sampleState(5);
  const std::string text = formatSessionState(a);
  const SessionState b = readSessionStateBytes("s.txt", text);

  EXPECT_EQ(b.header.writer, a.header.writer);
  EXPECT_EQ(b.header.backend, "ekf");
  EXPECT_EQ(b.header.rawlog, a.header.rawlog);
  EXPECT_EQ(b.header.sessions, 2);
  EXPECT_EQ(b.header.first_step, 100);
  EXPECT_EQ(b.header.next_step, 250);
  EXPECT_EQ(b.header.resume_options, a.header.resume_options);
  ASSERT_EQ(b.map.landmarks.size(), 5u);
  for (std::size_t i = 0; i < 5; ++i) {
    const auto &x = a.map.landmarks[i], &y = b.map.landmarks[i];
    EXPECT_EQ(y.id, x.id);
    EXPECT_TRUE(same(y.mean.x(), x.mean.x()) && same(y.mean.y(), x.mean.y())) << i;
    EXPECT_TRUE(same(y.obs_mean.x(), x.obs_mean.x()) && same(y.obs_mean.y(), x.obs_mean.y()));
    EXPECT_EQ(y.n_obs, x.n_obs);
    EXPECT_EQ(y.first_step, x.first_step);
    EXPECT_EQ(y.last_step, x.last_step);
    // The views' marginals are the joint's diagonal blocks.
    EXPECT_TRUE(sameMatrix(y.cov, a.map.covariance.block<2, 2>(2 * i, 2 * i)));
  }
  EXPECT_TRUE(same(b.map.landmarks[0].mean.y(), -0.0));  // the sign of zero survives
  EXPECT_TRUE(same(b.map.landmarks[1].obs_mean.y(), 4.9406564584124654e-324));
  EXPECT_TRUE(sameMatrix(b.map.covariance, a.map.covariance));
  ASSERT_TRUE(b.robot.has_value());
  EXPECT_TRUE(same(b.robot->pose.mean.x, 1.0 / 3.0));
  EXPECT_TRUE(same(b.robot->pose.mean.phi, 0.7));
  EXPECT_TRUE(sameMatrix(b.robot->pose.cov, a.robot->pose.cov));
  EXPECT_TRUE(sameMatrix(b.robot->cross_covariance, a.robot->cross_covariance));

  const auto& budget = b.take("budget");
  EXPECT_EQ(budget.integers("refused_ids"), (std::vector<std::int64_t>{4, 9, 12}));
  EXPECT_EQ(budget.integer("next_id"), 42);
  const auto& scores = budget.reals("scores");
  ASSERT_EQ(scores.size(), 3u);
  EXPECT_TRUE(same(scores[1], 1.0 / 3.0) && same(scores[2], -1e-300));
  EXPECT_EQ(budget.text("reducer"), "place-coverage");
  budget.integers("refused_at");
  const auto& pc = b.take("place-coverage");
  EXPECT_TRUE(sameMatrix(pc.matrix("places", 2, 3),
                         std::get<Eigen::MatrixXd>(a.sections()[1].fields()[0].value)));
  EXPECT_EQ(pc.real("place_size"), 2.5);
  EXPECT_NO_THROW(b.checkAllRead());

  // Written again, the state gives the same bytes.
  EXPECT_EQ(formatSessionState(b), text);
}

TEST(SessionState, RandomStatesRoundTripExactly) {
  for (unsigned seed = 1; seed <= 20; ++seed) {
    SessionState a = sampleState(seed % 7, seed % 2 == 0, seed);
    const std::string text = formatSessionState(a);
    const SessionState b = readSessionStateBytes("s.txt", text);
    EXPECT_TRUE(sameMatrix(b.map.covariance, a.map.covariance)) << seed;
    EXPECT_EQ(b.robot.has_value(), a.robot.has_value());
    EXPECT_EQ(formatSessionState(b), text) << seed;
  }
}

TEST(SessionState, AnEmptyMapWithoutRobotReadsBack) {
  SessionState a;
  a.header.writer = "w";
  a.header.backend = "graph";
  const SessionState b = readSessionStateBytes("s.txt", formatSessionState(a));
  EXPECT_TRUE(b.map.landmarks.empty());
  EXPECT_EQ(b.map.covariance.rows(), 0);
  EXPECT_FALSE(b.robot.has_value());
  EXPECT_EQ(b.header.rawlog, "");
  EXPECT_NO_THROW(b.checkAllRead());
}

TEST(SessionState, TheFileSaysWhatItIs) {
  const std::string text = formatSessionState(sampleState(2));
  EXPECT_EQ(text.rfind("budget-slam-session-state 1\n# ", 0), 0u);
  EXPECT_NE(text.find("\n[session]\ntext writer budget-slam 0.1.0\ntext backend ekf\n"),
            std::string::npos);
  EXPECT_NE(text.find("\n[resume_options]\ntext LandmarkBudget.max_landmarks 50\n"),
            std::string::npos);
  EXPECT_NE(text.find("\n[landmarks]\nints ids 2\n3 10\nreals mean 4\n"), std::string::npos);
  EXPECT_NE(text.find("\nmatrix covariance 4 4\n"), std::string::npos);
  EXPECT_NE(text.find("\n[robot]\nreals mean 3\n0.3333333333333333 -2.5 0.7\n"), std::string::npos);
  EXPECT_NE(text.find("\nmatrix cross_covariance 3 4\n"), std::string::npos);
  EXPECT_NE(text.find("\n[budget]\nints refused_ids 3\n4 9 12\n"), std::string::npos);
  // Long arrays wrap at ten values a line.
  SessionState s = sampleState(1);
  s.section("budget").putIntegers("many", std::vector<std::int64_t>(25, 7));
  const std::string t = formatSessionState(s);
  EXPECT_NE(t.find("ints many 25\n7 7 7 7 7 7 7 7 7 7\n7 7 7 7 7 7 7 7 7 7\n7 7 7 7 7\n"),
            std::string::npos);
  EXPECT_EQ(t.substr(t.size() - 19, 10), "end crc32 ");
}

TEST(SessionState, OwnersTakeTheirSectionsAndNothingPassesUnread) {
  const std::string text = formatSessionState(sampleState(2));
  {
    const SessionState s = readSessionStateBytes("s.txt", text);
    readOwners(s);
    EXPECT_NO_THROW(s.checkAllRead());
  }
  {  // A section no owner takes: the run reading it does not know what it means.
    const SessionState s = readSessionStateBytes("s.txt", text);
    s.take("budget").integers("refused_ids");
    s.take("budget").integers("refused_at");
    s.take("budget").integer("next_id");
    s.take("budget").reals("scores");
    s.take("budget").text("reducer");
    EXPECT_EQ(errorOf([&] { s.checkAllRead(); }),
              "session state 's.txt': line 52: section 'place-coverage': unknown section (no "
              "part of this run reads it)");
  }
  {  // A field its owner does not read.
    const SessionState s = readSessionStateBytes("s.txt", text);
    readOwners(s);
    SessionState t = readSessionStateBytes("s.txt", text);
    const auto& b = t.take("budget");
    b.integers("refused_ids");
    t.take("place-coverage").matrix("places");
    t.take("place-coverage").real("place_size");
    EXPECT_EQ(errorOf([&] { t.checkAllRead(); }),
              "session state 's.txt': line 46: section 'budget', field 'refused_at': unknown "
              "field (its section's owner does not read it)");
  }
  const SessionState s = readSessionStateBytes("s.txt", text);
  EXPECT_EQ(errorOf([&] { s.take("mi"); }), "session state 's.txt': missing section 'mi'");
  EXPECT_EQ(s.takeIfPresent("mi"), nullptr);
  const auto& b = s.take("budget");
  EXPECT_EQ(errorOf([&] { b.integer("nope"); }),
            "session state 's.txt': line 43: section 'budget': missing field 'nope'");
  EXPECT_EQ(errorOf([&] { b.reals("refused_ids"); }),
            "session state 's.txt': line 44: section 'budget', field 'refused_ids': is 'ints', "
            "expected 'reals'");
  EXPECT_EQ(errorOf([&] { b.integer("next_id", 50); }),
            "session state 's.txt': line 48: section 'budget', field 'next_id': 42 is out of "
            "range [50, 9223372036854775807]");
  EXPECT_EQ(errorOf([&] { b.integers("refused_ids", 2, 0, 100); }),
            "session state 's.txt': line 44: section 'budget', field 'refused_ids': 3 values, "
            "expected 2");
  EXPECT_EQ(errorOf([&] { b.integers("refused_ids", 3, 0, 10); }),
            "session state 's.txt': line 44: section 'budget', field 'refused_ids': value 3 (12) "
            "is out of range [0, 10]");
  EXPECT_EQ(errorOf([&] { s.take("place-coverage").matrix("places", 3, 3); }),
            "session state 's.txt': line 53: section 'place-coverage', field 'places': 2 x 3, "
            "expected 3 x 3");
}

TEST(SessionState, NamesAreCheckedWhereTheyAreMade) {
  SessionState s;
  s.header.backend = "graph";
  EXPECT_THROW(s.section("landmarks"), std::invalid_argument);
  EXPECT_THROW(s.section("robot"), std::invalid_argument);
  EXPECT_THROW(s.section("has space"), std::invalid_argument);
  EXPECT_THROW(s.section(""), std::invalid_argument);
  EXPECT_THROW(s.section(std::string(65, 'a')), std::invalid_argument);
  auto& b = s.section("budget");
  EXPECT_EQ(&s.section("budget"), &b);  // the same section again
  s.section("other");
  EXPECT_EQ(&s.section("budget"), &b);  // references stay valid
  b.putInteger("x", 1);
  EXPECT_THROW(b.putInteger("x", 2), std::invalid_argument);
  EXPECT_THROW(b.putReal("bad name", 1), std::invalid_argument);
  EXPECT_THROW(b.putText("t", "two\nlines"), std::invalid_argument);
  EXPECT_THROW(b.putText("t", "\xff"), std::invalid_argument);
  EXPECT_NO_THROW(b.putText("t", "  spaces kept, UTF-8 \xc3\xa9 too  "));
  const SessionState r = readSessionStateBytes("s.txt", formatSessionState(s));
  EXPECT_EQ(r.take("budget").text("t"), "  spaces kept, UTF-8 \xc3\xa9 too  ");
}

TEST(SessionState, ResumeMismatchesNameEachOption) {
  const std::map<std::string, std::string> saved = {{"LandmarkBudget.max_landmarks", "50"},
                                                    {"LandmarkBudget.reducer", "mi"},
                                                    {"GraphSLAM.solver", "lm"}};
  EXPECT_TRUE(resumeMismatches(saved, saved).empty());
  auto now = saved;
  now["LandmarkBudget.max_landmarks"] = "40";
  now.erase("GraphSLAM.solver");
  now["Metrics.eig_max_rows"] = "10";
  EXPECT_EQ(
      resumeMismatches(saved, now),
      (std::vector<std::string>{"[GraphSLAM] solver = (unset), the saved session had lm",
                                "[LandmarkBudget] max_landmarks = 40, the saved session had 50",
                                "[Metrics] eig_max_rows = 10, the saved session had (unset)"}));
}

TEST(SessionState, TheWriterRefusesAStateTheReaderWouldRefuse) {
  {
    SessionState s = sampleState(2);
    s.map.landmarks[1].mean.x() = std::nan("");
    EXPECT_EQ(errorOf([&] { formatSessionState(s, "out/s.txt"); }),
              "session state 'out/s.txt': section 'landmarks', field 'mean': value 3 is not "
              "finite (nan) (not written)");
  }
  {
    SessionState s = sampleState(2);
    s.map.covariance(0, 1) += 1.0;
    EXPECT_EQ(errorOf([&] { formatSessionState(s, "out/s.txt"); }).substr(0, 99),
              "session state 'out/s.txt': section 'landmarks', field 'covariance': not symmetric "
              "(row 1, column 2 ");
  }
  {
    SessionState s = sampleState(2);
    s.map.covariance(3, 3) = -1;
    EXPECT_EQ(errorOf([&] { formatSessionState(s, "out/s.txt"); }),
              "session state 'out/s.txt': section 'landmarks', field 'covariance': not positive "
              "definite (diagonal entry 4 is -1) (not written)");
  }
  {
    SessionState s = sampleState(2);
    s.robot->cross_covariance *= 100;  // each block fine, the joint not
    EXPECT_EQ(errorOf([&] { formatSessionState(s, "out/s.txt"); }),
              "session state 'out/s.txt': section 'robot', field 'cross_covariance': the joint "
              "covariance of the robot and the landmarks is not positive definite (not written)");
  }
  {
    SessionState s = sampleState(2);
    s.section("budget").putReal("inf", std::numeric_limits<double>::infinity());
    EXPECT_EQ(errorOf([&] { formatSessionState(s, "out/s.txt"); }),
              "session state 'out/s.txt': section 'budget', field 'inf': the value is not finite "
              "(inf) (not written)");
  }
  {
    SessionState s = sampleState(2);
    s.map.landmarks[1].id = s.map.landmarks[0].id;
    EXPECT_EQ(errorOf([&] { formatSessionState(s, "out/s.txt"); }),
              "session state 'out/s.txt': section 'landmarks', field 'ids': landmark 3 appears "
              "twice (not written)");
  }
  {
    SessionState s = sampleState(2);
    s.map.covariance.resize(2, 2);
    s.map.covariance.setIdentity();
    EXPECT_EQ(errorOf([&] { formatSessionState(s, "out/s.txt"); }),
              "session state 'out/s.txt': section 'landmarks', field 'covariance': 2 x 2, "
              "expected 4 x 4 (not written)");
  }
}

TEST(SessionState, WritesAtomicallyAndNeverOverAForeignFile) {
  const auto d = tempDir("write");
  const std::string p = (d / kStateFileName).string();
  const SessionState s = sampleState(3);
  writeSessionState(p, s);
  EXPECT_EQ(slurp(p), formatSessionState(s, p));
  EXPECT_FALSE(fs::exists(p + ".tmp"));
  // Its own earlier file is replaced.
  SessionState t = sampleState(4);
  writeSessionState(p, t);
  EXPECT_EQ(readSessionState(p).map.landmarks.size(), 4u);

  const std::string foreign = (d / "notes.txt").string();
  std::ofstream(foreign) << "my notes\n";
  EXPECT_EQ(errorOf([&] { writeSessionState(foreign, s); }),
            "session state '" + foreign +
                "': the file exists and is not a session state; not written over");
  EXPECT_EQ(slurp(foreign), "my notes\n");
  EXPECT_EQ(errorOf([&] { writeSessionState(d.string(), s); }),
            "session state '" + d.string() + "': is a folder; not written over");
  EXPECT_EQ(errorOf([&] { writeSessionState((d / "no" / "such").string(), s); }),
            "cannot write '" + (d / "no" / "such").string() + "' (No such file or directory)");
  // A state the reader would refuse leaves the earlier file as it was.
  SessionState bad = sampleState(2);
  bad.robot->pose.mean.x = std::nan("");
  const std::string before = slurp(p);
  EXPECT_NE(errorOf([&] { writeSessionState(p, bad); }), "no error");
  EXPECT_EQ(slurp(p), before);
  fs::remove_all(d);
}

TEST(SessionState, ReadsFromAFile) {
  const auto d = tempDir("read");
  const std::string p = (d / kStateFileName).string();
  writeSessionState(p, sampleState(3));
  const SessionState s = readSessionState(p);
  EXPECT_EQ(s.source, p);
  EXPECT_EQ(s.map.landmarks.size(), 3u);
  EXPECT_EQ(errorOf([&] { readSessionState((d / "none.txt").string()); }),
            "session state '" + (d / "none.txt").string() + "': no such file");
  EXPECT_EQ(errorOf([&] { readSessionState(d.string()); }),
            "session state '" + d.string() + "': is a folder, not a file");
  fs::remove_all(d);
}
