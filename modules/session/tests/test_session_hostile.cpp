// The session state reader on corrupt, truncated, foreign and hostile files: every failure is one
// InputError line naming the file (and the line, section and field where there is one), raised
// before anything the file declares is allocated.
#include <gtest/gtest.h>

#include "SessionTestUtil.h"

using namespace budget_slam;
using namespace budget_slam::session;
using namespace budget_slam::session::test;

namespace {

const std::string& goodText() {
  static const std::string t = formatSessionState(sampleState(3));
  return t;
}

}  // namespace

TEST(SessionHostile, ForeignFilesAndVersions) {
  EXPECT_EQ(readError(""),
            "session state 's.txt': not a budget-slam session state (the file is empty)");
  EXPECT_EQ(readError("id,x,y,var_x\n1,2,3,4\n"),
            "session state 's.txt': not a budget-slam session state (it begins 'id,x,y,var_x')");
  EXPECT_EQ(readError(std::string("\x1f\x8b\x08\x00\x00\x00", 6) + std::string(100000, 'z')),
            "session state 's.txt': not a budget-slam session state (it begins "
            "'\\x1f\\x8b\\x08\\x00\\x00\\x00zzzzzzzzzzzzzzzz...')");
  EXPECT_EQ(readError("budget-slam\n"),
            "session state 's.txt': not a budget-slam session state (it begins 'budget-slam')");
  EXPECT_EQ(readError(std::string(kFormatName) + " " + std::string(100, '1')),
            "session state 's.txt': line 1 is longer than 64 bytes");
  EXPECT_EQ(readError(replaced(goodText(), "state 1\n", "state 2\n")),
            "session state 's.txt': format version 2; this budget-slam reads version 1");
  EXPECT_EQ(readError(replaced(goodText(), "state 1\n", "state one\n")),
            "session state 's.txt': line 1: 'one' is not a format version");
}

TEST(SessionHostile, ChecksumCatchesAChangedDigit) {
  // A digit of the landmark means changed: every line still parses.
  std::string t = goodText();
  const auto at = t.find("reals mean 6\n") + 13;
  t[at + 2] = t[at + 2] == '1' ? '2' : '1';
  const std::string body = t.substr(0, t.rfind("end crc32 "));
  char contents[16];
  std::snprintf(contents, sizeof contents, "%08lx",
                crc32_z(0L, reinterpret_cast<const Bytef*>(body.data()), body.size()));
  EXPECT_EQ(readError(t), "session state 's.txt': checksum mismatch (the end line says " +
                              goodText().substr(goodText().size() - 9, 8) + ", the contents give " +
                              contents + "): the file was changed or damaged");
  EXPECT_EQ(readError(replaced(goodText(), "end crc32 ", "end crc32 x")).substr(0, 40),
            "session state 's.txt': line 59: 'end crc");
  EXPECT_EQ(readError(goodText() + "more\n"),
            "session state 's.txt': data after the end line (line 59)");
}

