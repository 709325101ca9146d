// Progress on stderr: nothing for a stage within a second or with --quiet, plain lines when stderr
// is not a terminal, a redrawn bar with count and rate when it is (a pseudo-terminal here).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <pty.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "polyaxis/core/progress.h"

namespace polyaxis::core {
namespace {

// Runs BODY with stderr (fd 2) sent to FD, then puts stderr back.
template <typename Body>
void with_stderr(int fd, Body body) {
  std::fflush(stderr);
  const int saved = dup(STDERR_FILENO);
  ASSERT_GE(saved, 0);
  ASSERT_GE(dup2(fd, STDERR_FILENO), 0);
  body();
  std::fflush(stderr);
  dup2(saved, STDERR_FILENO);
  close(saved);
}

std::string read_all(int fd) {
  std::string out;
  char buf[4096];
  for (;;) {
    const ssize_t n = read(fd, buf, sizeof buf);
    if (n <= 0) break;
    out.append(buf, static_cast<std::size_t>(n));
  }
  return out;
}

// A stage that lasts a little over the one-second threshold and reports 5 of 10, then ends.
void slow_stage() {
  Progress p("stage", 10);
  std::this_thread::sleep_for(std::chrono::milliseconds(1100));
  p.update(5);
}

std::string captured_through_file(void (*body)()) {
  std::FILE* f = std::tmpfile();
  EXPECT_NE(f, nullptr);
  with_stderr(fileno(f), body);
  std::fseek(f, 0, SEEK_SET);
  std::string out;
  for (int c = std::fgetc(f); c != EOF; c = std::fgetc(f)) out += static_cast<char>(c);
  std::fclose(f);
  return out;
}

TEST(Progress, PlainLinesWhenStderrIsNotATerminal) {
  set_progress_mode(ProgressMode::kAuto);
  const std::string out = captured_through_file(slow_stage);
  EXPECT_NE(out.find("stage: 5/10 ("), std::string::npos) << out;
  EXPECT_NE(out.find("stage: 10/10 ("), std::string::npos) << out;  // the end
  EXPECT_EQ(out.find('\r'), std::string::npos);
}

TEST(Progress, NothingForAShortStage) {
  set_progress_mode(ProgressMode::kAuto);
  const std::string out = captured_through_file([] {
    Progress p("quick", 10);
    p.update(10);
  });
  EXPECT_EQ(out, "");
}

TEST(Progress, NothingWhenQuiet) {
  set_progress_mode(ProgressMode::kQuiet);
  const std::string out = captured_through_file(slow_stage);
  set_progress_mode(ProgressMode::kAuto);
  EXPECT_EQ(out, "");
}

TEST(Progress, CountAndRateWhenTheTotalIsUnknown) {
  set_progress_mode(ProgressMode::kAuto);
  const std::string out = captured_through_file([] {
    Progress p("nodes", 0);
    std::this_thread::sleep_for(std::chrono::milliseconds(1100));
    p.update(7);
    p.update(9);  // within the plain-line interval: not shown until the end
  });
  EXPECT_NE(out.find("nodes: 7 ("), std::string::npos) << out;
  EXPECT_NE(out.find("nodes: 9 ("), std::string::npos) << out;  // the end is always shown
  EXPECT_EQ(out.find("/0"), std::string::npos) << out;
}

TEST(Progress, BarWithCountAndRateOnATerminal) {
  set_progress_mode(ProgressMode::kAuto);
  int master = -1, slave = -1;
  ASSERT_EQ(openpty(&master, &slave, nullptr, nullptr, nullptr), 0);
  with_stderr(slave, slow_stage);
  close(slave);
  fcntl(master, F_SETFL, O_NONBLOCK);
  const std::string out = read_all(master);
  close(master);
  EXPECT_NE(out.find("\rstage"), std::string::npos) << out;
  EXPECT_NE(out.find("[###############...............] 5/10"), std::string::npos) << out;
  EXPECT_NE(out.find("10/10"), std::string::npos) << out;
  EXPECT_NE(out.find("/s"), std::string::npos) << out;
}

// A callback in scope hears every stage made on its thread, from the start and at the end, and
// nothing reaches stderr; outside the scope, or on another thread, stderr is used again.
TEST(ProgressScope, TheCallbackInScopeHearsTheStagesInsteadOfStderr) {
  set_progress_mode(ProgressMode::kAuto);
  std::vector<std::pair<std::string, bool>> heard;
  std::uint64_t last_done = 0, last_total = 0;
  const auto record = [&](const ProgressEvent& e) {
    heard.emplace_back(std::string(e.stage), e.finished);
    last_done = e.done, last_total = e.total;
  };
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  with_stderr(fileno(f), [&] {
    ProgressScope scope(record);
    Progress p("quick", 4);
    p.update(2);
    p.update(3);  // within the interval: not sent
  });
  EXPECT_EQ(std::ftell(f), 0L);  // nothing on stderr
  std::fclose(f);
  ASSERT_EQ(heard.size(), 2u);
  EXPECT_EQ(heard[0], std::make_pair(std::string("quick"), false));
  EXPECT_EQ(heard[1], std::make_pair(std::string("quick"), true));
  EXPECT_EQ(last_done, 4u);
  EXPECT_EQ(last_total, 4u);
}

TEST(ProgressScope, ScopesNestAndStayOnTheirThread) {
  std::vector<std::string> outer, inner;
  {
    ProgressScope a([&](const ProgressEvent& e) { outer.emplace_back(e.stage); });
    {
      ProgressScope b([&](const ProgressEvent& e) { inner.emplace_back(e.stage); });
      Progress p("inner", 1);
      ProgressScope empty(ProgressCallback{});  // an empty callback keeps the current one
      Progress q("still inner", 1);
    }
    Progress r("outer", 1);
    std::thread([] {
      set_progress_mode(ProgressMode::kQuiet);  // the other thread reports to stderr, quietly here
      Progress s("elsewhere", 1);
      set_progress_mode(ProgressMode::kAuto);
    }).join();
  }
  // A task on another thread reports where the call does when it carries the scope's callback.
  {
    ProgressScope a([&](const ProgressEvent& e) { outer.emplace_back(e.stage); });
    std::thread([carried = ProgressScope::current()] {
      const ProgressScope scope(carried);
      Progress t("carried", 1);
    }).join();
  }
  // Each stage's end (no update came): the inner stages in the order they ended, then the outer.
  EXPECT_EQ(inner, (std::vector<std::string>{"still inner", "inner"}));
  EXPECT_EQ(outer, (std::vector<std::string>{"outer", "carried"}));
}

}  // namespace
}  // namespace polyaxis::core
