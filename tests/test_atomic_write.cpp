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

}  // namespace
}  // namespace flexure::modeling