TEST(SessionHostile, EachCorruptionClassHasItsLine) {
  const std::string& g = goodText();
  // Values the parser refuses, at the line where they are.
  EXPECT_EQ(
      readError(withChecksum(replaced(g, "reals mean 6\n2.78723363418735", "reals mean 6\nnan"))),
      "session state 's.txt': line 18: section 'landmarks', field 'mean': value 1 is not "
      "finite (nan)");
  EXPECT_EQ(
      readError(withChecksum(replaced(g, "reals mean 6\n2.78723363418735", "reals mean 6\n1e999"))),
      "session state 's.txt': line 18: section 'landmarks', field 'mean': value 1 (1e999) "
      "is out of range");
  EXPECT_EQ(
      readError(withChecksum(replaced(g, "reals mean 6\n2.78723363418735", "reals mean 6\nabc"))),
      "session state 's.txt': line 18: section 'landmarks', field 'mean': 'abc' is not a "
      "number");
  EXPECT_EQ(readError(withChecksum(replaced(g, "ints ids 3\n3", "ints ids 3\n3.5"))),
            "session state 's.txt': line 16: section 'landmarks', field 'ids': '3.5' is not an "
            "integer");
  EXPECT_EQ(readError(withChecksum(replaced(g, "ints ids 3\n3 10 17", "ints ids 3\n3 10 17 24"))),
            "session state 's.txt': line 16: section 'landmarks', field 'ids': more values than "
            "the 3 declared");
  EXPECT_EQ(readError(withChecksum(replaced(g, "ints ids 3\n", "ints ids 3\n\n"))),
            "session state 's.txt': line 16: section 'landmarks', field 'ids': a line without "
            "values");
  EXPECT_EQ(
      readError(withChecksum(replaced(g, "matrix covariance 6 6\n", "matrix covariance 6 6\n1 "))),
      "session state 's.txt': line 20: section 'landmarks', field 'covariance': row 1 has 7 "
      "values, expected 6");
  // Structure.
  EXPECT_EQ(readError(withChecksum(replaced(g, "[session]", "[sess ion]"))),
            "session state 's.txt': line 3: 'sess ion' is not a section name");
  EXPECT_EQ(readError(withChecksum(replaced(g, "[session]", "[session"))),
            "session state 's.txt': line 3: '[session' is not a section line");
  EXPECT_EQ(readError(withChecksum(replaced(g, "[resume_options]", "[session]"))),
            "session state 's.txt': line 10: section 'session' appears twice");
  EXPECT_EQ(readError(withChecksum(replaced(g, "text backend", "text writer"))),
            "session state 's.txt': line 5: section 'session': field 'writer' appears twice");
  EXPECT_EQ(readError(withChecksum(replaced(g, "int sessions", "integer sessions"))),
            "session state 's.txt': line 7: section 'session': 'integer' is not a field type "
            "(int, real, text, ints, reals, matrix)");
  EXPECT_EQ(readError(withChecksum(replaced(g, "int sessions 2", "int sessions 2 3"))),
            "session state 's.txt': line 7: section 'session', field 'sessions': 'int sessions 2 "
            "3' is not a 'int' line");
  EXPECT_EQ(readError(withChecksum(replaced(g, "[session]\n", "[session]\n\n"))),
            "session state 's.txt': line 4: section 'session': an empty line");
  EXPECT_EQ(readError(withChecksum(replaced(g, "[session]\n", ""))),
            "session state 's.txt': line 3: a field before the first section");
  EXPECT_EQ(readError(withChecksum(replaced(g, "text rawlog rawlogs", "text rawlog \x01rawlogs"))),
            "session state 's.txt': line 6: section 'session', field 'rawlog': text with a "
            "control character");
  // The blocks' rules, after the checksum.
  EXPECT_EQ(readError(withChecksum(replaced(g, "[landmarks]", "[landmark]"))),
            "session state 's.txt': missing section 'landmarks'");
  EXPECT_EQ(readError(withChecksum(replaced(g, "ints ids 3\n3 10", "ints ids 3\n3 3"))),
            "session state 's.txt': line 15: section 'landmarks', field 'ids': landmark 3 appears "
            "twice");
  EXPECT_EQ(readError(withChecksum(replaced(g, "ints ids 3\n3 10", "ints ids 3\n3 -10"))),
            "session state 's.txt': line 15: section 'landmarks', field 'ids': value 2 (-10) is "
            "not a landmark id (negative)");
  EXPECT_EQ(readError(withChecksum(replaced(g, "int next_step 250", "int next_step 150"))),
            "session state 's.txt': line 32: section 'landmarks', field 'last_step': value 1 (200) "
            "is out of range [0, 149]");
  EXPECT_EQ(readError(withChecksum(replaced(g, "ints sightings 3", "reals sightings 3"))),
            "session state 's.txt': line 26: section 'landmarks', field 'sightings': is 'reals', "
            "expected 'ints'");
  EXPECT_EQ(readError(withChecksum(replaced(g, "[robot]\n", "[robot]\nint extra 1\n"))),
            "session state 's.txt': line 35: section 'robot', field 'extra': unknown field");
  EXPECT_EQ(
      readError(withChecksum(replaced(g, "reals mean 6\n2.78723363418735", "reals mean 6\n1e10"))),
      "session state 's.txt': line 17: section 'landmarks', field 'mean': value 1 (1e+10) is "
      "beyond +-1e9 m");
  EXPECT_EQ(readError(withChecksum(replaced(g, "text backend ekf", "text backend"))),
            "session state 's.txt': line 5: section 'session', field 'backend': empty");
  EXPECT_EQ(readError(withChecksum(replaced(g, "int sessions 2", "int sessions 0"))),
            "session state 's.txt': line 7: section 'session', field 'sessions': 0 is out of range "
            "[1, 1099511627776]");
}

