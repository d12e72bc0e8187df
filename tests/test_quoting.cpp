// The quoting rules of the output languages (src/io/quoting.hpp): exact outputs, and gnuplot
// itself reading the literals back as the visible text, running nothing.
#include "io/quoting.hpp"

#include <gtest/gtest.h>

#include <unistd.h>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

using linx::io::gnuplotString;
using linx::io::povComment;
using linx::io::povString;
using linx::io::visible;
using namespace std::string_literals;

namespace fs = std::filesystem;

TEST(Visible, ControlCharactersAndNulAreShownAsEscapes) {
  EXPECT_EQ(visible("a\x1b[2Jb"), "a\\x1b[2Jb");
  EXPECT_EQ(visible("a\0b"s), "a\\0b");
  EXPECT_EQ(visible("l1\nl2\r\t|"), "l1\\nl2\\r\\t|");
  EXPECT_EQ(visible("\x07\x7f"), "\\x07\\x7f");
}

TEST(Visible, ValidUtf8IsKept) {
  EXPECT_EQ(visible("pendule \xc3\xa9t\xc3\xa9 \xe6\x97\xa5 \xf0\x9f\x99\x82"),
            "pendule \xc3\xa9t\xc3\xa9 \xe6\x97\xa5 \xf0\x9f\x99\x82");
  EXPECT_EQ(visible("plain `name` $(x) @m \"q\" \\"), "plain `name` $(x) @m \"q\" \\");
}

TEST(Visible, BytesThatAreNotUtf8AreShownAsHex) {
  EXPECT_EQ(visible("\xff\xc3"), "\\xff\\xc3");                    // stray byte, cut sequence
  EXPECT_EQ(visible("\xc0\xaf"), "\\xc0\\xaf");                    // overlong '/'
  EXPECT_EQ(visible("\xed\xa0\x80"), "\\xed\\xa0\\x80");           // a surrogate
  EXPECT_EQ(visible("\xf4\x90\x80\x80"), "\\xf4\\x90\\x80\\x80");  // past U+10FFFF
  EXPECT_EQ(visible("\x80x"), "\\x80x");
}

TEST(Visible, TerminalAndBidiControlCodePointsAreShownAsU) {
  EXPECT_EQ(visible("\xc2\x9b"
                    "2J"),
            "\\u009b2J");  // C1 CSI
  EXPECT_EQ(visible("a\xe2\x80\xae"
                    "b"),
            "a\\u202eb");                         // right-to-left override
  EXPECT_EQ(visible("\xe2\x80\xa8"), "\\u2028");  // line separator
  EXPECT_EQ(visible("\xe2\x81\xa6"), "\\u2066");  // left-to-right isolate
}

TEST(Visible, IsIdempotentAndOneLine) {
  const std::string hostile = "a\x1b]0;t\x07\n\0\xff\xc2\x85 \xe2\x80\xae"s;
  const std::string once = visible(hostile);
  EXPECT_EQ(visible(once), once);
  for (const char c : once) {
    EXPECT_GE(static_cast<unsigned char>(c), 0x20);
    EXPECT_NE(c, '\x7f');
  }
}

TEST(GnuplotString, EveryByteButPlainOnesIsAnOctalEscape) {
  EXPECT_EQ(gnuplotString("pivot`id > owned` (hinge)"),
            "\"pivot\\140id \\076 owned\\140 (hinge)\"");
  EXPECT_EQ(gnuplotString("a\"b\\c@m$x%y'z"), "\"a\\042b\\134c\\100m\\044x\\045y\\047z\"");
  EXPECT_EQ(gnuplotString("\xc3\xa9"), "\"\\303\\251\"");
  // Shown as visible() shows it first: a newline is the two characters \ and n.
  EXPECT_EQ(gnuplotString("x\ny"), "\"x\\134ny\"");
  EXPECT_EQ(gnuplotString(""), "\"\"");
  EXPECT_EQ(gnuplotString("Joint errors (2 joints; all zero, linear scale)"),
            "\"Joint errors (2 joints; all zero, linear scale)\"");
}

TEST(PovRay, CommentsHoldNoLineEndAndStringsAreEscaped) {
  EXPECT_EQ(povComment("a\nb\r#declare X = 1; */ /*"), "a\\nb\\r#declare X = 1; */ /*");
  EXPECT_EQ(povString("scene.inc"), "\"scene.inc\"");
  EXPECT_EQ(povString("a\"b\\c\n"), "\"a\\\"b\\\\c\\\\n\"");
}

// gnuplot reads each literal back as visible(text) and substitutes nothing: no backquoted
// command runs, no macro or variable is expanded.
TEST(GnuplotString, GnuplotReadsItBackAsTheVisibleText) {
  if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) GTEST_SKIP() << "no gnuplot";
  const fs::path dir = fs::temp_directory_path() / ("linx_quoting_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path canary = dir / "CANARY";
  const std::vector<std::string> texts = {
      "pivot`id > owned`",
      "`touch " + canary.string() + "`",
      "$(touch " + canary.string() + ")",
      "@m and @m@",
      "q\"u'o\\te\\\" \\",
      "two\nlines\r\tand \x1b[2J \0 nul"s,
      "\xc3\xa9t\xc3\xa9 \xe6\x97\xa5 \xff\xfe",
      "%s %d {} #comment ; print 'x'",
  };
  std::string script = "m = \"system('touch " + canary.string() + "')\"\n";
  for (const std::string& t : texts) script += "print " + gnuplotString(t) + "\n";
  std::ofstream(dir / "t.gp") << script;
  const std::string command = "cd '" + dir.string() + "' && gnuplot t.gp > out.txt 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << script;
  std::ifstream in(dir / "out.txt");
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), texts.size());
  for (std::size_t i = 0; i < texts.size(); ++i) EXPECT_EQ(lines[i], visible(texts[i]));
  EXPECT_FALSE(fs::exists(canary));
  fs::remove_all(dir);
}

// Any byte string: visible() holds no control byte and is idempotent; gnuplotString() holds only
// plain bytes and three-digit octal escapes between its quotes; povComment() no line end.
TEST(Quoting, AnyBytesComeOutInert) {
  std::mt19937 random(43);
  for (int trial = 0; trial < 20000; ++trial) {
    std::string text(random() % 24, '\0');
    for (char& c : text) c = static_cast<char>(random() % 256);
    const std::string shown = visible(text);
    for (const char c : shown) ASSERT_TRUE(static_cast<unsigned char>(c) >= 0x20 && c != 0x7f);
    ASSERT_EQ(visible(shown), shown);
    const std::string literal = gnuplotString(text);
    ASSERT_GE(literal.size(), 2u);
    ASSERT_EQ(literal.front(), '"');
    ASSERT_EQ(literal.back(), '"');
    for (std::size_t i = 1; i + 1 < literal.size(); ++i) {
      const char c = literal[i];
      if (c != '\\') {
        const bool plain = std::isalnum(static_cast<unsigned char>(c)) ||
                           std::string_view(" .,:;_-+=()/").find(c) != std::string_view::npos;
        ASSERT_TRUE(plain) << literal;
        continue;
      }
      ASSERT_LT(i + 3, literal.size()) << literal;
      for (std::size_t k = 1; k <= 3; ++k)
        ASSERT_TRUE(literal[i + k] >= '0' && literal[i + k] <= '7');
      i += 3;
    }
    ASSERT_EQ(povComment(text).find_first_of("\n\r"), std::string::npos);
  }
}
