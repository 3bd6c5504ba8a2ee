#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include "odometry/eval/plots.h"
#include "odometry/eval/series_plot.h"
#include "tests/support/temp_dir.h"

// Under AddressSanitizer (UF_SANITIZE) LeakSanitizer reports fontconfig's process-wide caches, which PLplot's
// cairo driver fills through Pango; they are not leaks of ours. This is LeakSanitizer's documented hook.
extern "C" const char* __lsan_default_suppressions() { return "leak:libfontconfig.so\n"; }

namespace uf {
namespace {

namespace fs = std::filesystem;

// A blank 1280x960 page from PLplot's pngcairo device (white, nothing drawn) is about 6 KB; a plot with axes,
// text and data is several times that.
constexpr std::uintmax_t kBlankPageBytes = 6 * 1024;

// A spiral reference and an estimate pushed outwards by a known, growing offset (error[i] = 0.05 + 0.95 i/n).
struct SpiralCase {
  std::vector<Eigen::Vector3d> reference, estimate;
  std::vector<double> error, seconds;
};

SpiralCase Spiral(int n) {
  SpiralCase c;
  for (int i = 0; i < n; ++i) {
    const double angle = 0.01 * i, radius = 5.0 + 2.0 * angle;
    const Eigen::Vector3d outward(std::cos(angle), std::sin(angle), 0.0);
    const Eigen::Vector3d p = radius * outward + Eigen::Vector3d(0, 0, 0.1 * angle);
    const double error = 0.05 + 0.95 * i / n;
    c.reference.push_back(p);
    c.estimate.push_back(p + error * outward);
    c.error.push_back(error);
    c.seconds.push_back(1.7e9 + 0.1 * i);  // absolute stamps; the plot counts from the first
  }
  return c;
}

std::uint32_t BigEndian32(const std::string& bytes, std::size_t at) {
  std::uint32_t value = 0;
  for (std::size_t i = 0; i < 4; ++i) value = (value << 8) | static_cast<unsigned char>(bytes[at + i]);
  return value;
}

// Checks the PNG signature and that the first chunk is IHDR with the given size (big-endian at bytes 16..23).
void ExpectPng(const std::string& path, std::uint32_t width, std::uint32_t height) {
  const std::string bytes = testing::ReadText(path);
  ASSERT_GE(bytes.size(), 24u) << path;
  EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8)) << path;
  EXPECT_EQ(bytes.substr(12, 4), "IHDR") << path;
  EXPECT_EQ(BigEndian32(bytes, 16), width) << path;
  EXPECT_EQ(BigEndian32(bytes, 20), height) << path;
}

class PlotsTest : public ::testing::Test {
 protected:
  std::string Path(const std::string& name) const { return dir_.File(name); }

  // The folder holds exactly these file names (no temporary left over).
  void ExpectFolderHolds(std::vector<std::string> names) const {
    std::vector<std::string> found;
    for (const auto& entry : fs::directory_iterator(dir_.path()))
      found.push_back(entry.path().filename().string());
    std::sort(found.begin(), found.end());
    std::sort(names.begin(), names.end());
    EXPECT_EQ(found, names);
  }

  testing::TempDir dir_;
};

TEST_F(PlotsTest, TopViewIsAPngOfTheRequestedSize) {
  const SpiralCase c = Spiral(2000);
  const Status status = WriteTopViewPlot(Path("top.png"), c.reference, c.estimate, c.error,
                                         "ATE (SE(3) aligned)", "APE translation [m]");
  ASSERT_TRUE(status.ok()) << status.message();
  ExpectPng(Path("top.png"), 1280, 960);
  ExpectFolderHolds({"top.png"});
}

TEST_F(PlotsTest, ErrorPlotIsAPngOfTheRequestedSize) {
  const SpiralCase c = Spiral(2000);
  const Status status = WriteErrorPlot(Path("error.png"), c.seconds, c.error, ComputeStats(c.error), "APE",
                                       "time [s]", "APE translation [m]");
  ASSERT_TRUE(status.ok()) << status.message();
  ExpectPng(Path("error.png"), 1280, 960);
  ExpectFolderHolds({"error.png"});
}

