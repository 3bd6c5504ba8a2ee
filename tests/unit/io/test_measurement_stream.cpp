#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "odometry/io/measurement_stream.h"
#include "tests/support/scripted_reader.h"

namespace uf {
namespace {

using test::Gnss;
using test::Imu;
using test::Info;
using test::Scan;
using test::ScriptedReader;

constexpr Stamp kMs = 1'000'000;

std::vector<Measurement> Drain(MeasurementStream& stream) {
  std::vector<Measurement> out;
  while (true) {
    Expected<std::optional<Measurement>> next = stream.Next();
    EXPECT_TRUE(next.ok()) << next.error();
    if (!next.ok() || !next->has_value()) return out;
    out.push_back(std::move(**next));
  }
}

MeasurementStream MakeStream(ScriptedReader& reader, MeasurementStreamOptions options = {}) {
  Expected<MeasurementStream> stream = MeasurementStream::Create(reader, std::move(options));
  EXPECT_TRUE(stream.ok()) << stream.error();
  return std::move(stream).value();
}

// Three sensors whose records are stored by arrival time (stamp + a per-sensor latency with jitter):
// the stream must give back exactly the stamp-sorted sequence, nothing dropped.
TEST(MeasurementStream, MergesStreamsStoredByArrivalIntoStampOrder) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<Stamp> jitter(0, 40 * kMs);
  struct Record {
    Stamp arrival;
    Measurement m;
  };
  std::vector<Record> records;
  const Stamp latency[3] = {2 * kMs, 150 * kMs, 60 * kMs};
  const Stamp period[3] = {5 * kMs, 100 * kMs, 400 * kMs};
  for (int s = 0; s < 3; ++s) {
    Stamp last_arrival = 0;
    for (Stamp t = 1000 * kMs + s; t < 11000 * kMs; t += period[s]) {
      last_arrival =
          std::max(last_arrival, t + latency[s] + jitter(rng));  // a sensor's records stay in order
      records.push_back(
          {last_arrival, s == 1 ? Scan(s, t, t + 99 * kMs) : (s == 0 ? Imu(s, t) : Gnss(s, t))});
    }
  }
  std::stable_sort(records.begin(), records.end(), [](auto& a, auto& b) { return a.arrival < b.arrival; });
  std::vector<Measurement> script;
  for (auto& r : records) script.push_back(r.m);
  std::vector<Measurement> expected = script;
  std::stable_sort(expected.begin(), expected.end(), [](const Measurement& a, const Measurement& b) {
    return StampOf(a.data) < StampOf(b.data);
  });

  ScriptedReader reader(
      {Info("/imu", SensorKind::kImu), Info("/points", SensorKind::kLidar), Info("/fix", SensorKind::kGnss)},
      script);
  MeasurementStream stream = MakeStream(reader);
  std::vector<Measurement> merged = Drain(stream);
  ASSERT_EQ(merged.size(), expected.size());
  for (std::size_t i = 0; i < merged.size(); ++i) {
    ASSERT_EQ(StampOf(merged[i].data), StampOf(expected[i].data)) << i;
    ASSERT_EQ(merged[i].stream, expected[i].stream) << i;
  }
  EXPECT_TRUE(stream.finished());
  EXPECT_TRUE(stream.warnings().empty());
  EXPECT_EQ(stream.drop_counts()[0].delivered + stream.drop_counts()[1].delivered +
                stream.drop_counts()[2].delivered,
            static_cast<std::int64_t>(script.size()));
}

TEST(MeasurementStream, EndIsExplicitAndStays) {
  ScriptedReader reader({Info("/imu", SensorKind::kImu)}, {Imu(0, 10)});
  MeasurementStream stream = MakeStream(reader);
  EXPECT_FALSE(stream.finished());
  ASSERT_TRUE(stream.Next()->has_value());
  for (int i = 0; i < 3; ++i) {
    Expected<std::optional<Measurement>> next = stream.Next();
    ASSERT_TRUE(next.ok());
    EXPECT_FALSE(next->has_value());
    EXPECT_TRUE(stream.finished());
  }
}

TEST(MeasurementStream, AppliesTimeOffsetsByStreamNameBeforeKind) {
  ScriptedReader reader(
      {Info("/imu", SensorKind::kImu), Info("/points", SensorKind::kLidar),
       Info("/points_rear", SensorKind::kLidar)},
      {Imu(0, 1000 * kMs), Scan(1, 1000 * kMs, 1100 * kMs), Scan(2, 1000 * kMs, 1100 * kMs)});
  MeasurementStreamOptions options;
  options.time_offsets = {{"lidar", -30 * kMs}, {"/points_rear", 20 * kMs}, {"/imu", 5}};
  MeasurementStream stream = MakeStream(reader, options);
  std::vector<Measurement> out = Drain(stream);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0].stream, 1);
  EXPECT_EQ(StampOf(out[0].data), 970 * kMs);
  EXPECT_EQ(std::get<LidarScan>(out[0].data).end, 1070 * kMs);
  EXPECT_EQ(out[1].stream, 0);
  EXPECT_EQ(StampOf(out[1].data), 1000 * kMs + 5);
  EXPECT_EQ(out[2].stream, 2);
  EXPECT_EQ(StampOf(out[2].data), 1020 * kMs);
}

