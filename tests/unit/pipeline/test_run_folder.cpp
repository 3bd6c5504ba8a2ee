// Versioned run folders: runs/<UTC YYYYmmdd-HHMMSS>/, a suffix when the name is taken, and runs/latest
// moved atomically onto the newest.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <set>

#include "tests/support/temp_dir.h"
#include "viewer/pipeline/run_folder.h"

namespace uf::pipeline {
namespace {

namespace fs = std::filesystem;
using std::chrono::system_clock;

// 1700000000 s since the epoch is 2023-11-14 22:13:20 UTC.
const system_clock::time_point kTime = system_clock::time_point(std::chrono::seconds(1700000000));

TEST(RunFolder, NameIsTheUtcTimeToTheSecond) {
  EXPECT_EQ(RunFolderName(kTime), "20231114-221320");
  EXPECT_EQ(RunFolderName(kTime + std::chrono::milliseconds(999)), "20231114-221320");
  EXPECT_EQ(RunFolderName(system_clock::time_point(std::chrono::seconds(0))), "19700101-000000");
}

TEST(RunFolder, ASecondRunInTheSameSecondGetsASuffixAndLatestFollows) {
  testing::TempDir dir;
  const fs::path runs = dir.path() / "runs";  // created on demand
  Expected<fs::path> first = CreateVersionedRunFolder(runs, kTime);
  ASSERT_TRUE(first.ok()) << first.status().message();
  EXPECT_EQ(*first, runs / "20231114-221320");
  ASSERT_TRUE(UpdateLatestLink(runs, *first).ok());
  EXPECT_EQ(fs::read_symlink(runs / "latest"), fs::path("20231114-221320"));  // relative: runs/ can move

  Expected<fs::path> second = CreateVersionedRunFolder(runs, kTime);
  ASSERT_TRUE(second.ok());
  EXPECT_EQ(*second, runs / "20231114-221320-2");
  EXPECT_TRUE(fs::is_directory(*first));
  EXPECT_TRUE(fs::is_empty(*second));
  std::ofstream(*second / "marker") << "x";
  ASSERT_TRUE(UpdateLatestLink(runs, *second).ok());
  EXPECT_EQ(fs::read_symlink(runs / "latest"), fs::path("20231114-221320-2"));
  EXPECT_TRUE(fs::exists(runs / "latest" / "marker"));  // resolves to the folder

  // No temporary link left behind: exactly the two folders and the link.
  std::set<std::string> names;
  for (const fs::directory_entry& entry : fs::directory_iterator(runs)) names.insert(entry.path().filename());
  EXPECT_EQ(names, (std::set<std::string>{"20231114-221320", "20231114-221320-2", "latest"}));
}

TEST(RunFolder, ALatestThatIsARealFolderIsNotReplaced) {
  testing::TempDir dir;
  const fs::path runs = dir.path() / "runs";
  fs::create_directories(runs / "latest");
  std::ofstream(runs / "latest" / "keep") << "keep me";
  Expected<fs::path> folder = CreateVersionedRunFolder(runs, kTime);
  ASSERT_TRUE(folder.ok());
  const Status status = UpdateLatestLink(runs, *folder);
  EXPECT_FALSE(status.ok());
  EXPECT_NE(status.message().find("latest"), std::string::npos) << status.message();
  EXPECT_EQ(testing::ReadText((runs / "latest" / "keep").string()), "keep me");
}

TEST(RunFolder, AnUncreatableRootIsAnErrorNamingIt) {
  testing::TempDir dir;
  const std::string file = dir.Write("not-a-folder", "x");
  Expected<fs::path> folder = CreateVersionedRunFolder(fs::path(file) / "runs", kTime);
  ASSERT_FALSE(folder.ok());
  EXPECT_NE(folder.status().message().find("not-a-folder/runs"), std::string::npos)
      << folder.status().message();
}

}  // namespace
}  // namespace uf::pipeline