TEST(SessionHostile, CovariancesMustBeSymmetricAndPositiveDefinite) {
  const SessionState good = sampleState(3);
  const auto edit = [&](const std::function<void(Eigen::MatrixXd&)>& f) {
    // Edits the covariance in the text (as a damaged or hand-made file would hold it).
    SessionState s = good;
    f(s.map.covariance);
    // Format without the writer's checks: the covariance lines written by hand.
    std::string t = formatSessionState(good);
    const auto from = t.find("matrix covariance 6 6\n") + 22;
    const auto to = t.find("ints sightings");
    std::string rows;
    for (Eigen::Index r = 0; r < 6; ++r) {
      for (Eigen::Index c = 0; c < 6; ++c) {
        char buf[40];
        std::snprintf(buf, sizeof buf, "%.17g", s.map.covariance(r, c));
        rows += buf;
        rows += c == 5 ? '\n' : ' ';
      }
    }
    t.replace(from, to - from, rows);
    return readError(withChecksum(t));
  };
  EXPECT_EQ(edit([](Eigen::MatrixXd&) {}), "no error");
  EXPECT_EQ(edit([](Eigen::MatrixXd& m) {
              m(1, 4) = 0.5;
              m(4, 1) = 0.25;
            }),
            "session state 's.txt': line 19: section 'landmarks', field 'covariance': not "
            "symmetric (row 2, column 5 is 0.5, row 5, column 2 is 0.25)");
  // Round-off asymmetry passes (relative 1e-9 of the diagonal's scale).
  EXPECT_EQ(edit([](Eigen::MatrixXd& m) { m(1, 4) = m(4, 1) * (1 + 1e-12); }), "no error");
  EXPECT_EQ(edit([](Eigen::MatrixXd& m) { m(2, 2) = 0; }),
            "session state 's.txt': line 19: section 'landmarks', field 'covariance': not positive "
            "definite (diagonal entry 3 is 0)");
  EXPECT_EQ(edit([](Eigen::MatrixXd& m) {
              m(0, 1) = m(1, 0) = 2 * std::sqrt(m(0, 0) * m(1, 1));  // correlation 2
            }),
            "session state 's.txt': line 19: section 'landmarks', field 'covariance': not positive "
            "definite");
}

TEST(SessionHostile, TruncatedAtEveryByteIsAnErrorNeverACrash) {
  const std::string& g = goodText();
  ASSERT_EQ(readError(g), "no error");
  for (std::size_t n = 0; n < g.size(); ++n) {
    const std::string e = readError(g.substr(0, n));
    ASSERT_NE(e, "no error") << n;
    ASSERT_EQ(e.rfind("session state 's.txt': ", 0), 0u) << e;
    ASSERT_EQ(e.find('\n'), std::string::npos) << e;
  }
  // Cut inside a line and after one, with the section and field named.
  EXPECT_EQ(readError(g.substr(0, g.find("ints sightings") - 5)),
            "session state 's.txt': truncated inside line 25 (section 'landmarks', field "
            "'covariance')");
  const auto after_cov_row = g.find('\n', g.find("matrix covariance 6 6\n") + 22) + 1;
  EXPECT_EQ(readError(g.substr(0, after_cov_row)),
            "session state 's.txt': truncated after line 20 (section 'landmarks', field "
            "'covariance'); the end line is missing");
  EXPECT_EQ(readError(g.substr(0, g.find("[landmarks]"))),
            "session state 's.txt': truncated after line 13 (section 'resume_options'); the end "
            "line is missing");
  EXPECT_EQ(readError(g.substr(0, g.size() - 1)),
            "session state 's.txt': truncated inside line 59 (the end line)");
  EXPECT_EQ(readError(g.substr(0, 10)), "session state 's.txt': truncated inside line 1");
}

