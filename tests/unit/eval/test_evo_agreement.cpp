// `ultrafusion eval` figures against evo on the trajectories of ../shared/data/trajectories (the evo test
// set): every statistic agrees to 1e-6 relative with the numbers evo 1.36 prints for the command named in
// each case (evo's own code run with numpy 1.24; the commands are in the table). A second, deliberately plain
// implementation in this file (brute-force association in double seconds, Eigen::umeyama, 4x4 matrices)
// checks the same figures independently of the library code.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>

#include "odometry/eval/evaluation.h"
#include "odometry/io/trajectory_file.h"
#include "tests/support/temp_dir.h"

namespace uf {
namespace {

enum class Metric { kApe, kRpe };

struct EvoCase {
  const char* name;
  const char* evo_command;
  const char* reference;
  const char* estimate;  // empty: the perturbed KITTI trajectory made by PerturbedKitti()
  AlignMode align;
  RpeUnit rpe_unit;
  double rpe_delta;
  double t_offset;
  Metric metric;
  std::size_t n;
  double rmse, mean, median, std, min, max;
};

const EvoCase kEvoCases[] = {
    {"A", "evo_ape tum freiburg1_xyz-groundtruth.txt freiburg1_xyz-rgbdslam.txt -a",
     "freiburg1_xyz-groundtruth.txt", "freiburg1_xyz-rgbdslam.txt", AlignMode::kSe3, RpeUnit::kFrames, 1, 0.0,
     Metric::kApe, 785, 0.013470088849733684, 0.012024498709110232, 0.011183186775061124,
     0.006070809205890603, 0.0009550461813177855, 0.03475954589500919},
    {"B", "evo_ape tum freiburg1_xyz-groundtruth.txt freiburg1_xyz-rgbdslam.txt",
     "freiburg1_xyz-groundtruth.txt", "freiburg1_xyz-rgbdslam.txt", AlignMode::kNone, RpeUnit::kFrames, 1,
     0.0, Metric::kApe, 785, 0.020079418378506592, 0.01806251843069654, 0.016517756173282164,
     0.008770887660884508, 0.0012561023047507462, 0.04328943388403233},
    {"C", "evo_rpe tum freiburg1_xyz-groundtruth.txt freiburg1_xyz-rgbdslam.txt -a --delta 1 --delta_unit f",
     "freiburg1_xyz-groundtruth.txt", "freiburg1_xyz-rgbdslam.txt", AlignMode::kSe3, RpeUnit::kFrames, 1, 0.0,
     Metric::kRpe, 784, 0.005764370848928308, 0.00481560947020396, 0.004138857799364397, 0.003168260834346882,
     0.0001710611534619414, 0.020865814532329583},
    {"D",
     "evo_rpe tum freiburg1_xyz-groundtruth.txt freiburg1_xyz-rgbdslam.txt -a --delta 0.1 --delta_unit m",
     "freiburg1_xyz-groundtruth.txt", "freiburg1_xyz-rgbdslam.txt", AlignMode::kSe3, RpeUnit::kMetres, 0.1,
     0.0, Metric::kRpe, 79, 0.014384451144396451, 0.012644112873136245, 0.011630205601738077,
     0.006858487032642013, 0.0015413055812115147, 0.038654181019498045},
    {"E", "evo_ape tum freiburg1_xyz-groundtruth.txt freiburg1_xyz-ORB_kf_mono.txt -as",
     "freiburg1_xyz-groundtruth.txt", "freiburg1_xyz-ORB_kf_mono.txt", AlignMode::kSim3, RpeUnit::kFrames, 1,
     0.0, Metric::kApe, 32, 0.009754581898685104, 0.00821869858881662, 0.007909070259951205,
     0.005254032881924017, 0.0018768480970276496, 0.02792400173407602},
    {"F", "evo_ape tum fr2_desk_groundtruth.txt fr2_desk_ORB_kf_mono.txt -as", "fr2_desk_groundtruth.txt",
     "fr2_desk_ORB_kf_mono.txt", AlignMode::kSim3, RpeUnit::kFrames, 1, 0.0, Metric::kApe, 118,
     0.007729264783424089, 0.007103615951625629, 0.0070998222113337756, 0.0030463378840978475,
     0.0012163596984309894, 0.015688557595242614},
    {"G", "evo_rpe tum fr2_desk_groundtruth.txt fr2_desk_ORB_kf_mono.txt -as --delta 1 --delta_unit m",
     "fr2_desk_groundtruth.txt", "fr2_desk_ORB_kf_mono.txt", AlignMode::kSim3, RpeUnit::kMetres, 1, 0.0,
     Metric::kRpe, 11, 0.020381580698244355, 0.018208539586048858, 0.016590113407059716, 0.009157396895534147,
     0.009101027058014311, 0.04338041165431116},
    {"H", "evo_rpe tum fr2_desk_groundtruth.txt fr2_desk_ORB_kf_mono.txt -as --delta 5 --delta_unit f",
     "fr2_desk_groundtruth.txt", "fr2_desk_ORB_kf_mono.txt", AlignMode::kSim3, RpeUnit::kFrames, 5, 0.0,
     Metric::kRpe, 23, 0.012600407708729191, 0.01096489410820514, 0.00994450336586171, 0.006208169748166544,
     0.004103076100889459, 0.032201024088187515},
    {"I", "evo_ape tum freiburg1_xyz-groundtruth.txt freiburg1_xyz-rgbdslam.txt -a --t_offset 0.005",
     "freiburg1_xyz-groundtruth.txt", "freiburg1_xyz-rgbdslam.txt", AlignMode::kSe3, RpeUnit::kFrames, 1,
     0.005, Metric::kApe, 786, 0.013460866854796435, 0.012059197890444961, 0.01123331238172022,
     0.005980859697538893, 0.00105443015286577, 0.03586909473426873},
    {"K1", "evo_ape kitti KITTI_00_gt.txt KITTI_00_perturbed.txt -a", "KITTI_00_gt.txt", "", AlignMode::kSe3,
     RpeUnit::kFrames, 1, 0.0, Metric::kApe, 4541, 1.3172645770883469, 1.1290219860946846, 1.1404590745647438,
     0.6785980555281272, 0.08644065070687001, 2.5062039725700322},
    {"K2", "evo_rpe kitti KITTI_00_gt.txt KITTI_00_perturbed.txt -a --delta 1 --delta_unit f",
     "KITTI_00_gt.txt", "", AlignMode::kSe3, RpeUnit::kFrames, 1, 0.0, Metric::kRpe, 4540,
     0.005444662908268874, 0.0048342911555850675, 0.004353258845759063, 0.002504792048795839,
     0.0008273280555301698, 0.01267956516842474},
    {"K3", "evo_rpe kitti KITTI_00_gt.txt KITTI_00_perturbed.txt -a --delta 100 --delta_unit m",
     "KITTI_00_gt.txt", "", AlignMode::kSe3, RpeUnit::kMetres, 100, 0.0, Metric::kRpe, 36, 0.496370475390706,
     0.42460763876944596, 0.36446520315210906, 0.25708364774569237, 0.0608415622846698, 1.1090957596220394},
    {"K4", "evo_ape kitti KITTI_00_gt.txt KITTI_00_perturbed.txt -as", "KITTI_00_gt.txt", "",
     AlignMode::kSim3, RpeUnit::kFrames, 1, 0.0, Metric::kApe, 4541, 1.3133277503201322, 1.1316309648100087,
     1.1915592407116924, 0.666514170325064, 0.05968940048707624, 2.4997249005520215},
};

// The KITTI estimate: pose i of KITTI_00_gt.txt turned by yaw_i = 0.01 sin(i/40) about z (R' = Rz R) and
// moved by [0.2 sin(i/50) + 0.001 i, 0.1 cos(i/70), 0.05 sin(i/30)], written with "%.9e" as evo's case file
// was.
std::string PerturbedKitti(const std::string& gt_path, const testing::TempDir& dir) {
  auto gt = ReadKittiTrajectory(gt_path);
  EXPECT_TRUE(gt) << gt.error();
  const std::string path = dir.File("KITTI_00_perturbed.txt");
  FILE* out = std::fopen(path.c_str(), "w");
  for (std::size_t i = 0; i < gt->size(); ++i) {
    const double k = static_cast<double>(i), yaw = 0.01 * std::sin(k / 40.0);
    Eigen::Matrix3d Rz;
    Rz << std::cos(yaw), -std::sin(yaw), 0, std::sin(yaw), std::cos(yaw), 0, 0, 0, 1;
    const Eigen::Matrix3d R = Rz * gt->poses[i].rotation();
    const Eigen::Vector3d t =
        gt->poses[i].translation() + Eigen::Vector3d(0.2 * std::sin(k / 50.0) + 0.001 * k,
                                                     0.1 * std::cos(k / 70.0), 0.05 * std::sin(k / 30.0));
    for (int r = 0; r < 3; ++r)
      std::fprintf(out, "%.9e %.9e %.9e %.9e%s", R(r, 0), R(r, 1), R(r, 2), t[r], r < 2 ? " " : "\n");
  }
  std::fclose(out);
  return path;
}

void ExpectRelative(double actual, double expected, const char* what, const char* name) {
  EXPECT_LE(std::abs(actual - expected), 1e-6 * std::abs(expected))
      << name << " " << what << ": " << actual << " vs evo " << expected;
}

// --- the plain second implementation ---------------------------------------------------------------

std::vector<std::pair<std::size_t, std::size_t>> PlainAssociate(const Trajectory& ref, const Trajectory& est,
                                                                double max_dt, double offset) {
  std::vector<std::pair<std::size_t, std::size_t>> pairs;  // (ref, est)
  if (!ref.has_stamps()) {
    for (std::size_t i = 0; i < ref.size(); ++i) pairs.emplace_back(i, i);
    return pairs;
  }
  const bool est_longer = est.size() > ref.size();
  const std::size_t n_short = est_longer ? ref.size() : est.size(),
                    n_long = est_longer ? est.size() : ref.size();
  auto seconds = [&](bool is_est, std::size_t i) {
    return ToSeconds(is_est ? est.stamps[i] : ref.stamps[i]) + (is_est ? offset : 0.0);
  };
  for (std::size_t i = 0; i < n_short; ++i) {
    std::size_t best = 0;
    for (std::size_t j = 1; j < n_long; ++j)
      if (std::abs(seconds(est_longer, j) - seconds(!est_longer, i)) <
          std::abs(seconds(est_longer, best) - seconds(!est_longer, i)))
        best = j;
    if (std::abs(seconds(est_longer, best) - seconds(!est_longer, i)) <= max_dt)
      pairs.emplace_back(est_longer ? i : best, est_longer ? best : i);
  }
  return pairs;
}

std::vector<double> PlainErrors(const EvoCase& c, const Trajectory& ref, const Trajectory& est) {
  const auto pairs = PlainAssociate(ref, est, 0.01, c.t_offset);
  Eigen::Matrix3Xd src(3, pairs.size()), dst(3, pairs.size());
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    src.col(k) = est.poses[pairs[k].second].translation();
    dst.col(k) = ref.poses[pairs[k].first].translation();
  }
  Eigen::Matrix4d align = Eigen::Matrix4d::Identity();
  if (c.align != AlignMode::kNone) align = Eigen::umeyama(src, dst, c.align == AlignMode::kSim3);
  std::vector<Eigen::Matrix4d> Q, P;
  for (const auto& [i, j] : pairs) {
    Q.push_back(ref.poses[i].matrix());
    P.push_back(align * est.poses[j].matrix());  // scale and rotation both in the top-left block
    P.back().topLeftCorner<3, 3>() /= std::cbrt(align.topLeftCorner<3, 3>().determinant());
  }
  std::vector<double> errors;
  if (c.metric == Metric::kApe) {
    for (std::size_t k = 0; k < P.size(); ++k) errors.push_back((Q[k].col(3) - P[k].col(3)).norm());
    return errors;
  }
  std::vector<std::size_t> ids;
  if (c.rpe_unit == RpeUnit::kFrames) {
    for (std::size_t i = 0; i < P.size(); i += static_cast<std::size_t>(c.rpe_delta)) ids.push_back(i);
  } else {
    double path = 0;
    for (std::size_t i = 1; i < P.size(); ++i)
      if ((path += (P[i].col(3) - P[i - 1].col(3)).norm()) >= c.rpe_delta) ids.push_back(i), path = 0;
  }
  auto inverse = [](const Eigen::Matrix4d& T) {  // R^T, as evo inverts
    Eigen::Matrix4d inv = Eigen::Matrix4d::Identity();
    inv.topLeftCorner<3, 3>() = T.topLeftCorner<3, 3>().transpose();
    inv.topRightCorner<3, 1>() = -inv.topLeftCorner<3, 3>() * T.topRightCorner<3, 1>();
    return inv;
  };
  for (std::size_t k = 1; k < ids.size(); ++k) {
    const std::size_t i = ids[k - 1], j = ids[k];
    const Eigen::Matrix4d E = inverse(inverse(Q[i]) * Q[j]) * (inverse(P[i]) * P[j]);
    errors.push_back(E.topRightCorner<3, 1>().norm());
  }
  return errors;
}

// --------------------------------------------------------------------------------------------------------

void PrintTo(const EvoCase& c, std::ostream* out) { *out << c.evo_command; }

class EvoAgreement : public ::testing::TestWithParam<EvoCase> {};

TEST_P(EvoAgreement, EveryStatisticWithin1e6Relative) {
  const std::string data = testing::SharedData();
  if (data.empty())
    GTEST_SKIP() << "../shared/data is absent: the evo agreement tests need the recorded trajectories";
  const EvoCase& c = GetParam();
  testing::TempDir dir;
  const std::string folder = data + "/trajectories/";
  const std::string estimate_path =
      std::string(c.estimate).empty() ? PerturbedKitti(folder + c.reference, dir) : folder + c.estimate;
  // fr2_desk_groundtruth.txt repeats the stamp 1311868229.5760 (lines 10862-10863); evo's nearest-stamp
  // association always takes the first of the two, which is what skipping the repeat does.
  const TrajectoryReadOptions keep_first{.skip_duplicate_stamps = true};
  auto reference = ReadTrajectory(folder + c.reference, TrajectoryFormat::kAuto, keep_first);
  auto estimate = ReadTrajectory(estimate_path, TrajectoryFormat::kAuto, keep_first);
  ASSERT_TRUE(reference) << reference.error();
  ASSERT_TRUE(estimate) << estimate.error();

  EvalOptions options;
  options.align = c.align;
  options.rpe_unit = c.rpe_unit;
  options.rpe_delta = c.rpe_delta;
  options.estimate_offset = FromSeconds(c.t_offset);
  auto result = Evaluate(*reference, *estimate, options);
  ASSERT_TRUE(result) << result.error();
  ASSERT_TRUE(c.metric == Metric::kApe || result->rpe);
  const ErrorStats& s = c.metric == Metric::kApe ? result->ape : *result->rpe;

  EXPECT_EQ(s.n, c.n) << c.evo_command;
  ExpectRelative(s.rmse, c.rmse, "rmse", c.name);
  ExpectRelative(s.mean, c.mean, "mean", c.name);
  ExpectRelative(s.median, c.median, "median", c.name);
  ExpectRelative(s.std, c.std, "std", c.name);
  ExpectRelative(s.min, c.min, "min", c.name);
  ExpectRelative(s.max, c.max, "max", c.name);

  const std::vector<double> plain = PlainErrors(c, *reference, *estimate);
  const std::vector<double>& ours = c.metric == Metric::kApe ? result->ape_errors : result->rpe_errors;
  ASSERT_EQ(plain.size(), ours.size());
  for (std::size_t k = 0; k < plain.size(); ++k) EXPECT_NEAR(ours[k], plain[k], 1e-9 + 1e-9 * plain[k]) << k;
}

INSTANTIATE_TEST_SUITE_P(TrajectoriesOfTheEvoTestSet, EvoAgreement, ::testing::ValuesIn(kEvoCases),
                         [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace uf
