#include "pipeline/progress_reporter.h"

#include <chrono>
#include <sstream>
#include <string>

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace fitbase::pipeline {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;
using namespace std::chrono_literals;

// A clock that only moves when the test says so.
class FakeClock {
 public:
  ProgressReporter::Clock AsClock() {
    return [this] { return now_; };
  }
  void Advance(std::chrono::steady_clock::duration d) { now_ += d; }

 private:
  std::chrono::steady_clock::time_point now_{std::chrono::hours(1000)};
};

TEST(ProgressReporterTest, LineShowsCountElapsedAndEta) {
  FakeClock clock;
  std::ostringstream out;
  ProgressReporter progress("avatars", 40, out, /*is_terminal=*/false, clock.AsClock());
  clock.Advance(5s);
  progress.Update(10);
  // 10 items in 5 s: the remaining 30 take 15 s.
  EXPECT_EQ(progress.Line(), "avatars 10/40  elapsed 5.0s  ETA 15.0s");
  clock.Advance(5s);
  progress.Update(30);
  // 30 items in 10 s: the remaining 10 take 3.3 s.
  EXPECT_EQ(progress.Line(), "avatars 30/40  elapsed 10.0s  ETA 3.3s");
}

// Items found done at the start (a cache's) are counted but do not speed up the ETA.
TEST(ProgressReporterTest, EtaFromTheItemsDoneSinceTheStart) {
  FakeClock clock;
  std::ostringstream out;
  ProgressReporter progress("drapes", 100, out, /*is_terminal=*/false, clock.AsClock());
  progress.Resume(60);
  EXPECT_EQ(progress.Line(), "drapes 60/100  elapsed 0.0s  (60 at start)");
  clock.Advance(10s);
  progress.Update(70);
  // 10 items in 10 s: the remaining 30 take 30 s, not the 4.3 s of 70 items in 10 s.
  EXPECT_EQ(progress.Line(), "drapes 70/100  elapsed 10.0s  ETA 30.0s  (60 at start)");
  progress.Update(100);
  EXPECT_EQ(progress.Line(), "drapes 100/100  elapsed 10.0s  (60 at start)");
}

TEST(ProgressReporterTest, NoEtaBeforeTheFirstItemOrAfterTheLast) {
  FakeClock clock;
  std::ostringstream out;
  ProgressReporter progress("reading", 4, out, false, clock.AsClock());
  clock.Advance(1500ms);
  EXPECT_EQ(progress.Line(), "reading 0/4  elapsed 1.5s");
  progress.Update(4);
  EXPECT_EQ(progress.Line(), "reading 4/4  elapsed 1.5s");
}

TEST(ProgressReporterTest, LongDurationsUseMinutesAndHours) {
  FakeClock clock;
  std::ostringstream out;
  ProgressReporter progress("basis", 3, out, false, clock.AsClock());
  clock.Advance(100s);
  progress.Update(1);
  EXPECT_EQ(progress.Line(), "basis 1/3  elapsed 1m40s  ETA 3m20s");
  clock.Advance(3600s);
  progress.Update(2);
  // 3700 s for 2 items: the last takes 1850 s.
  EXPECT_EQ(progress.Line(), "basis 2/3  elapsed 1h01m40s  ETA 30m50s");
}

TEST(ProgressReporterTest, NonTerminalPrintsOnlyTheFinalLineOnShortRuns) {
  FakeClock clock;
  std::ostringstream out;
  ProgressReporter progress("avatars", 3, out, /*is_terminal=*/false, clock.AsClock());
  for (int i = 1; i <= 3; ++i) {
    clock.Advance(2s);
    progress.Update(i);
    EXPECT_EQ(out.str(), "") << "after item " << i;
  }
  progress.Finish();
  EXPECT_EQ(out.str(), "avatars 3/3  elapsed 6.0s\n");
  EXPECT_THAT(out.str(), Not(HasSubstr("\r")));
  EXPECT_THAT(out.str(), Not(HasSubstr("\033")));
}

TEST(ProgressReporterTest, NonTerminalPrintsALineAMinuteOnLongRuns) {
  FakeClock clock;
  std::ostringstream out;
  ProgressReporter progress("drapes", 4, out, /*is_terminal=*/false, clock.AsClock());
  clock.Advance(50s);
  progress.Update(1);
  EXPECT_EQ(out.str(), "");
  clock.Advance(20s);
  progress.Update(2);
  EXPECT_EQ(out.str(), "drapes 2/4  elapsed 1m10s  ETA 1m10s\n");
  clock.Advance(30s);
  progress.Update(3);
  EXPECT_EQ(out.str(), "drapes 2/4  elapsed 1m10s  ETA 1m10s\n");
  clock.Advance(60s);
  progress.Update(4);
  progress.Finish();
  EXPECT_EQ(out.str(), "drapes 2/4  elapsed 1m10s  ETA 1m10s\ndrapes 4/4  elapsed 2m40s\n");
}

TEST(ProgressReporterTest, TerminalRedrawsInPlace) {
  FakeClock clock;
  std::ostringstream out;
  ProgressReporter progress("avatars", 40, out, /*is_terminal=*/true, clock.AsClock());
  clock.Advance(5s);
  progress.Update(10);
  EXPECT_EQ(out.str(), "\ravatars 10/40  elapsed 5.0s  ETA 15.0s\033[K");

  out.str("");
  clock.Advance(5s);
  progress.Update(20);
  EXPECT_EQ(out.str(), "\ravatars 20/40  elapsed 10.0s  ETA 10.0s\033[K");

  out.str("");
  progress.Finish();
  EXPECT_EQ(out.str(), "\ravatars 20/40  elapsed 10.0s  ETA 10.0s\033[K\n");
}

TEST(ProgressReporterTest, TerminalRedrawsAtMostEvery100MsExceptTheLastItem) {
  FakeClock clock;
  std::ostringstream out;
  ProgressReporter progress("avatars", 3, out, /*is_terminal=*/true, clock.AsClock());
  clock.Advance(10ms);
  progress.Update(1);  // Too soon after the start.
  EXPECT_EQ(out.str(), "");
  clock.Advance(190ms);
  progress.Update(2);
  EXPECT_EQ(out.str(), "\ravatars 2/3  elapsed 0.2s  ETA 0.1s\033[K");
  out.str("");
  clock.Advance(1ms);
  progress.Update(3);  // Too soon, but the last item is always drawn.
  EXPECT_EQ(out.str(), "\ravatars 3/3  elapsed 0.2s\033[K");
}

}  // namespace
}  // namespace fitbase::pipeline