TEST(SessionHostile, DeclaredSizesAreBoundedBeforeAllocating) {
  const std::string& g = goodText();
  // More than the file can hold: refused before the vector is made.
  EXPECT_EQ(readError(replaced(g, "ints ids 3\n", "ints ids 1000000000000\n")),
            "session state 's.txt': line 15: section 'landmarks', field 'ids': 1000000000000 "
            "values, more than a map of 2000 landmarks needs (16016000 in all)");
  EXPECT_EQ(readError(replaced(g, "ints ids 3\n", "ints ids 100000\n")),
            "session state 's.txt': line 15: section 'landmarks', field 'ids': 100000 values, more "
            "than the rest of the file can hold (truncated or corrupt)");
  EXPECT_EQ(readError(replaced(g, "matrix covariance 6 6\n",
                               "matrix covariance 99999999999 99999999999\n")),
            "session state 's.txt': line 19: section 'landmarks', field 'covariance': 99999999999 "
            "x 99999999999 values, more than the rest of the file can hold (truncated or corrupt)");
  EXPECT_EQ(readError(replaced(g, "matrix covariance 6 6\n",
                               "matrix covariance 18446744073709551615 2\n")),
            "session state 's.txt': line 19: section 'landmarks', field 'covariance': "
            "18446744073709551615 x 2 values, more than the rest of the file can hold (truncated "
            "or corrupt)");
  EXPECT_EQ(
      readError(replaced(g, "ints ids 3\n", "ints ids -3\n")),
      "session state 's.txt': line 15: section 'landmarks', field 'ids': '-3' is not a count");
  SessionLimits small;
  small.max_landmarks = 2;
  EXPECT_EQ(readError(g, small),
            "session state 's.txt': line 19: section 'landmarks', field 'covariance': 36 values, "
            "more than a map of 2 landmarks needs (32 in all)");
  small.max_landmarks = 3;
  small.max_section_values = 9;
  EXPECT_EQ(readError(g, small),
            "session state 's.txt': line 51: section 'budget', field 'scores': 3 values, more than "
            "the 9 this section may hold");
  small = {};
  small.max_values = 50;
  EXPECT_EQ(readError(g, small),
            "session state 's.txt': line 19: section 'landmarks', field 'covariance': 36 values, "
            "more than the 50 a session state may hold");
  small = {};
  small.max_line_bytes = 120;
  EXPECT_EQ(readError(g, small),
            "session state 's.txt': line 23: section 'landmarks', field 'covariance': longer than "
            "120 bytes");
  small = {};
  small.max_sections = 5;
  EXPECT_EQ(readError(g, small), "session state 's.txt': line 54: more than 5 sections");
  small = {};
  small.max_fields = 4;
  EXPECT_EQ(readError(g, small),
            "session state 's.txt': line 8: section 'session': more than 4 fields");
}

// Issue 36 case 3: a state that leaves no room for the sessions and steps to come (a resumed run
// adds to these and writes them as int64) is refused, naming the field.
TEST(SessionHostile, CountersLeaveRoomForTheNextSession) {
  const std::string& g = goodText();
  EXPECT_EQ(
      readError(withChecksum(replaced(g, "int sessions 2", "int sessions 9223372036854775807"))),
      "session state 's.txt': line 7: section 'session', field 'sessions': "
      "9223372036854775807 is out of range [1, 1099511627776]");
  EXPECT_EQ(
      readError(
          withChecksum(replaced(g, "int next_step 250", "int next_step 9223372036854775800"))),
      "session state 's.txt': line 9: section 'session', field 'next_step': 9223372036854775800 "
      "is out of range [100, 9007199254740992]");
  EXPECT_EQ(
      readError(withChecksum(replaced(g, "int first_step 100", "int first_step 9007199254740993"))),
      "session state 's.txt': line 8: section 'session', field 'first_step': "
      "9007199254740993 is out of range [0, 9007199254740992]");
}

// Issue 35 case 7: the rawlog's path may hold any byte a file name may (a newline, a backslash,
// bytes that are not UTF-8): written escaped on one line, read back the same.
TEST(SessionHostile, AnyRawlogPathRoundTrips) {
  for (const std::string& path :
       {std::string("runs/demo\nsecond line.rawlog"), std::string("a\\b\\x41.rawlog"),
        std::string("bad\xff\xfe utf8 \xc3\xa9.rawlog"), std::string("tab\there\x7f.rawlog")}) {
    SessionState s = sampleState(3);
    s.header.rawlog = path;
    const std::string text = formatSessionState(s);
    EXPECT_EQ(readSessionStateBytes("s.txt", text).header.rawlog, path);
  }
  SessionState s = sampleState(3);
  s.header.rawlog = "x\ny";
  EXPECT_NE(formatSessionState(s).find("text rawlog x\\x0ay\n"), std::string::npos);
  EXPECT_EQ(readError(withChecksum(replaced(goodText(), "text rawlog rawlogs/rooms.rawlog",
                                            "text rawlog rawlogs\\rooms.rawlog"))),
            "session state 's.txt': line 6: section 'session', field 'rawlog': '\\' at byte 8 is "
            "not an escape ('\\\\' or '\\xNN')");
}
