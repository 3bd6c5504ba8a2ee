// KITTI-style folders: stamps from times.txt, azimuth point times, ground truth, damaged folders, and the
// recorded KITTI keyframes when ../shared/data is present.
#include <gtest/gtest.h>

#include "odometry/io/folders/folder_readers.h"
#include "odometry/io/trajectory_file.h"
#include "tests/support/temp_dir.h"
#include "tests/unit/io/folders/folder_fixtures.h"

namespace uf {
namespace {

namespace fs = std::filesystem;
using testing::TempDir;

// velodyne/ with `scans` .bin files of two points each, and times.txt with `times`.
void MakeKittiFolder(const TempDir& dir, int scans, const std::string& times) {
  fs::create_directories(dir.path() / "velodyne");
  for (int i = 0; i < scans; ++i) {
    char name[32];
    std::snprintf(name, sizeof(name), "velodyne/%06d.bin", i);
    testing::WriteBytes(dir.File(name),
                        testing::PackXyzi({{10, 0, 0, 1}, {0, 10, 0, static_cast<float>(i)}}));
  }
  dir.Write("times.txt", times);
}

std::vector<LidarScan> ReadAll(DatasetReader& reader) {
  std::vector<LidarScan> scans;
  while (true) {
    auto next = reader.Next();
    EXPECT_TRUE(next.ok()) << next.error();
    if (!next.ok() || !*next) break;
    scans.push_back(std::get<LidarScan>((*next)->data));
  }
  return scans;
}

TEST(KittiFolder, StampsScansFromTimesTxtExactly) {
  TempDir dir;
  MakeKittiFolder(dir, 3, "0.000000e+00\n1.037359e-01\n2.072000000001\n");
  auto reader = OpenKittiFolder(dir.path());
  ASSERT_TRUE(reader.ok()) << reader.error();
  const DatasetDescription& description = (*reader)->description();
  ASSERT_EQ(description.streams.size(), 1u);
  EXPECT_EQ(description.streams[0].kind, SensorKind::kLidar);
  EXPECT_EQ(description.streams[0].name, "velodyne");
  EXPECT_EQ(description.streams[0].point_time, PointTimeConvention::kAzimuth);
  EXPECT_FALSE(description.ground_truth);
  const std::vector<LidarScan> scans = ReadAll(**reader);
  ASSERT_EQ(scans.size(), 3u);
  // times.txt stamps the middle of each 100 ms sweep (KITTI's convention): scans start 50 ms earlier.
  EXPECT_EQ(scans[0].stamp, -50'000'000);
  EXPECT_EQ(scans[1].stamp, 103'735'900 - 50'000'000);
  EXPECT_EQ(scans[2].stamp, 2'072'000'000 - 50'000'000);
  EXPECT_EQ(scans[2].end, Stamp{2'072'000'000} + 50'000'000);
  EXPECT_EQ(scans[2].points[1].intensity, 2);
  EXPECT_TRUE(scans[0].point_times_from_azimuth);
  EXPECT_EQ(scans[0].points[0].offset_ns, 50'000'000);  // forward: half a sweep, at the times.txt stamp
  EXPECT_EQ(scans[0].points[1].offset_ns, 25'000'000);  // left: a quarter
  EXPECT_TRUE((*reader)->warnings().empty());
  EXPECT_EQ(description.streams[0].azimuth_convention, kClockwiseFromBehind);
}

TEST(KittiFolder, PointTimeConventionOptionDerivesTheTimesItsWay) {
  TempDir dir;
  MakeKittiFolder(dir, 1, "5\n");
  DatasetOptions options;
  options.point_time_convention = AzimuthConvention{AzimuthSweep::kCounterClockwise, SweepStart::kAhead};
  auto reader = OpenKittiFolder(dir.path(), options);
  ASSERT_TRUE(reader.ok()) << reader.error();
  EXPECT_EQ((*reader)->description().streams[0].azimuth_convention, options.point_time_convention);
  const std::vector<LidarScan> scans = ReadAll(**reader);
  ASSERT_EQ(scans.size(), 1u);
  EXPECT_EQ(scans[0].points[0].offset_ns, 0);           // forward: the start
  EXPECT_EQ(scans[0].points[1].offset_ns, 25'000'000);  // left: a quarter turn counter-clockwise
  options.point_time_convention = kNoDeskew;
  const std::vector<LidarScan> none = ReadAll(**OpenKittiFolder(dir.path(), options));
  EXPECT_EQ(none[0].points[0].offset_ns, 50'000'000);
  EXPECT_EQ(none[0].points[1].offset_ns, 50'000'000);
}

TEST(KittiFolder, OptionsTurnOffAzimuthTimesAndSetTheSweep) {
  TempDir dir;
  MakeKittiFolder(dir, 1, "5\n");
  DatasetOptions options;
  options.derive_point_times_from_azimuth = false;
  options.lidar_sweep_period_s = 0.05;
  auto reader = OpenKittiFolder(dir.path(), options);
  ASSERT_TRUE(reader.ok()) << reader.error();
  EXPECT_EQ((*reader)->description().streams[0].point_time, PointTimeConvention::kNone);
  const std::vector<LidarScan> scans = ReadAll(**reader);
  ASSERT_EQ(scans.size(), 1u);
  EXPECT_FALSE(scans[0].has_point_times);
  EXPECT_EQ(scans[0].stamp, 4'975'000'000);
  EXPECT_EQ(scans[0].end, 5'025'000'000);
  options.folder_scan_stamp = ScanStampPosition::kSweepStart;
  const std::vector<LidarScan> from_start = ReadAll(**OpenKittiFolder(dir.path(), options));
  EXPECT_EQ(from_start[0].stamp, 5'000'000'000);
  EXPECT_EQ(from_start[0].end, 5'050'000'000);
  options.lidar_sweep_period_s = 0;
  EXPECT_NE(OpenKittiFolder(dir.path(), options).error().find("lidar_sweep_period_s"), std::string::npos);
}

TEST(KittiFolder, ReadsPcdScansAndFindsGroundTruth) {
  TempDir dir;
  fs::create_directories(dir.path() / "lidar");
  testing::WriteBytes(dir.File("lidar/a.pcd"), testing::XyziPcd({{1, 2, 3, 4}, {NAN, 0, 0, 0}}, "binary"));
  testing::WriteBytes(dir.File("lidar/b.pcd"), testing::XyziPcd({{5, 6, 7, 8}}, "ascii"));
  dir.Write("times.txt", "100.5\n100.6\n");
  dir.Write("groundtruth_lidar.tum", "100.5 0 0 0 0 0 0 1\n");
  auto reader = OpenKittiFolder(dir.path());
  ASSERT_TRUE(reader.ok()) << reader.error();
  ASSERT_TRUE((*reader)->description().ground_truth);
  EXPECT_EQ(*(*reader)->description().ground_truth, dir.path() / "groundtruth_lidar.tum");
  EXPECT_EQ((*reader)->description().streams[0].message_type, "kitti velodyne .pcd");
  const std::vector<LidarScan> scans = ReadAll(**reader);
  ASSERT_EQ(scans.size(), 2u);
  EXPECT_EQ(scans[0].points.size(), 1u);
  EXPECT_EQ(scans[1].stamp, 100'550'000'000);
  const ReadWarning* warning = testing::FindWarning(**reader, "NaN");
  ASSERT_NE(warning, nullptr);
  EXPECT_EQ(warning->count, 1);
  EXPECT_EQ(warning->stream, "lidar");
}

TEST(KittiFolder, FindsKittiPosesInTheDatasetLayout) {
  TempDir dir;  // dataset/sequences/07/{velodyne,times.txt} and dataset/poses/07.txt
  const fs::path sequence = dir.path() / "sequences" / "07";
  fs::create_directories(sequence / "velodyne");
  fs::create_directories(dir.path() / "poses");
  testing::WriteBytes(sequence / "velodyne" / "000000.bin", testing::PackXyzi({{1, 0, 0, 0}}));
  testing::WriteBytes(sequence / "times.txt", "0\n");
  testing::WriteBytes(dir.path() / "poses" / "07.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n");
  auto reader = OpenKittiFolder(sequence);
  ASSERT_TRUE(reader.ok()) << reader.error();
  ASSERT_TRUE((*reader)->description().ground_truth);
  EXPECT_TRUE(fs::equivalent(*(*reader)->description().ground_truth, dir.path() / "poses" / "07.txt"));
}

TEST(KittiFolder, DamagedFoldersGiveNamedErrors) {
  {
    TempDir dir;
    MakeKittiFolder(dir, 2, "0\n0.1\n");
    fs::remove(dir.path() / "times.txt");
    auto reader = OpenKittiFolder(dir.path());
    ASSERT_FALSE(reader.ok());
    EXPECT_NE(reader.error().find("times.txt: missing"), std::string::npos) << reader.error();
  }
  {
    TempDir dir;
    MakeKittiFolder(dir, 3, "0\n0.1\n");
    auto reader = OpenKittiFolder(dir.path());
    ASSERT_FALSE(reader.ok());
    EXPECT_NE(reader.error().find("times.txt: 2 stamps for 3 scan files"), std::string::npos)
        << reader.error();
  }
  {
    TempDir dir;
    MakeKittiFolder(dir, 3, "0\n0.2\n0.1\n");
    auto reader = OpenKittiFolder(dir.path());
    ASSERT_FALSE(reader.ok());
    EXPECT_NE(reader.error().find("times.txt:3: stamp goes backwards: 0.100000000 s"), std::string::npos)
        << reader.error();
  }
  {
    TempDir dir;
    MakeKittiFolder(dir, 2, "0\n0.1\n");
    testing::WriteBytes(dir.File("velodyne/000001.bin"), "0123456789");
    auto reader = OpenKittiFolder(dir.path());
    ASSERT_TRUE(reader.ok()) << reader.error();
    EXPECT_TRUE((*reader)->Next().ok());
    auto damaged = (*reader)->Next();
    ASSERT_FALSE(damaged.ok());
    EXPECT_NE(damaged.error().find("000001.bin: size 10 bytes is not a multiple of 16"), std::string::npos);
    EXPECT_EQ((*reader)->Next().error(), damaged.error());  // the error sticks
  }
  {
    TempDir dir;
    fs::create_directories(dir.path() / "velodyne");
    dir.Write("times.txt", "0\n");
    EXPECT_NE(OpenKittiFolder(dir.path()).error().find("no .bin or .pcd scan files"), std::string::npos);
    EXPECT_NE(OpenKittiFolder(dir.path() / "nothing").error().find("no velodyne/ or lidar/"),
              std::string::npos);
  }
}

TEST(KittiFolder, ReadsTheRecordedKittiKeyframes) {
  const std::string data = testing::SharedData();
  if (data.empty()) GTEST_SKIP() << "../shared/data is absent: skipping the recorded KITTI 00 keyframes";
  const fs::path folder = fs::path(data) / "kitti00-keyframes";
  auto times = ReadTimesFile((folder / "times.txt").string());
  ASSERT_TRUE(times.ok()) << times.error();
  auto reader = OpenKittiFolder(folder);
  ASSERT_TRUE(reader.ok()) << reader.error();
  ASSERT_TRUE((*reader)->description().ground_truth);
  EXPECT_EQ((*reader)->description().ground_truth->filename(), "groundtruth_velodyne.tum");
  std::size_t count = 0;
  while (true) {
    auto next = (*reader)->Next();
    ASSERT_TRUE(next.ok()) << next.error();
    if (!*next) break;
    const LidarScan& scan = std::get<LidarScan>((*next)->data);
    ASSERT_LT(count, times->size());
    EXPECT_EQ(scan.stamp, (*times)[count] - 50'000'000) << "scan " << count;  // times.txt: mid-sweep
    EXPECT_EQ(scan.end, (*times)[count] + 50'000'000) << "scan " << count;
    EXPECT_GE(scan.points.size(), 101'000u) << "scan " << count;
    EXPECT_LE(scan.points.size(), 127'000u) << "scan " << count;
    EXPECT_TRUE(scan.point_times_from_azimuth);
    ++count;
  }
  EXPECT_EQ(count, 80u);
  EXPECT_TRUE((*reader)->warnings().empty());
}

}  // namespace
}  // namespace uf
