// The recorded Husky bag (../shared/data): counts, stamps and IMU unit against what is known of it.
#include <gtest/gtest.h>

#include <map>

#include "odometry/io/rosbag/rosbag_reader.h"
#include "tests/support/temp_dir.h"

namespace uf {
namespace {

TEST(RosBagHusky, ReadsEveryImuWheelAndGnssMessage) {
  const std::string data = testing::SharedData();
  if (data.empty()) GTEST_SKIP() << "../shared/data is absent: the Husky bag test needs the recorded data";
  const std::string path = data + "/husky-imu-wheel-gps/husky_watertown_2015-05-21.bag";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent";

  auto reader = OpenRosBag(path, {});
  ASSERT_TRUE(reader.ok()) << reader.error();
  const DatasetDescription& description = (*reader)->description();
  std::map<SensorKind, int> counts;
  std::map<int, Stamp> last_stamp;
  int backwards = 0;
  while (true) {
    auto next = (*reader)->Next();
    ASSERT_TRUE(next.ok()) << next.error();
    if (!next->has_value()) break;
    const Measurement& m = **next;
    ++counts[KindOf(m.data)];
    const Stamp stamp = StampOf(m.data);
    if (last_stamp.contains(m.stream) && stamp <= last_stamp[m.stream]) ++backwards;
    last_stamp[m.stream] = stamp;
  }
  EXPECT_EQ(counts[SensorKind::kImu], 11865);
  EXPECT_EQ(counts[SensorKind::kWheel], 3952);
  EXPECT_EQ(counts[SensorKind::kGnss], 989);
  EXPECT_EQ(counts[SensorKind::kLidar], 0);
  EXPECT_EQ(backwards, 0);  // stamps increase within every stream
  for (const StreamInfo& info : description.streams) {
    if (info.kind == SensorKind::kImu) {
      EXPECT_EQ(info.imu_accel_unit, "m/s^2") << info.name;
    }
  }
  EXPECT_TRUE((*reader)->warnings().empty());
}

}  // namespace
}  // namespace uf
