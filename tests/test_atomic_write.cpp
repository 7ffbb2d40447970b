#include "modeling/atomic_write.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "modeling/errors.h"

namespace flexure::modeling {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

fs::path freshDir(const std::string& name) {
  const fs::path dir = fs::path(FLEXURE_TEST_TMP) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

TEST(AtomicWrite, WritesAndReplacesLeavingNoTemporaries) {
  const fs::path dir = freshDir("atomic_write");
  const fs::path file = dir / "out.txt";
  writeFileAtomically(file.string(), "first");
  EXPECT_EQ(slurp(file), "first");
  writeFileAtomically(file.string(), std::string("second\0binary", 13));
  EXPECT_EQ(slurp(file), std::string("second\0binary", 13));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
  EXPECT_EQ(fs::status(file).permissions() & fs::perms::others_read, fs::perms::others_read);
}

TEST(AtomicWrite, MissingDirectoryIsAnInputErrorAndCreatesNothing) {
  const fs::path dir = freshDir("atomic_write_missing");
  const fs::path file = dir / "no" / "such" / "out.obj";
  try {
    writeFileAtomically(file.string(), "x");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr(file.string()));
    EXPECT_THAT(e.what(), ::testing::HasSubstr("does not exist"));
  }
  EXPECT_FALSE(fs::exists(dir / "no"));
}

std::size_t entries(const fs::path& dir) {
  return static_cast<std::size_t>(
      std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

TEST(OutputBatch, CommitRenamesEverythingAndAFailureLeavesNothing) {
  const fs::path dir = freshDir("output_batch");
  std::ofstream(dir / "old.txt") << "old";
  {
    OutputBatch batch;
    writeFileAtomically((dir / "a.txt").string(), "a");
    writeFileAtomically((dir / "old.txt").string(), "first");
    writeFileAtomically((dir / "old.txt").string(), "new");  // the last bytes win
    EXPECT_FALSE(fs::exists(dir / "a.txt"));                 // staged, not yet in place
    EXPECT_EQ(slurp(dir / "old.txt"), "old");
    EXPECT_EQ(stagedOutputs().size(), 2u);
    batch.commit();
  }
  EXPECT_EQ(slurp(dir / "a.txt"), "a");
  EXPECT_EQ(slurp(dir / "old.txt"), "new");
  EXPECT_EQ(entries(dir), 2u);  // no temporaries left

  {
    OutputBatch failed;  // destroyed without commit: a run that failed
    writeFileAtomically((dir / "b.txt").string(), "b");
    writeFileAtomically((dir / "a.txt").string(), "changed");
    createOutputDirectory((dir / "made" / "deeper").string());
    EXPECT_TRUE(fs::is_directory(dir / "made" / "deeper"));
    removeWhenCommitted((dir / "old.txt").string());
  }
  EXPECT_FALSE(fs::exists(dir / "b.txt"));
  EXPECT_FALSE(fs::exists(dir / "made"));  // the directories it made are gone again
  EXPECT_EQ(slurp(dir / "a.txt"), "a");
  EXPECT_EQ(slurp(dir / "old.txt"), "new");  // a removal waits for the commit
  EXPECT_EQ(entries(dir), 2u);
}

TEST(OutputBatch, NestedBatchesCommitOnTheirOwnAndImmediateWritesStay) {
  const fs::path dir = freshDir("output_batch_nested");
  {
    OutputBatch outer;
    writeFileAtomically((dir / "outer.txt").string(), "outer");
    {
      OutputBatch step;  // one `flexure run` step: its outputs are there for the next step
      writeFileAtomically((dir / "step.txt").string(), "step");
      step.commit();
    }
    EXPECT_EQ(slurp(dir / "step.txt"), "step");
    EXPECT_FALSE(fs::exists(dir / "outer.txt"));
    writeFileNow((dir / "report.json").string(), "why it failed");
    removeWhenCommitted((dir / "step.txt").string());
  }  // the outer run fails
  EXPECT_FALSE(fs::exists(dir / "outer.txt"));
  EXPECT_EQ(slurp(dir / "step.txt"), "step");
  EXPECT_EQ(slurp(dir / "report.json"), "why it failed");
  EXPECT_EQ(entries(dir), 2u);
  {
    OutputBatch batch;
    removeWhenCommitted((dir / "step.txt").string());
    batch.commit();
  }
  EXPECT_FALSE(fs::exists(dir / "step.txt"));
}

}  // namespace
}  // namespace flexure::modeling