TEST(MeasurementStream, OffsetForUnknownStreamIsAnErrorNamingIt) {
  ScriptedReader reader({Info("/imu", SensorKind::kImu)}, {});
  MeasurementStreamOptions options;
  options.time_offsets = {{"/camera", 3}};
  Expected<MeasurementStream> stream = MeasurementStream::Create(reader, options);
  ASSERT_FALSE(stream.ok());
  EXPECT_NE(stream.error().find("'/camera'"), std::string::npos) << stream.error();
  EXPECT_NE(stream.error().find("/imu"), std::string::npos) << stream.error();
}

TEST(MeasurementStream, DropsBackwardsAndDuplicateStampsAndCountsThem) {
  ScriptedReader reader({Info("/imu", SensorKind::kImu)},
                        {Imu(0, 10), Imu(0, 20), Imu(0, 20), Imu(0, 15), Imu(0, 30), Imu(0, 30), Imu(0, 40)});
  MeasurementStream stream = MakeStream(reader);
  std::vector<Measurement> out = Drain(stream);
  std::vector<Stamp> stamps;
  for (auto& m : out) stamps.push_back(StampOf(m.data));
  EXPECT_EQ(stamps, (std::vector<Stamp>{10, 20, 30, 40}));
  EXPECT_EQ(stream.drop_counts()[0].backwards, 1);
  EXPECT_EQ(stream.drop_counts()[0].duplicates, 2);
  std::vector<ReadWarning> warnings = stream.warnings();
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_EQ(warnings[0].stream, "/imu");
  EXPECT_EQ(warnings[0].count, 1);
  EXPECT_EQ(warnings[1].count, 2);
}

// A sensor that goes quiet holds the others back for the reorder window only; what it sends later than
// that, older than what was already handed out, is dropped as late.
TEST(MeasurementStream, QuietStreamHoldsOthersForTheReorderWindowOnly) {
  std::vector<Measurement> script = {Gnss(1, 0)};
  for (Stamp t = 1; t <= 3000; ++t) script.push_back(Imu(0, t * kMs));  // 1 kHz for 3 s
  script.push_back(Gnss(1, 500 * kMs));                                 // 2.5 s late
  script.push_back(Gnss(1, 2999 * kMs + 500'000));                      // in time
  ScriptedReader reader({Info("/imu", SensorKind::kImu), Info("/fix", SensorKind::kGnss)}, script);
  MeasurementStreamOptions options;
  options.reorder_window = 200 * kMs;
  MeasurementStream stream = MakeStream(reader, options);
  ASSERT_TRUE(stream.Next()->has_value());  // the GNSS fix at 0
  Expected<std::optional<Measurement>> first_imu = stream.Next();
  ASSERT_TRUE(first_imu.ok() && first_imu->has_value());
  EXPECT_EQ(StampOf((*first_imu)->data), 1 * kMs);
  // Released once the newest stamp read is a window past it: ~200 IMU samples buffered, not 3000.
  EXPECT_LE(reader.delivered(), 1u + 202u);
  EXPECT_GE(reader.delivered(), 1u + 200u);
  std::vector<Measurement> rest = Drain(stream);
  EXPECT_EQ(rest.size(), 2999u + 1u);
  EXPECT_EQ(stream.drop_counts()[1].late, 1);
  EXPECT_EQ(stream.drop_counts()[1].delivered, 2);
}

TEST(MeasurementStream, BufferBoundReleasesTheOldest) {
  std::vector<Measurement> script = {Gnss(1, 0)};
  for (Stamp t = 1; t <= 1000; ++t) script.push_back(Imu(0, t * kMs));
  ScriptedReader reader({Info("/imu", SensorKind::kImu), Info("/fix", SensorKind::kGnss)}, script);
  MeasurementStreamOptions options;
  options.reorder_window = 3600'000 * kMs;
  options.max_buffered = 50;
  MeasurementStream stream = MakeStream(reader, options);
  ASSERT_TRUE(stream.Next()->has_value());
  ASSERT_TRUE(stream.Next()->has_value());
  EXPECT_LE(reader.delivered(), 52u);
  EXPECT_EQ(Drain(stream).size(), 999u);
}

TEST(MeasurementStream, ReaderErrorsPassThrough) {
  ScriptedReader reader({Info("/imu", SensorKind::kImu)}, {Imu(0, 1), Imu(0, 2), Imu(0, 3)});
  reader.FailAt(2, "bag.bag: chunk at byte 4096: bz2 data corrupt");
  MeasurementStream stream = MakeStream(reader);
  Expected<std::optional<Measurement>> next = stream.Next();
  while (next.ok() && next->has_value()) next = stream.Next();
  ASSERT_FALSE(next.ok());
  EXPECT_NE(next.error().find("byte 4096"), std::string::npos);
}

}  // namespace
}  // namespace uf
