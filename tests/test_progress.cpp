// The progress bar of `linx run`: its text, its throttled redraws and its erasure.
#include "progress.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

namespace {

// Everything written to a temporary file so far.
std::string contents(std::FILE* f) {
  std::fflush(f);
  std::rewind(f);
  std::string text;
  for (int c; (c = std::fgetc(f)) != EOF;) text += static_cast<char>(c);
  return text;
}

TEST(Progress, Render) {
  EXPECT_EQ(linx::cli::renderProgress(0, 200, 0.0, 5.0, 10), "[          ]   0%  t = 0 / 5 s");
  EXPECT_EQ(linx::cli::renderProgress(90, 200, 2.25, 5.0, 10), "[####      ]  45%  t = 2.25 / 5 s");
  EXPECT_EQ(linx::cli::renderProgress(200, 200, 5.0, 5.0, 10), "[##########] 100%  t = 5 / 5 s");
  EXPECT_EQ(linx::cli::renderProgress(0, 0, 0.0, 0.0, 4), "[####] 100%  t = 0 / 0 s");
}

TEST(Progress, RedrawsAtMostTenTimesASecondAndAlwaysAtTheEnd) {
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  {
    linx::cli::ProgressBar bar(f, 1000, 1.0);
    bar.update(1, 0.001);
    bar.update(2, 0.002);   // within 100 ms of the first: skipped
    bar.update(1000, 1.0);  // the last step: drawn
    const std::string text = contents(f);
    EXPECT_EQ(text, "\r\033[K" + linx::cli::renderProgress(1, 1000, 0.001, 1.0) + "\r\033[K" +
                        linx::cli::renderProgress(1000, 1000, 1.0, 1.0));
    std::fseek(f, 0, SEEK_END);
  }
  // The destructor erases the bar.
  const std::string text = contents(f);
  EXPECT_EQ(text.substr(text.size() - 4), "\r\033[K");
  std::fclose(f);
}

}  // namespace