// Without a PNG decoder the drawing is judged by compressed size: a blank page compresses to ~6 KB; axes and
// text alone (a two-pose trajectory) to several times that; the spiral's coloured segments and the error
// series add clearly more. A plot that drew nothing, or only its frame, fails one of the two checks.
TEST_F(PlotsTest, PlotsAreNotBlankAndShowTheData) {
  const SpiralCase spiral = Spiral(2000);
  const SpiralCase tiny = Spiral(2);
  ASSERT_TRUE(WriteTopViewPlot(Path("spiral_top.png"), spiral.reference, spiral.estimate, spiral.error, "ATE",
                               "APE [m]")
                  .ok());
  ASSERT_TRUE(
      WriteTopViewPlot(Path("tiny_top.png"), tiny.reference, tiny.estimate, tiny.error, "ATE", "APE [m]")
          .ok());
  // A saw-tooth error series fills the time axis with line pixels.
  std::vector<double> saw;
  for (std::size_t i = 0; i < spiral.error.size(); ++i)
    saw.push_back(0.2 + 0.1 * static_cast<double>(i % 25));
  ASSERT_TRUE(WriteErrorPlot(Path("spiral_error.png"), spiral.seconds, saw, ComputeStats(saw), "APE", "t [s]",
                             "APE [m]")
                  .ok());
  ASSERT_TRUE(WriteErrorPlot(Path("tiny_error.png"), tiny.seconds, tiny.error, ComputeStats(tiny.error),
                             "APE", "t [s]", "APE [m]")
                  .ok());

  for (const char* name : {"spiral_top.png", "tiny_top.png", "spiral_error.png", "tiny_error.png"})
    EXPECT_GT(fs::file_size(Path(name)), 4 * kBlankPageBytes) << name;
  EXPECT_GT(fs::file_size(Path("spiral_top.png")), fs::file_size(Path("tiny_top.png")) + 20 * 1024);
  EXPECT_GT(fs::file_size(Path("spiral_error.png")), fs::file_size(Path("tiny_error.png")) + 20 * 1024);
}

TEST_F(PlotsTest, ReplacesAnExistingFileAndPrintsNothing) {
  std::ofstream(Path("top.png")) << "old";
  const SpiralCase c = Spiral(500);
  ::testing::internal::CaptureStdout();
  ::testing::internal::CaptureStderr();
  const Status top = WriteTopViewPlot(Path("top.png"), c.reference, c.estimate, c.error, "t", "e");
  const Status error =
      WriteErrorPlot(Path("error.png"), c.seconds, c.error, ComputeStats(c.error), "t", "x", "y");
  std::fflush(stdout);
  std::fflush(stderr);
  EXPECT_EQ(::testing::internal::GetCapturedStdout(), "");
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
  ASSERT_TRUE(top.ok()) << top.message();
  ASSERT_TRUE(error.ok()) << error.message();
  ExpectPng(Path("top.png"), 1280, 960);
  ExpectFolderHolds({"top.png", "error.png"});
}

TEST_F(PlotsTest, SinglePoseAndConstantErrorStillPlot) {
  const std::vector<Eigen::Vector3d> one{Eigen::Vector3d(1, 2, 3)};
  const std::vector<double> e{0.5}, t{42.0};
  EXPECT_TRUE(WriteTopViewPlot(Path("one_top.png"), one, one, e, "one", "e").ok());
  EXPECT_TRUE(WriteErrorPlot(Path("one_error.png"), t, e, ComputeStats(e), "one", "x", "y").ok());
  const SpiralCase c = Spiral(100);
  const std::vector<double> zero(c.error.size(), 0.0);
  EXPECT_TRUE(WriteTopViewPlot(Path("zero_top.png"), c.reference, c.reference, zero, "zero", "e").ok());
  EXPECT_TRUE(
      WriteErrorPlot(Path("zero_error.png"), c.seconds, zero, ComputeStats(zero), "zero", "x", "y").ok());
  for (const char* name : {"one_top.png", "one_error.png", "zero_top.png", "zero_error.png"})
    ExpectPng(Path(name), 1280, 960);
}

