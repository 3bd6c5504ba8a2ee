// Trajectory files: exact round trips, format detection, and a clear error naming file and line for each
// kind of bad input.
#include <gtest/gtest.h>

#include <cmath>

#include "odometry/io/trajectory_file.h"
#include "tests/support/temp_dir.h"

namespace uf {
namespace {

using testing::TempDir;

Trajectory Helix(std::size_t n, Stamp start) {
  Trajectory trajectory;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = 0.1 * static_cast<double>(i);
    trajectory.stamps.push_back(start + static_cast<Stamp>(i) * 33'333'337);  // not a round number of ns
    trajectory.poses.emplace_back(SO3::Exp(Eigen::Vector3d(0.1 * a, -0.2, a)),
                                  Eigen::Vector3d(std::cos(a) * 5, std::sin(a) * 5, 0.3 * a));
  }
  return trajectory;
}

void ExpectSamePoses(const Trajectory& a, const Trajectory& b, double tolerance) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_LT((a.poses[i].translation() - b.poses[i].translation()).norm(), tolerance) << i;
    EXPECT_LT((a.poses[i].rotation() - b.poses[i].rotation()).norm(), tolerance) << i;
  }
}

TEST(TrajectoryFile, TumRoundTripKeepsNanosecondStamps) {
  TempDir dir;
  const Trajectory written = Helix(50, 1'305'031'102'160'407'123);
  ASSERT_TRUE(WriteTumTrajectory(dir.File("t.tum"), written).ok());
  auto read = ReadTrajectory(dir.File("t.tum"));
  ASSERT_TRUE(read) << read.error();
  EXPECT_EQ(read->stamps, written.stamps);  // exact, to the nanosecond
  ExpectSamePoses(*read, written, 1e-8);
}

TEST(TrajectoryFile, EurocRoundTrip) {
  TempDir dir;
  const Trajectory written = Helix(20, 1'403'636'579'758'555'392);
  ASSERT_TRUE(WriteEurocTrajectory(dir.File("gt.csv"), written).ok());
  EXPECT_EQ(*DetectTrajectoryFormat(dir.File("gt.csv")), TrajectoryFormat::kEuroc);
  auto read = ReadTrajectory(dir.File("gt.csv"));
  ASSERT_TRUE(read) << read.error();
  EXPECT_EQ(read->stamps, written.stamps);
  ExpectSamePoses(*read, written, 1e-8);
}

TEST(TrajectoryFile, KittiRoundTripWithTimesFile) {
  TempDir dir;
  Trajectory written = Helix(30, 0);
  ASSERT_TRUE(WriteKittiTrajectory(dir.File("poses.txt"), written).ok());
  EXPECT_EQ(*DetectTrajectoryFormat(dir.File("poses.txt")), TrajectoryFormat::kKitti);
  auto read = ReadTrajectory(dir.File("poses.txt"));
  ASSERT_TRUE(read) << read.error();
  EXPECT_FALSE(read->has_stamps());
  ExpectSamePoses(*read, written, 1e-10);

  auto times = ReadTimesFile(dir.Write("times.txt", "0.0\n1.037359e-01\n2.073381e-01\n"));
  ASSERT_TRUE(times) << times.error();
  EXPECT_EQ((*times)[1], 103'735'900);
  Status mismatch = AttachStamps(*read, *times, dir.File("times.txt"));
  ASSERT_FALSE(mismatch.ok());
  EXPECT_NE(mismatch.message().find("3 times for 30 poses"), std::string::npos) << mismatch.message();
}

