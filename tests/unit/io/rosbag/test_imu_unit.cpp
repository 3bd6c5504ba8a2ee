// IMU acceleration unit: detection from the median norm, and the gate that holds the first second back.
#include <gtest/gtest.h>

#include "odometry/io/rosbag/imu_unit.h"

namespace uf {
namespace {

ImuSample Sample(Stamp stamp, double acc_z) {
  ImuSample sample;
  sample.stamp = stamp;
  sample.acc = {0.1, -0.2, acc_z};
  sample.gyro = {0.01, 0.02, 0.03};
  return sample;
}

TEST(ImuUnit, MedianNormDecidesTheUnit) {
  const std::vector<double> in_g = {0.98, 1.02, 1.0, 25.0 /* a bump */, 0.99};
  const std::vector<double> in_si = {9.7, 9.81, 9.9, 0.0 /* a glitch */, 9.8};
  EXPECT_EQ(*DetectImuAccelUnit(in_g, "/imu"), ImuAccelUnit::kStandardGravity);
  EXPECT_EQ(*DetectImuAccelUnit(in_si, "/imu"), ImuAccelUnit::kMetersPerSecond2);
  const std::vector<double> neither = {3.0, 3.1, 2.9};
  const auto unit = DetectImuAccelUnit(neither, "/imu/data_raw");
  ASSERT_FALSE(unit.ok());
  EXPECT_NE(unit.error().find("/imu/data_raw"), std::string::npos) << unit.error();
  EXPECT_NE(unit.error().find("3"), std::string::npos) << unit.error();
  EXPECT_FALSE(DetectImuAccelUnit({}, "/imu").ok());
}

TEST(ImuUnit, GateHoldsTheFirstSecondThenConvertsG) {
  ImuUnitGate gate(ImuAccelUnit::kAuto, "/imu");
  std::vector<ImuSample> ready;
  for (int i = 0; i < 100; ++i) {  // 100 Hz: 0.00 .. 0.99 s
    ASSERT_TRUE(gate.Push(Sample(i * 10'000'000, 1.0), ready).ok());
    EXPECT_TRUE(ready.empty());
  }
  ASSERT_TRUE(gate.Push(Sample(1'000'000'000, 1.0), ready).ok());
  ASSERT_TRUE(gate.resolved());
  EXPECT_EQ(gate.unit(), ImuAccelUnit::kStandardGravity);
  ASSERT_EQ(ready.size(), 101u);
  for (std::size_t i = 0; i < ready.size(); ++i) {
    EXPECT_EQ(ready[i].stamp, static_cast<Stamp>(i) * 10'000'000);  // order kept
    EXPECT_DOUBLE_EQ(ready[i].acc.z(), kStandardGravity);
    EXPECT_DOUBLE_EQ(ready[i].acc.x(), 0.1 * kStandardGravity);
    EXPECT_DOUBLE_EQ(ready[i].gyro.z(), 0.03);  // gyro untouched
  }
  ready.clear();
  ASSERT_TRUE(gate.Push(Sample(2'000'000'000, 1.0), ready).ok());
  ASSERT_EQ(ready.size(), 1u);  // passes straight through now
}

TEST(ImuUnit, ConfiguredUnitPassesThroughAndFlushDecidesShortRecordings) {
  ImuUnitGate configured(ImuAccelUnit::kMetersPerSecond2, "/imu");
  std::vector<ImuSample> ready;
  ASSERT_TRUE(configured.Push(Sample(0, 1.0), ready).ok());
  ASSERT_EQ(ready.size(), 1u);
  EXPECT_DOUBLE_EQ(ready[0].acc.z(), 1.0);

  ImuUnitGate short_topic(ImuAccelUnit::kAuto, "/imu");
  ready.clear();
  ASSERT_TRUE(short_topic.Push(Sample(0, 9.81), ready).ok());
  ASSERT_TRUE(short_topic.Push(Sample(5'000'000, 9.81), ready).ok());
  EXPECT_TRUE(ready.empty());
  ASSERT_TRUE(short_topic.Flush(ready).ok());
  EXPECT_EQ(short_topic.unit(), ImuAccelUnit::kMetersPerSecond2);
  EXPECT_EQ(ready.size(), 2u);

  ImuUnitGate bad(ImuAccelUnit::kAuto, "/imu");
  ready.clear();
  ASSERT_TRUE(bad.Push(Sample(0, 3.0), ready).ok());
  EXPECT_FALSE(bad.Push(Sample(kNanosecondsPerSecond, 3.0), ready).ok());
}

}  // namespace
}  // namespace uf
