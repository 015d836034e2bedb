// Issue 17 item 3: every output of a command is committed together (all new or all old), hidden
// temporaries never survive a failure, a signal or the next run (core/atomic_file.h).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <thread>

#include "core/atomic_file.h"
#include "core/error.h"
#include "robustness_support.h"
#include "support/testing.h"

namespace {

using namespace nf::robustness;

// A rename failing in the middle of commit (the second target became a directory) restores the
// first target's previous contents and removes every temporary.
TEST(RobustnessOutputs, FailedCommitKeepsEveryOldFile) {
  const auto dir = nf::testing::temp_dir("tx_rollback");
  write(dir, "a.txt", "old a");
  nf::OutputTransaction tx;
  nf::write_text(tx, dir / "a.txt", "new a");
  nf::write_text(tx, dir / "b.txt", "new b");
  std::filesystem::create_directories(dir / "b.txt" / "occupied");  // rename onto it fails
  try {
    tx.commit();
    FAIL() << "commit succeeded";
  } catch (const nf::Error& e) {
    EXPECT_NE(std::string(e.what()).find("b.txt"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find("nftmp"), std::string::npos) << e.what();
  }
  EXPECT_EQ(slurp(dir / "a.txt"), "old a");
  EXPECT_TRUE(temporaries(dir).empty());
}

TEST(RobustnessOutputs, CommitReplacesAllAndAbandonRemovesAll) {
  const auto dir = nf::testing::temp_dir("tx_ok");
  write(dir, "a.txt", "old a");
  {
    nf::OutputTransaction tx;
    nf::write_text(tx, dir / "a.txt", "new a");
    nf::write_text(tx, dir / "b.txt", "new b");
    tx.commit();
  }
  EXPECT_EQ(slurp(dir / "a.txt"), "new a");
  EXPECT_EQ(slurp(dir / "b.txt"), "new b");
  {
    nf::OutputTransaction tx;
    nf::write_text(tx, dir / "a.txt", "newer a");
  }  // destroyed uncommitted
  EXPECT_EQ(slurp(dir / "a.txt"), "new a");
  EXPECT_TRUE(temporaries(dir).empty());
}

// The case: `render -o X.exr --png Y.png` where Y.png cannot be written must keep X.exr.
TEST(RobustnessOutputs, RenderKeepsTheOldExrWhenThePngCannotBeWritten) {
  const auto dir = nf::testing::temp_dir("render_png_fails");
  const auto scene = write(dir, "s.json", small_scene(32, 20));
  write(dir, "x.exr", "previous exr");
  std::filesystem::create_directories(dir / "y.png");
  const auto r = nf::testing::run_nearfield("render " + q(scene) + " -o " + q(dir / "x.exr") + " --png " +
                                            q(dir / "y.png"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("y.png"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(dir / "x.exr"), "previous exr");
  EXPECT_TRUE(temporaries(dir).empty());
}

// `luminaire gen` whose manifest cannot be placed keeps the previous EXR.
TEST(RobustnessOutputs, LuminaireGenKeepsTheOldExrWhenTheManifestCannotBeWritten) {
  const auto dir = nf::testing::temp_dir("gen_manifest_fails");
  write(dir, "panel.exr", "previous exr");
  std::filesystem::create_directories(dir / "panel.json");
  const auto r = nf::testing::run_nearfield("luminaire gen --preset panel --res-scale 0.2 -o " + q(dir));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("panel.json"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(dir / "panel.exr"), "previous exr");
  EXPECT_TRUE(temporaries(dir).empty());
}

// Temporaries of dead processes (earlier names too) are removed by the next run in that
// directory; those of live processes (this test's own pid) are left alone.
TEST(RobustnessOutputs, StaleTemporariesOfDeadRunsAreRemoved) {
  const auto dir = nf::testing::temp_dir("stale");
  int dead = 0;
  {
    const pid_t child = fork();
    if (child == 0) _exit(0);
    waitpid(child, nullptr, 0);
    dead = child;  // reaped: no process has this pid now (reuse within the test is negligible)
  }
  const std::string alive = std::to_string(getpid());
  write(dir, ".big.tmp" + std::to_string(dead) + "-0.exr", "stale, old name");
  write(dir, ".car2.nftmp" + std::to_string(dead) + "-3.exr", "stale");
  write(dir, ".x.nfbak" + std::to_string(dead) + "-1.png", "stale backup");
  write(dir, ".live.nftmp" + alive + "-0.exr", "in use");
  write(dir, ".notours.tmp", "unrelated");
  const auto r = nf::testing::run_nearfield("luminaire gen --preset panel --res-scale 0.2 -o " + q(dir));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(temporaries(dir), (std::set<std::string>{".live.nftmp" + alive + "-0.exr", ".notours.tmp"}));
}

// SIGTERM while a large EXR is being written: the temporary is removed, nothing else appears.
TEST(RobustnessOutputs, SigtermRemovesTheTemporaries) {
  const auto dir = nf::testing::temp_dir("sigterm");
  const pid_t child = fork();
  if (child == 0) {
    const std::string out = dir.string();
    ::freopen("/dev/null", "w", stdout);
    ::freopen("/dev/null", "w", stderr);
    execl(NEARFIELD_BINARY, NEARFIELD_BINARY, "luminaire", "gen", "--preset", "car2", "--res-scale", "1.5", "-o",
          out.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  bool seen = false;
  const auto start = std::chrono::steady_clock::now();
  int status = 0;
  while (std::chrono::steady_clock::now() - start < std::chrono::seconds(300)) {
    if (!temporaries(dir).empty()) {
      seen = true;
      break;
    }
    if (waitpid(child, &status, WNOHANG) == child) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  if (!seen) {
    kill(child, SIGKILL);
    waitpid(child, &status, 0);
    FAIL() << "the writer never showed a temporary (finished too fast?)";
  }
  kill(child, SIGTERM);
  waitpid(child, &status, 0);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << status;
  EXPECT_TRUE(temporaries(dir).empty());
  EXPECT_FALSE(std::filesystem::exists(dir / "car2.json"));
}

}  // namespace