TEST(TrajectoryFile, ReadsCommentsCommasAndCrLf) {
  TempDir dir;
  auto read = ReadTumTrajectory(
      dir.Write("t.tum", "# header\r\n\r\n1.5,1,2,3,0,0,0,1\r\n% other comment\n2.5 4 5 6 0 0 1 0\n"));
  ASSERT_TRUE(read) << read.error();
  ASSERT_EQ(read->size(), 2u);
  EXPECT_EQ(read->stamps[1], 2'500'000'000);
  EXPECT_EQ(read->poses[1].translation(), Eigen::Vector3d(4, 5, 6));
  EXPECT_NEAR(read->poses[1].so3().angle(), M_PI, 1e-12);  // qz = 1: half a turn about z
}

struct BadFile {
  const char* name;
  const char* text;
  const char* expected;  // part of the message
};

// `read` on a file `name` holding bad.text fails with an error naming the file and holding bad.expected.
template <typename Read>
void ExpectErrorNamingTheFile(const BadFile& bad, const char* name, Read read) {
  TempDir dir;
  const std::string path = dir.Write(name, bad.text);
  auto result = read(path);
  ASSERT_FALSE(result);
  EXPECT_NE(result.error().find(path), std::string::npos) << result.error();
  EXPECT_NE(result.error().find(bad.expected), std::string::npos) << result.error();
}

class BadTumFile : public ::testing::TestWithParam<BadFile> {};

TEST_P(BadTumFile, ErrorNamesFileLineAndValue) {
  ExpectErrorNamingTheFile(GetParam(), "bad.tum",
                           [](const std::string& path) { return ReadTumTrajectory(path); });
}

INSTANTIATE_TEST_SUITE_P(
    Cases, BadTumFile,
    ::testing::Values(
        BadFile{"columns", "1 0 0 0 0 0 0 1\n2 0 0 0 0 0 1\n", ":2: expected 8 columns"},
        BadFile{"text", "1 0 0 0 0 0 0 1\n2 0 zero 0 0 0 0 1\n", ":2: y (column 3) is not a number: 'zero'"},
        BadFile{"nan", "1 0 0 nan 0 0 0 1\n", ":1: z (column 4) is not finite: 'nan'"},
        BadFile{"inf", "1 0 0 0 0 0 0 1e999\n", ":1: qw (column 8) is out of the range of a double: '1e999'"},
        BadFile{"stamp", "1x 0 0 0 0 0 0 1\n", ":1: timestamp (column 1) is not a time in seconds: '1x'"},
        BadFile{"duplicate", "1 0 0 0 0 0 0 1\n1.0 0 0 0 0 0 0 1\n", ":2: duplicate stamp 1.000000000 s"},
        BadFile{"backwards", "2 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n", ":2: stamp goes backwards"},
        BadFile{"quaternion", "1 0 0 0 0 0 0 0\n", ":1: quaternion norm is 0.0"},
        BadFile{"empty", "# only a comment\n", "no poses in file"}),
    [](const auto& info) { return std::string(info.param.name); });

TEST(TrajectoryFile, DuplicateStampsCanBeSkippedKeepingTheFirst) {
  TempDir dir;
  const std::string path =
      dir.Write("d.tum", "1 0 0 0 0 0 0 1\n2 1 0 0 0 0 0 1\n2 9 9 9 0 0 0 1\n3 2 0 0 0 0 0 1\n");
  EXPECT_FALSE(ReadTumTrajectory(path));
  TrajectoryReadReport report;
  auto read = ReadTumTrajectory(path, {.skip_duplicate_stamps = true}, &report);
  ASSERT_TRUE(read) << read.error();
  ASSERT_EQ(read->size(), 3u);
  EXPECT_EQ(read->poses[1].translation().x(), 1);  // the first of the two poses at t = 2 s
  EXPECT_EQ(report.skipped_duplicates, 1u);
  EXPECT_EQ(report.first_skipped_line, 3);
  // Going backwards stays an error.
  EXPECT_FALSE(ReadTumTrajectory(dir.Write("b.tum", "2 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n"),
                                 {.skip_duplicate_stamps = true}));
}

// The stamps of `render --stamps`: exact nanoseconds, comments and blank lines, any order.
TEST(StampsFile, ReadsExactNanosecondsInAnyOrderWithComments) {
  TempDir dir;
  auto stamps = ReadStampsFile(dir.Write(
      "stamps.txt", "# frames to render\n\n1305031102.160407123\n  0.5 # the bridge\r\n1.037359e-01\n0.5\n"));
  ASSERT_TRUE(stamps) << stamps.error();
  // Decreasing and repeated stamps are kept as they are: each is one view.
  EXPECT_EQ(*stamps, (std::vector<Stamp>{1'305'031'102'160'407'123, 500'000'000, 103'735'900, 500'000'000}));
  // times.txt takes the same trailing comment, and still wants its times increasing.
  auto times = ReadTimesFile(dir.Write("times.txt", "0.1 # first\n0.2\n"));
  ASSERT_TRUE(times) << times.error();
  EXPECT_EQ((*times)[0], 100'000'000);
  EXPECT_FALSE(ReadTimesFile(dir.File("stamps.txt")));
}

class BadStampsFile : public ::testing::TestWithParam<BadFile> {};

TEST_P(BadStampsFile, ErrorNamesFileLineAndText) {
  ExpectErrorNamingTheFile(GetParam(), "stamps.txt", ReadStampsFile);
}

INSTANTIATE_TEST_SUITE_P(
    Cases, BadStampsFile,
    ::testing::Values(BadFile{"text", "1.0\nabc\n", ":2: time (column 1) is not a time in seconds: 'abc'"},
                      BadFile{"nan", "NaN\n", ":1: time (column 1) is not a time in seconds: 'NaN'"},
                      BadFile{"two", "1.0 2.0\n", ":1: expected 1 columns (one time in seconds per line)"},
                      BadFile{"empty", "# nothing\n\n", "no times in file"}),
    [](const auto& info) { return std::string(info.param.name); });

TEST(TrajectoryFile, KittiRejectsNonRotation) {
  TempDir dir;
  auto read = ReadKittiTrajectory(dir.Write("k.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n2 0 0 0 0 1 0 0 0 0 1 0\n"));
  ASSERT_FALSE(read);
  EXPECT_NE(read.error().find(":2: the 3x3 block is not a rotation"), std::string::npos) << read.error();
}

TEST(TrajectoryFile, DetectionNamesTheColumnCount) {
  TempDir dir;
  auto format = DetectTrajectoryFormat(dir.Write("x.txt", "1 2 3\n"));
  ASSERT_FALSE(format);
  EXPECT_NE(format.error().find(":1: cannot tell the trajectory format from 3 columns"), std::string::npos);
  EXPECT_FALSE(ReadTrajectory(dir.File("missing.txt")));
  EXPECT_NE(ReadTrajectory(dir.File("missing.txt")).error().find("cannot open file"), std::string::npos);
}

TEST(TrajectoryFile, FailedWriteLeavesNoFileAndKeepsTheOldOne) {
  TempDir dir;
  const Trajectory trajectory = Helix(5, 0);
  EXPECT_FALSE(WriteTumTrajectory(dir.File("no/such/folder/t.tum"), trajectory).ok());
  EXPECT_FALSE(std::filesystem::exists(dir.File("no/such/folder/t.tum")));
  // EuRoC needs stamps: the write is refused before anything touches the existing good file.
  const std::string good = dir.Write("gt.csv", "kept");
  Trajectory stampless = trajectory;
  stampless.stamps.clear();
  EXPECT_FALSE(WriteEurocTrajectory(good, stampless).ok());
  EXPECT_EQ(testing::ReadText(good), "kept");
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()), {}), 1);  // no temporary left
}

}  // namespace
}  // namespace uf