TEST_F(PlotsTest, AwkwardTextIsDrawnLiterally) {
  // '#' is PLplot's escape character, the rest is invalid UTF-8, control characters and overlong text.
  const std::string awkward = "#u #d ## 100% <b>&amp; \xff\xfe \x01\t" + std::string(2000, 'x');
  const SpiralCase c = Spiral(200);
  EXPECT_TRUE(WriteTopViewPlot(Path("top.png"), c.reference, c.estimate, c.error, awkward, awkward).ok());
  EXPECT_TRUE(
      WriteErrorPlot(Path("error.png"), c.seconds, c.error, ComputeStats(c.error), awkward, awkward, awkward)
          .ok());
  ExpectFolderHolds({"top.png", "error.png"});
}

TEST_F(PlotsTest, BadInputIsAnErrorAndLeavesNoFile) {
  const SpiralCase c = Spiral(100);
  const ErrorStats stats = ComputeStats(c.error);
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  const std::string path = Path("bad.png");
  const auto expect_error = [&](const Status& status, const std::string& what) {
    EXPECT_FALSE(status.ok()) << what;
    EXPECT_NE(status.message().find(path), std::string::npos) << what << ": " << status.message();
    EXPECT_TRUE(fs::is_empty(dir_.path())) << what;  // neither the PNG nor a temporary
  };

  std::vector<double> nan_error = c.error;
  nan_error[7] = nan;
  expect_error(WriteTopViewPlot(path, c.reference, c.estimate, nan_error, "t", "e"), "NaN error (top view)");
  expect_error(WriteErrorPlot(path, c.seconds, nan_error, stats, "t", "x", "y"), "NaN error (error plot)");
  std::vector<Eigen::Vector3d> inf_estimate = c.estimate;
  inf_estimate[3].y() = inf;
  expect_error(WriteTopViewPlot(path, c.reference, inf_estimate, c.error, "t", "e"), "Inf estimate");
  std::vector<Eigen::Vector3d> nan_reference = c.reference;
  nan_reference[0].x() = nan;
  expect_error(WriteTopViewPlot(path, nan_reference, c.estimate, c.error, "t", "e"), "NaN reference");
  std::vector<double> inf_seconds = c.seconds;
  inf_seconds.back() = -inf;
  expect_error(WriteErrorPlot(path, inf_seconds, c.error, stats, "t", "x", "y"), "Inf stamp");
  std::vector<double> huge_error = c.error;
  huge_error[1] = 1e300;
  expect_error(WriteErrorPlot(path, c.seconds, huge_error, stats, "t", "x", "y"), "error too large to plot");
  ErrorStats nan_stats = stats;
  nan_stats.median = nan;
  expect_error(WriteErrorPlot(path, c.seconds, c.error, nan_stats, "t", "x", "y"), "NaN statistic");

  const std::vector<double> short_error(c.error.begin(), c.error.end() - 1);
  expect_error(WriteTopViewPlot(path, c.reference, c.estimate, short_error, "t", "e"),
               "error/estimate sizes");
  expect_error(WriteErrorPlot(path, c.seconds, short_error, stats, "t", "x", "y"), "seconds/error sizes");

  expect_error(WriteTopViewPlot(path, {}, c.estimate, c.error, "t", "e"), "empty reference");
  expect_error(WriteTopViewPlot(path, c.reference, {}, {}, "t", "e"), "empty estimate");
  expect_error(WriteErrorPlot(path, {}, {}, stats, "t", "x", "y"), "empty error series");
  ExpectFolderHolds({});
}

TEST_F(PlotsTest, FailureKeepsThePreviousFile) {
  std::ofstream(Path("top.png")) << "previous";
  const SpiralCase c = Spiral(100);
  std::vector<double> bad = c.error;
  bad[0] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(WriteTopViewPlot(Path("top.png"), c.reference, c.estimate, bad, "t", "e").ok());
  EXPECT_EQ(testing::ReadText(Path("top.png")), "previous");
  ExpectFolderHolds({"top.png"});
}

TEST_F(PlotsTest, UnwritableFolderIsAnError) {
  const SpiralCase c = Spiral(100);
  const Status top = WriteTopViewPlot("/nonexistent/x.png", c.reference, c.estimate, c.error, "t", "e");
  ASSERT_FALSE(top.ok());
  EXPECT_NE(top.message().find("/nonexistent/x.png"), std::string::npos) << top.message();
  const Status error =
      WriteErrorPlot("/nonexistent/x.png", c.seconds, c.error, ComputeStats(c.error), "t", "x", "y");
  ASSERT_FALSE(error.ok());
  EXPECT_FALSE(fs::exists("/nonexistent/x.png"));
  // A folder where the PNG should go cannot be replaced by it.
  fs::create_directory(Path("taken.png"));
  const Status taken = WriteTopViewPlot(Path("taken.png"), c.reference, c.estimate, c.error, "t", "e");
  EXPECT_FALSE(taken.ok());
  EXPECT_TRUE(fs::is_directory(Path("taken.png")));
  ExpectFolderHolds({"taken.png"});
}

