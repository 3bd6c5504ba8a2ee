// The KITTI raw drive reader: hand-checked values of the real drive in ../shared/data/kitti-raw-0009 (counts,
// stamps, one OXTS record, the calibration against KITTI's own projection formula, the OXTS poses against
// the devkit-made reference), and small made-up drives with the damage real downloads have.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <variant>
#include <vector>

#include "odometry/io/dataset_reader.h"
#include "odometry/io/folders/folder_readers.h"
#include "odometry/io/folders/kitti_raw_files.h"
#include "odometry/io/folders/kitti_raw_oxts.h"
#include "odometry/io/folders/point_cloud_files.h"
#include "odometry/io/trajectory_file.h"
#include "odometry/types/rings_from_storage_order.h"
#include "tests/support/read_all.h"
#include "tests/support/temp_dir.h"
#include "tests/unit/io/folders/folder_fixtures.h"

namespace uf {
namespace {

namespace fs = std::filesystem;
using testing::ReadAll;
using testing::SharedData;
using testing::TempDir;

TEST(KittiWallClock, ParsesToTheNanosecondAsUtc) {
  // 2011-09-26 is day 15243 after 1970-01-01: 15243 * 86400 + 13 h 08 min 24 s = 1317042504 s.
  EXPECT_EQ(ParseKittiWallClock("2011-09-26 13:08:24.969505176"), Stamp{1317042504969505176});
  EXPECT_EQ(ParseKittiWallClock("2011-09-26 13:08:24.5"), Stamp{1317042504500000000});
  EXPECT_EQ(ParseKittiWallClock("2011-09-26 13:08:24"), Stamp{1317042504000000000});
  EXPECT_EQ(ParseKittiWallClock("1970-01-01 00:00:00.000000001"), Stamp{1});
  for (const char* bad : {"", "2011-02-30 00:00:00", "2011-09-26 24:00:00", "2011-09-26T13:08:24",
                          "2011-09-26 13:08:24.1234567890", "2011-09-26 13:08:2x", "13:08:24.9",
                          "2398-01-01 12:00:00", "1969-12-31 23:59:59"})  // int64 ns ends in 2262
    EXPECT_FALSE(ParseKittiWallClock(bad)) << bad;
}

TEST(KittiCalibFile, ReadsNumbersAndRefusesRepeatedKeys) {
  TempDir dir;
  auto values = ReadKittiCalibFile(dir.Write("c.txt",
                                             "calib_time: 09-Jan-2012 13:57:47\nR: 1 0 0 0 1 0 0 0 1\n"
                                             "T: 1.5e-01 -2 3\n"));
  ASSERT_TRUE(values.ok()) << values.error();
  EXPECT_FALSE(values->contains("calib_time"));
  EXPECT_EQ(values->at("T"), (std::vector<double>{0.15, -2, 3}));
  auto repeated = ReadKittiCalibFile(dir.Write("d.txt", "T: 1 2 3\nT: 1 2 3\n"));
  ASSERT_FALSE(repeated.ok());
  EXPECT_NE(repeated.error().find("d.txt:2: key 'T' given twice"), std::string::npos) << repeated.error();
  auto short_t = CalibNumbers(*values, "R", 12, dir.File("c.txt"));
  ASSERT_FALSE(short_t.ok());
  EXPECT_NE(short_t.error().find("'R:' has 9 numbers, expected 12"), std::string::npos) << short_t.error();
}

// ---- the real drive ----

fs::path RealDrive() {
  const std::string data = SharedData();
  if (data.empty()) return {};
  return fs::path(data) / "kitti-raw-0009" / "2011_09_26" / "2011_09_26_drive_0009_sync";
}

#define SKIP_WITHOUT_DRIVE()                                                                           \
  const fs::path drive = RealDrive();                                                                  \
  if (drive.empty() || !fs::exists(drive)) GTEST_SKIP() << "../shared/data/kitti-raw-0009 is absent: " \
                                                           "skipped"

int StreamNamed(const DatasetDescription& d, const std::string& name) {
  for (std::size_t i = 0; i < d.streams.size(); ++i)
    if (d.streams[i].name == name) return static_cast<int>(i);
  return -1;
}

TEST(KittiRawDrive, RealDriveCountsStampsAndOneOxtsRecord) {
  SKIP_WITHOUT_DRIVE();
  auto reader = OpenDataset(drive);
  ASSERT_TRUE(reader.ok()) << reader.error();
  const DatasetDescription& d = (*reader)->description();
  EXPECT_EQ(d.format, DatasetFormat::kKittiRaw);
  const int lidar = StreamNamed(d, "velodyne_points"), imu = StreamNamed(d, "oxts/imu");
  const int gnss = StreamNamed(d, "oxts/gnss"), camera = StreamNamed(d, "image_02");
  ASSERT_TRUE(lidar >= 0 && imu >= 0 && gnss >= 0 && camera >= 0);
  EXPECT_EQ(d.streams.size(), 4u) << "image_00/01/03 have timestamps only: no stream";
  const std::vector<Measurement> all = ReadAll(**reader);
  std::vector<int> counts(d.streams.size(), 0);
  const LidarScan* first_scan = nullptr;
  const LidarScan* last_scan = nullptr;
  const ImuSample* first_imu = nullptr;
  const GnssFix* first_fix = nullptr;
  const CameraFrame* first_image = nullptr;
  for (const Measurement& m : all) {
    ++counts[m.stream];
    if (auto* scan = std::get_if<LidarScan>(&m.data)) (first_scan ? last_scan : first_scan) = scan;
    if (auto* sample = std::get_if<ImuSample>(&m.data); sample && !first_imu) first_imu = sample;
    if (auto* fix = std::get_if<GnssFix>(&m.data); fix && !first_fix) first_fix = fix;
    if (auto* image = std::get_if<CameraFrame>(&m.data); image && !first_image) first_image = image;
  }
  EXPECT_EQ(counts[lidar], 51);
  EXPECT_EQ(counts[imu], 447);
  EXPECT_EQ(counts[gnss], 447);
  EXPECT_EQ(counts[camera], 26);
  ASSERT_TRUE(first_scan && last_scan && first_imu && first_fix && first_image);
  // velodyne_points/timestamps_start.txt and _end.txt, lines 1 and 51.
  EXPECT_EQ(first_scan->stamp, *ParseKittiWallClock("2011-09-26 13:08:24.905593646"));
  EXPECT_EQ(first_scan->end, *ParseKittiWallClock("2011-09-26 13:08:25.009036215"));
  EXPECT_EQ(last_scan->stamp, *ParseKittiWallClock("2011-09-26 13:08:30.077665900"));
  EXPECT_TRUE(first_scan->has_point_times && first_scan->point_times_from_azimuth);
  EXPECT_TRUE(first_scan->has_ring);  // from the order the file stores the points in
  EXPECT_GT(first_scan->points.size(), 110000u);
  EXPECT_EQ(first_image->stamp, *ParseKittiWallClock("2011-09-26 13:08:24.967930880"));
  EXPECT_EQ(first_image->camera, 2);
  // oxts/data/0000000000.txt: ax ay az are fields 12-14, wx wy wz 18-20, pos_accuracy 24, navstat 26 (4),
  // posmode 28 (4: differential).
  EXPECT_EQ(first_imu->stamp, *ParseKittiWallClock("2011-09-26 13:08:24.969505176"));
  EXPECT_EQ(first_imu->acc, Eigen::Vector3d(0.0059525410318346, 0.845164147132, 9.9149729634473));
  EXPECT_EQ(first_imu->gyro, Eigen::Vector3d(0.016662646247367, -0.036831580656409, 0.003311640516573));
  EXPECT_DOUBLE_EQ(first_fix->latitude_deg, 49.009347760599);
  EXPECT_DOUBLE_EQ(first_fix->longitude_deg, 8.4371344308375);
  EXPECT_DOUBLE_EQ(first_fix->altitude_m, 114.45652008057);
  EXPECT_NEAR(first_fix->covariance_enu(0, 0), 0.42856154750514 * 0.42856154750514, 1e-12);
  EXPECT_EQ(first_fix->status, GnssFixStatus::kSbas);
  // The missing odd image frames are one counted warning.
  bool images_missing = false;
  for (const ReadWarning& w : (*reader)->warnings())
    images_missing |= w.stream == "image_02" && w.what.starts_with("images missing") && w.count == 25;
  EXPECT_TRUE(images_missing);
  EXPECT_LT(d.streams[imu].nominal_rate_hz, 11);
  EXPECT_NE(d.streams[imu].note.find("10 Hz"), std::string::npos) << d.streams[imu].note;
}

// The HDL-64E's scans are stored ring by ring, top laser first (rings_from_storage_order.h): the 64 rings
// derived from that order must run from the top (about +2.5 deg) to the bottom (about -24 deg), each ring's
// median elevation below the one before.
TEST(KittiRawDrive, RingsFromTheStorageOrderRunFromTheTopLaserDown) {
  SKIP_WITHOUT_DRIVE();
  auto scan = ReadKittiBin(drive / "velodyne_points" / "data" / "0000000000.bin.xz");
  ASSERT_TRUE(scan.ok()) << scan.error();
  ASSERT_EQ(DeriveRingsFromStorageOrder(*scan), 64);
  std::vector<std::vector<double>> elevations(64);
  for (const LidarPoint& p : scan->points)
    elevations[p.ring].push_back(std::atan2(p.z, std::hypot(p.x, p.y)) * 180 / M_PI);
  std::vector<double> medians;
  for (std::vector<double>& ring : elevations) {
    ASSERT_GT(ring.size(), 1000u);  // ~1900 returns per ring
    std::nth_element(ring.begin(), ring.begin() + ring.size() / 2, ring.end());
    medians.push_back(ring[ring.size() / 2]);
  }
  EXPECT_NEAR(medians.front(), 2.5, 1.0);
  EXPECT_NEAR(medians.back(), -24, 1.0);
  for (int r = 1; r < 64; ++r) EXPECT_LT(medians[r], medians[r - 1]) << "ring " << r;
}

TEST(KittiRawDrive, RealCalibrationProjectsAsKittisFormula) {
  SKIP_WITHOUT_DRIVE();
  auto reader = OpenDataset(drive);
  ASSERT_TRUE(reader.ok()) << reader.error();
  const DatasetDescription& d = (*reader)->description();
  const StreamInfo& lidar = d.streams[StreamNamed(d, "velodyne_points")];
  const StreamInfo& camera = d.streams[StreamNamed(d, "image_02")];
  // calib_imu_to_velo.txt: X_velo = R X_imu + T, so the IMU origin sits at T in the Velodyne frame.
  const SE3 T_velo_imu = lidar.T_body_sensor->inverse();
  EXPECT_LT((T_velo_imu.translation() - Eigen::Vector3d(-8.086759e-01, 3.195559e-01, -7.997231e-01)).norm(),
            1e-6);
  // KITTI's projection x = P_rect_02 R_rect_00 T_cam0_velo X_velo with the numbers of the calibration files.
  Eigen::Matrix<double, 3, 4> P;
  P << 7.215377e+02, 0, 6.095593e+02, 4.485728e+01, 0, 7.215377e+02, 1.728540e+02, 2.163791e-01, 0, 0, 1,
      2.745884e-03;
  Eigen::Matrix4d R_rect = Eigen::Matrix4d::Identity();
  R_rect.topLeftCorner<3, 3>() << 9.999239e-01, 9.837760e-03, -7.445048e-03, -9.869795e-03, 9.999421e-01,
      -4.278459e-03, 7.402527e-03, 4.351614e-03, 9.999631e-01;
  Eigen::Matrix4d T_cam0_velo = Eigen::Matrix4d::Identity();
  T_cam0_velo.topLeftCorner<3, 3>() << 7.533745e-03, -9.999714e-01, -6.166020e-04, 1.480249e-02, 7.280733e-04,
      -9.998902e-01, 9.998621e-01, 7.523790e-03, 1.480755e-02;
  T_cam0_velo.topRightCorner<3, 1>() << -4.069766e-03, -7.631618e-02, -2.717806e-01;
  const SE3 T_camera_velo = camera.T_body_sensor->inverse() * *lidar.T_body_sensor;
  for (const Eigen::Vector3d& p_velo :
       {Eigen::Vector3d(12, 3, -1), Eigen::Vector3d(30, -8, 0.5), Eigen::Vector3d(6, 0.2, -1.5)}) {
    const Eigen::Vector3d h = P * R_rect * T_cam0_velo * p_velo.homogeneous();
    const Eigen::Vector2d kitti = h.head<2>() / h.z();
    const std::optional<Eigen::Vector2d> ours = camera.camera_model->Project(T_camera_velo * p_velo);
    ASSERT_TRUE(ours);
    EXPECT_LT((*ours - kitti).norm(), 0.01) << p_velo.transpose();  // px (7-digit calibration numbers)
  }
  EXPECT_EQ(camera.camera_model->width(), 1242);
  EXPECT_EQ(camera.camera_model->height(), 375);
}

TEST(KittiRawDrive, OxtsReferenceMatchesTheDevkitPoses) {
  SKIP_WITHOUT_DRIVE();
  auto reader = OpenDataset(drive);
  ASSERT_TRUE(reader.ok()) << reader.error();
  const DatasetDescription& d = (*reader)->description();
  ASSERT_TRUE(d.reference);
  EXPECT_FALSE(d.ground_truth);
  EXPECT_EQ(d.streams[d.reference->stream].name, "oxts/imu");
  // derived/: made with the devkit's convertOxtsToPose (PROVENANCE.md), in the IMU and in the Velodyne frame.
  const fs::path derived = drive.parent_path().parent_path() / "derived";
  auto imu = ReadTrajectory((derived / "oxts_pose_imu.tum").string());
  auto velo = ReadTrajectory((derived / "oxts_pose_velodyne.tum").string());
  ASSERT_TRUE(imu.ok() && velo.ok());
  const Trajectory& ours = d.reference->poses;
  ASSERT_EQ(ours.size(), imu->size());
  const SE3 T_imu_velo = *d.streams[StreamNamed(d, "velodyne_points")].T_body_sensor;
  double worst_m = 0, worst_rad = 0, worst_velo_m = 0;
  for (std::size_t i = 0; i < ours.size(); ++i) {
    // The derived files' stamps have 9 decimals from the same wall-clock lines: equal to the ns.
    ASSERT_EQ(ours.stamps[i], imu->stamps[i]);
    worst_m = std::max(worst_m, (ours.poses[i].translation() - imu->poses[i].translation()).norm());
    worst_rad =
        std::max(worst_rad, Eigen::AngleAxisd(ours.poses[i].rotation().transpose() * imu->poses[i].rotation()).angle());
    const SE3 ours_velo = T_imu_velo.inverse() * ours.poses[i] * T_imu_velo;
    worst_velo_m = std::max(worst_velo_m, (ours_velo.translation() - velo->poses[i].translation()).norm());
  }
  EXPECT_LT(worst_m, 1e-5);  // the files print 6 decimals
  EXPECT_LT(worst_rad, 1e-8 + 2e-9 * ours.size());
  EXPECT_LT(worst_velo_m, 1e-4);
}

// ---- made-up drives ----

const char* kCalibImuToVelo = "R: 1 0 0 0 1 0 0 0 1\nT: -0.8 0.3 -0.8\n";
const char* kCalibVeloToCam = "R: 0 -1 0 0 0 -1 1 0 0\nT: 0 -0.08 -0.27\n";
const char* kCalibCamToCam =
    "S_rect_02: 8 4\nR_rect_00: 1 0 0 0 1 0 0 0 1\nP_rect_02: 5 0 4 0 0 5 2 0 0 0 1 0\n";

// date/ with the calibration, and date/2011_01_01_drive_0001_sync/ with velodyne_points and oxts.
struct MadeUpDrive {
  TempDir dir;
  fs::path date = dir.path() / "2011_01_01";
  fs::path drive = date / "2011_01_01_drive_0001_sync";

