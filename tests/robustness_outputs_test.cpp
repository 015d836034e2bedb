// Issue 17 item 3: every output of a command is committed together (all new or all old), hidden
// temporaries never survive a failure, a signal or the next run (core/atomic_file.h).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <initializer_list>
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
  const auto r =
      nf::testing::run_nearfield("render " + q(scene) + " -o " + q(dir / "x.exr") + " --png " + q(dir / "y.png"));
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

// Issue 28 item 1: `luminaire farfield -o` must name a new .ies file. The manifest, its EXR (by
// name, symlink or hard link), another extension, a directory, a missing or read-only directory
// are refused before any work, naming the file and the problem; every existing file stays as it was.
TEST(RobustnessOutputs, FarfieldRefusesOutputsThatAreNotANewIesFile) {
  const auto dir = nf::testing::temp_dir("farfield_outputs");
  const auto gen = nf::testing::run_nearfield("luminaire gen --preset panel --res-scale 0.2 -o " + q(dir));
  ASSERT_EQ(gen.exit_code, 0) << gen.err;
  const auto manifest = dir / "panel.json", exr = dir / "panel.exr";
  const std::string manifest_text = slurp(manifest), exr_bytes = slurp(exr);
  std::filesystem::create_symlink(manifest, dir / "link.ies");
  std::filesystem::create_hard_link(exr, dir / "hard.ies");
  std::filesystem::create_directories(dir / "folder.ies");
  write(dir, "other.txt", "keep me");
  struct Case {
    std::filesystem::path out;
    std::initializer_list<const char*> says;
  };
  const Case cases[] = {
      {manifest, {"panel.json", "must end in .ies"}},
      {exr, {"panel.exr", "must end in .ies"}},
      {dir / "other.txt", {"other.txt", "must end in .ies"}},
      {dir / "link.ies", {"link.ies", "refusing to overwrite", "panel.json", "an input of the light field"}},
      {dir / "hard.ies", {"hard.ies", "refusing to overwrite", "panel.exr"}},
      {dir / "folder.ies", {"folder.ies", "is a directory"}},
      {dir / "missing" / "x.ies", {"x.ies", "missing", "does not exist"}},
  };
  for (const auto& c : cases) {
    const auto r = nf::testing::run_nearfield("luminaire farfield " + q(manifest) + " -o " + q(c.out));
    EXPECT_NE(r.exit_code, 0) << c.out;
    for (const char* part : c.says) EXPECT_NE(r.err.find(part), std::string::npos) << part << " not in: " << r.err;
    EXPECT_EQ(slurp(manifest), manifest_text) << c.out;
    EXPECT_EQ(slurp(exr), exr_bytes) << c.out;
    EXPECT_TRUE(std::filesystem::is_symlink(dir / "link.ies"));
    EXPECT_EQ(slurp(dir / "other.txt"), "keep me");
    EXPECT_TRUE(temporaries(dir).empty());
  }
  if (geteuid() != 0) {  // root may write anywhere
    const auto ro = dir / "readonly";
    std::filesystem::create_directories(ro);
    std::filesystem::permissions(ro, std::filesystem::perms::owner_read | std::filesystem::perms::owner_exec);
    const auto r = nf::testing::run_nearfield("luminaire farfield " + q(manifest) + " -o " + q(ro / "x.ies"));
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find("is not writable"), std::string::npos) << r.err;
    std::filesystem::permissions(ro, std::filesystem::perms::owner_all);
  }
  // The extension is case-insensitive; a new file next to the inputs is fine.
  const auto ok = nf::testing::run_nearfield("luminaire farfield " + q(manifest) + " -o " + q(dir / "far.IES"));
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_EQ(slurp(dir / "far.IES").rfind("IESNA:LM-63-2002", 0), 0u);
  EXPECT_EQ(slurp(manifest), manifest_text);
}

// `luminaire gen|import -o DIR` where DIR is an existing file (or lies under one) fails before the
// work: the import's ray file here is not even readable as rays, and the error is about -o.
TEST(RobustnessOutputs, GenAndImportRefuseAFileAsTheirOutputDirectory) {
  const auto dir = nf::testing::temp_dir("gen_import_outputs");
  const auto file = write(dir, "occupied", "a file");
  const auto rays = write(dir, "rays.ray", "not a ray file");
  const std::string runs[] = {
      "luminaire gen --preset panel --res-scale 0.2 -o " + q(file),
      "luminaire gen --preset panel --res-scale 0.2 -o " + q(file / "sub"),
      "luminaire import " + q(rays) + " -o " + q(file),
      "luminaire import " + q(rays) + " -o " + q(file / "sub"),
  };
  for (const auto& args : runs) {
    const auto r = nf::testing::run_nearfield(args);
    EXPECT_NE(r.exit_code, 0) << args;
    EXPECT_NE(r.err.find("-o " + file.string()), std::string::npos) << r.err;
    EXPECT_TRUE(r.err.find("is an existing file, expected a directory") != std::string::npos ||
                r.err.find("is not a directory") != std::string::npos)
        << r.err;
    EXPECT_EQ(slurp(file), "a file");
  }
  std::filesystem::create_directories(dir / "out" / "panel.json");
  const auto r = nf::testing::run_nearfield("luminaire gen --preset panel --res-scale 0.2 -o " + q(dir / "out"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("panel.json: is a directory"), std::string::npos) << r.err;
}

}  // namespace