TEST_F(PlotsTest, SeriesPlotShowsItsDataOrRefusesBadInput) {
  const SpiralCase c = Spiral(40);
  ASSERT_TRUE(WriteSeriesPlot(Path("series.png"), c.seconds, c.error, "candidates",
                              SeriesLevel{0.5, "locked"}, "Series", "t [s]", "v")
                  .ok());
  ASSERT_TRUE(WriteSeriesPlot(Path("one.png"), {3.0}, {1.0}, "one", std::nullopt, "One", "t", "v").ok());
  ExpectPng(Path("series.png"), 1280, 960);
  ExpectPng(Path("one.png"), 1280, 960);
  EXPECT_GT(fs::file_size(Path("series.png")), 4 * kBlankPageBytes);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const auto& [seconds, values, level] :
       {std::tuple<std::vector<double>, std::vector<double>, double>{{}, {}, 0.0},
        {{1.0, 2.0}, {1.0}, 0.0},
        {{1.0, 2.0}, {1.0, nan}, 0.0},
        {{1.0, 2.0}, {1.0, 2.0}, nan}}) {
    const Status bad =
        WriteSeriesPlot(Path("bad.png"), seconds, values, "s", SeriesLevel{level, "l"}, "t", "x", "y");
    EXPECT_FALSE(bad.ok());
    EXPECT_NE(bad.message().find("bad.png"), std::string::npos) << bad.message();
  }
  ExpectFolderHolds({"series.png", "one.png"});
}

TEST_F(PlotsTest, ThreeSeriesPlotInOneOrRefuseBadInput) {
  const SpiralCase c = Spiral(40);
  std::vector<double> y = c.error, z = c.error;
  for (double& v : y) v = -v;
  for (double& v : z) v *= 0.5;
  ASSERT_TRUE(WriteSeriesPlot(Path("xyz.png"), c.seconds, {{"x", c.error}, {"y", y}, {"z", z}}, std::nullopt,
                              "Three", "t [s]", "v")
                  .ok());
  ExpectPng(Path("xyz.png"), 1280, 960);
  EXPECT_GT(fs::file_size(Path("xyz.png")), 4 * kBlankPageBytes);
  const std::vector<double> short_one(c.seconds.size() - 1, 1.0);
  for (const std::vector<NamedSeries>& bad :
       {std::vector<NamedSeries>{}, std::vector<NamedSeries>{{"x", c.error}, {"y", y}, {"z", z}, {"w", z}},
        std::vector<NamedSeries>{{"x", c.error}, {"y", short_one}}}) {
    const Status status = WriteSeriesPlot(Path("bad.png"), c.seconds, bad, std::nullopt, "t", "x", "y");
    EXPECT_FALSE(status.ok());
    EXPECT_NE(status.message().find("bad.png"), std::string::npos) << status.message();
  }
  ExpectFolderHolds({"xyz.png"});
}

TEST_F(PlotsTest, ThreadsCanPlotAtTheSameTime) {
  const SpiralCase c = Spiral(300);
  const ErrorStats stats = ComputeStats(c.error);
  std::vector<std::thread> threads;
  std::vector<int> ok(4, 0);
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&, t] {
      const std::string name = std::to_string(t);
      ok[t] =
          WriteTopViewPlot(Path("top" + name + ".png"), c.reference, c.estimate, c.error, name, "e").ok() &&
          WriteErrorPlot(Path("error" + name + ".png"), c.seconds, c.error, stats, name, "x", "y").ok();
    });
  }
  for (std::thread& thread : threads) thread.join();
  for (int t = 0; t < 4; ++t) {
    EXPECT_TRUE(ok[t]) << t;
    ExpectPng(Path("top" + std::to_string(t) + ".png"), 1280, 960);
    ExpectPng(Path("error" + std::to_string(t) + ".png"), 1280, 960);
  }
}

}  // namespace
}  // namespace uf