  MadeUpDrive() {
    fs::create_directories(drive / "velodyne_points" / "data");
    fs::create_directories(drive / "oxts" / "data");
    testing::WriteBytes(date / "calib_imu_to_velo.txt", kCalibImuToVelo);
    testing::WriteBytes(date / "calib_velo_to_cam.txt", kCalibVeloToCam);
    testing::WriteBytes(date / "calib_cam_to_cam.txt", kCalibCamToCam);
  }
  static std::string Stamp(int tenth) {
    return "2011-01-01 10:00:0" + std::to_string(tenth / 10) + "." + std::to_string(tenth % 10) + "00000000";
  }
  void Scan(int index, const std::string& bytes) {
    char name[32];
    std::snprintf(name, sizeof(name), "%010d.bin", index);
    testing::WriteBytes(drive / "velodyne_points" / "data" / name, bytes);
  }
  void Oxts(int index) {
    char name[32];
    std::snprintf(name, sizeof(name), "%010d.txt", index);
    testing::WriteBytes(
        drive / "oxts" / "data" / name,
        "49.0 8.4 110 0 0 0.1 0 0 0 0 0 0 0 9.81 0 0 9.81 0 0 0.01 0 0 0.01 0.3 0.1 4 9 5 5 0\n");
  }
};

std::string FourPoints() {
  return testing::PackXyzi({{5, 1, 0, 0.1f}, {-5, 1, 0, 0.2f}, {1, 5, 0, 0.3f}, {1, -5, 0, 0.4f}});
}

TEST(KittiRawDrive, MissingScansEmptyStampsAndDamagedFilesAreCountedWarnings) {
  MadeUpDrive made;
  // Frame 1: damaged (truncated), frame 2: no file, frame 4: empty stamp line.
  testing::WriteBytes(made.drive / "velodyne_points" / "timestamps.txt",
                      MadeUpDrive::Stamp(0) + "\n" + MadeUpDrive::Stamp(1) + "\n" + MadeUpDrive::Stamp(2) +
                          "\n" + MadeUpDrive::Stamp(3) + "\n\n" + MadeUpDrive::Stamp(5) + "\n");
  made.Scan(0, FourPoints());
  made.Scan(1, FourPoints().substr(0, 21));
  made.Scan(3, FourPoints());
  made.Scan(4, FourPoints());
  made.Scan(5, FourPoints());
  std::string oxts_stamps;
  for (int i = 0; i < 6; ++i) {
    made.Oxts(i);
    oxts_stamps += MadeUpDrive::Stamp(i) + "\n";
  }
  testing::WriteBytes(made.drive / "oxts" / "timestamps.txt", oxts_stamps);
  auto reader = OpenDataset(made.drive);
  ASSERT_TRUE(reader.ok()) << reader.error();
  const std::vector<Measurement> all = ReadAll(**reader);
  std::vector<Stamp> scans;
  for (const Measurement& m : all)
    if (auto* scan = std::get_if<LidarScan>(&m.data))
      scans.push_back(scan->end - (scan->end - scan->stamp) / 2);
  // Frames 0, 3 and 5, stamped half a sweep before their timestamps.txt line (no _start/_end files).
  ASSERT_EQ(scans.size(), 3u);
  EXPECT_EQ(scans[0], *ParseKittiWallClock(MadeUpDrive::Stamp(0)));
  EXPECT_EQ(scans[1], *ParseKittiWallClock(MadeUpDrive::Stamp(3)));
  std::map<std::string, std::int64_t> warnings;
  for (const ReadWarning& w : (*reader)->warnings())
    if (w.stream == "velodyne_points") warnings[w.what.substr(0, w.what.find(" ("))] += w.count;
  EXPECT_EQ(warnings["scan files missing"], 1);
  EXPECT_EQ(warnings["files without a stamp"], 1);
  EXPECT_EQ(warnings["damaged scan files skipped"], 1);
  for (const ReadWarning& w : (*reader)->warnings())
    if (w.what.starts_with("damaged")) {
      EXPECT_NE(w.what.find("0000000001.bin"), std::string::npos) << w.what;
    }
}

// Found by fuzz_kitti_raw: a status field far outside int's range was cast to int (undefined behaviour).
TEST(KittiRawOxts, StatusFieldsMustBeSmallWholeNumbers) {
  TempDir dir;
  const fs::path file = dir.path() / "0000000000.txt";
  auto record = [](const std::string& navstat) {
    std::string text = "49.0 8.4 115.0";
    for (int i = 3; i < 25; ++i) text += " 0.1";
    return text + " " + navstat + " 10 5 5 5\n";
  };
  for (const char* good : {"4", "-1"}) {  // -1 occurs in KITTI's own drives
    testing::WriteBytes(file, record(good));
    EXPECT_TRUE(ReadOxtsFile(file).ok()) << good;
  }
  for (const char* bad : {"4.88889e+17", "2.5", "-1e9"}) {
    testing::WriteBytes(file, record(bad));
    auto read = ReadOxtsFile(file);
    ASSERT_FALSE(read.ok()) << bad;
    EXPECT_NE(read.error().find("field 26 (navstat) is "), std::string::npos) << read.error();
    EXPECT_NE(read.error().find("not a whole number within +-1000"), std::string::npos) << read.error();
  }
}

TEST(KittiRawDrive, BadInputIsAClearError) {
  {
    MadeUpDrive made;
    fs::remove(made.date / "calib_velo_to_cam.txt");
    testing::WriteBytes(made.drive / "velodyne_points" / "timestamps.txt", MadeUpDrive::Stamp(0) + "\n");
    made.Scan(0, FourPoints());
    auto reader = OpenDataset(made.drive);
    ASSERT_FALSE(reader.ok());
    EXPECT_NE(reader.error().find("calib_velo_to_cam.txt: missing"), std::string::npos) << reader.error();
    EXPECT_NE(reader.error().find("looked in " + made.date.string()), std::string::npos) << reader.error();
  }
  {
    MadeUpDrive made;
    testing::WriteBytes(made.drive / "velodyne_points" / "timestamps.txt",
                        MadeUpDrive::Stamp(0) + "\n26/09/2011 13:08\n");
    made.Scan(0, FourPoints());
    auto reader = OpenDataset(made.drive);
    ASSERT_FALSE(reader.ok());
    EXPECT_NE(reader.error().find("timestamps.txt:2: '26/09/2011 13:08' is not a KITTI time"),
              std::string::npos)
        << reader.error();
  }
  {
    MadeUpDrive made;
    testing::WriteBytes(made.drive / "velodyne_points" / "timestamps.txt",
                        MadeUpDrive::Stamp(5) + "\n" + MadeUpDrive::Stamp(1) + "\n");
    made.Scan(0, FourPoints());
    made.Scan(1, FourPoints());
    auto reader = OpenDataset(made.drive);
    ASSERT_FALSE(reader.ok());
    EXPECT_NE(reader.error().find("the stamp of frame 1"), std::string::npos) << reader.error();
  }
  {
    MadeUpDrive made;  // an image of 8 x 5 px where the calibration says 8 x 4
    fs::remove_all(made.drive / "velodyne_points");
    fs::create_directories(made.drive / "image_02" / "data");
    testing::WriteBytes(made.drive / "image_02" / "timestamps.txt", MadeUpDrive::Stamp(0) + "\n");
    cv::imwrite((made.drive / "image_02" / "data" / "0000000000.png").string(),
                cv::Mat(5, 8, CV_8UC3, cv::Scalar(1, 2, 3)));
    testing::WriteBytes(made.drive / "oxts" / "timestamps.txt", MadeUpDrive::Stamp(0) + "\n");
    made.Oxts(0);
    auto reader = OpenDataset(made.drive);
    ASSERT_TRUE(reader.ok()) << reader.error();
    Expected<std::optional<Measurement>> next = std::optional<Measurement>();
    do next = (*reader)->Next();
    while (next.ok() && next->has_value());
    ASSERT_FALSE(next.ok());
    EXPECT_NE(next.error().find("image is 8 x 5 px, the calibration (calib_cam_to_cam.txt) says 8 x 4"),
              std::string::npos)
        << next.error();
  }
}

}  // namespace
}  // namespace uf
