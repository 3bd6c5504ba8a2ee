#include <gtest/gtest.h>

#include <cmath>

#include "odometry/io/stream_diagnostics.h"

namespace uf {
namespace {

constexpr Stamp kMs = 1'000'000;

TEST(StreamDiagnostics, RegularStreamIsOkWithItsRate) {
  StreamDiagnostics diagnostics(1);
  for (int i = 0; i < 101; ++i) diagnostics.Add(0, 5000 * kMs + i * 10 * kMs);  // 100 Hz for 1 s
  StreamTimeReport r = diagnostics.Report(0);
  EXPECT_EQ(r.count, 101);
  EXPECT_EQ(r.first, 5000 * kMs);
  EXPECT_EQ(r.last, 6000 * kMs);
  EXPECT_NEAR(r.rate_hz, 100.0, 1e-9);
  EXPECT_NEAR(r.median_period_s, 0.01, 1e-9);
  EXPECT_NEAR(r.jitter_percent, 0.0, 1e-3);
  EXPECT_EQ(r.verdict, StreamVerdict::kOk);
  EXPECT_TRUE(r.findings.empty());
}

// 100 periods, 10 ms and 20 ms alternating: mean 15 ms, standard deviation 5 ms, jitter 33.3 %.
TEST(StreamDiagnostics, JitterIsTheSpreadOfThePeriods) {
  StreamDiagnostics diagnostics(1);
  Stamp t = 0;
  for (int i = 0; i < 101; ++i) {
    diagnostics.Add(0, t);
    t += (i % 2 ? 20 : 10) * kMs;
  }
  StreamTimeReport r = diagnostics.Report(0);
  EXPECT_NEAR(r.jitter_percent, 100.0 / 3.0, 1e-3);
  EXPECT_EQ(r.gaps, 0);
  EXPECT_EQ(r.verdict, StreamVerdict::kWarning);
  ASSERT_EQ(r.findings.size(), 1u);
  EXPECT_NE(r.findings[0].find("jitter 33.3%"), std::string::npos) << r.findings[0];
}

TEST(StreamDiagnostics, CountsGapsBackwardsAndDuplicates) {
  StreamDiagnostics diagnostics(1);
  const Stamp stamps[] = {0, 10, 20, 20, 30, 25, 40, 540, 550, 560};  // ms
  for (Stamp s : stamps) diagnostics.Add(0, s * kMs);
  StreamTimeReport r = diagnostics.Report(0);
  EXPECT_EQ(r.count, 10);
  EXPECT_EQ(r.duplicates, 1);
  EXPECT_EQ(r.backwards, 1);
  EXPECT_EQ(r.gaps, 1);
  EXPECT_NEAR(r.largest_gap_s, 0.5, 1e-6);
  // 1 backwards stamp in 10 is more than 1 %: bad.
  EXPECT_EQ(r.verdict, StreamVerdict::kBad);
  EXPECT_EQ(r.findings.size(), 3u);
}

TEST(StreamDiagnostics, EmptyStreamIsBad) {
  StreamDiagnostics diagnostics(2);
  diagnostics.Add(0, 1);
  StreamTimeReport r = diagnostics.Report(1);
  EXPECT_EQ(r.count, 0);
  EXPECT_EQ(r.verdict, StreamVerdict::kBad);
  ASSERT_EQ(r.findings.size(), 1u);
  EXPECT_EQ(r.findings[0], "no messages");
}

TEST(StreamDiagnostics, MessagesStoredLongAfterNewerOnesAreOutOfOrder) {
  StreamDiagnosticsOptions options;
  options.reorder_window = 100 * kMs;
  StreamDiagnostics diagnostics(2, options);
  for (int i = 0; i <= 100; ++i) diagnostics.Add(0, i * 10 * kMs);  // 0 .. 1 s
  diagnostics.Add(1, 950 * kMs);                                    // 50 ms behind: fine
  diagnostics.Add(1, 800 * kMs);                                    // 200 ms behind: out of order
  StreamTimeReport r = diagnostics.Report(1);
  EXPECT_EQ(r.out_of_order, 1);
  EXPECT_EQ(r.backwards, 1);
  EXPECT_EQ(diagnostics.Report(0).out_of_order, 0);
}

}  // namespace
}  // namespace uf
