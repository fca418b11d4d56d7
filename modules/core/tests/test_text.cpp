#include <gtest/gtest.h>

#include <stdexcept>

#include "budget_slam/core/Text.h"

using namespace budget_slam;

TEST(Text, Utf8Validation) {
  std::size_t bad = 0;
  EXPECT_TRUE(isValidUtf8("plain ascii"));
  EXPECT_TRUE(isValidUtf8("caf\xC3\xA9 \xE2\x82\xAC \xF0\x9F\x98\x80"));
  EXPECT_FALSE(isValidUtf8("ab\xFFz", &bad));
  EXPECT_EQ(bad, 2u);
  EXPECT_FALSE(isValidUtf8("\xC0\xAF"));          // overlong '/'
  EXPECT_FALSE(isValidUtf8("\xED\xA0\x80"));      // UTF-16 surrogate
  EXPECT_FALSE(isValidUtf8("\xF4\x90\x80\x80"));  // past U+10FFFF
  EXPECT_FALSE(isValidUtf8("\xE2\x82"));          // cut short
}

TEST(Text, PrintableIsOneLineOfValidUtf8) {
  EXPECT_EQ(printable("ok \xC3\xA9"), "ok \xC3\xA9");
  // Unicode's own line breaks and C1 controls (NEL) are escaped too: one line on any terminal.
  EXPECT_EQ(printable("a\xC2\x85"
                      "b\xE2\x80\xA8"
                      "c\xE2\x80\xA9"),
            "a\\xc2\\x85b\\xe2\\x80\\xa8c\\xe2\\x80\\xa9");
  EXPECT_EQ(printable(std::string("a\nb\0c\xFF", 6)), "a\\x0ab\\x00c\\xff");
  EXPECT_TRUE(isValidUtf8(printable("\x80\x81\xFE\xFF mrpt::obs::C\xC1\xC2")));
  EXPECT_EQ(excerpt("abcdefghij", 4), "abcd...");
  EXPECT_EQ(excerpt("\xC3\xA9\xC3\xA9\xC3\xA9", 3), "\xC3\xA9...");  // never inside a character
}

TEST(Text, MrptExceptionDumpsBecomeTheirMessageLine) {
  const std::string dump =
      "==== MRPT exception ====\n"
      "Message:  Invalid value 'bogus' for enum type while reading key='method'.\n"
      "Location: /usr/include/mrpt/config/CConfigFileBase.h:287: [read_enum]\n"
      "Call stack backtrace:\n[0 ] (unknown file) mrpt::bayes::TKF_options::loadFromConfigFile\n";
  EXPECT_EQ(exceptionLine(dump), "Invalid value 'bogus' for enum type while reading key='method'.");
  EXPECT_EQ(exceptionLine(std::runtime_error("Line 2: Unknown variable `${NOPE}`\nmore")),
            "Line 2: Unknown variable `${NOPE}`");
  EXPECT_EQ(exceptionLine("\n\n"), "unknown error");
}

TEST(Text, LowerAsciiLowersLettersOnlyAndLeavesOtherBytes) {
  EXPECT_EQ(budget_slam::lowerAscii("LandmarkBudget.Max_Landmarks"),
            "landmarkbudget.max_landmarks");
  EXPECT_EQ(budget_slam::lowerAscii("\xC3\x89T\xC3\xA9[1]"), "\xC3\x89t\xC3\xA9[1]");
}
