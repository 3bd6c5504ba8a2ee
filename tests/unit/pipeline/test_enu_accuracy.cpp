// The accuracy stage's unaligned ENU figures (EvaluateInEnu): a ground truth in one ENU frame against an
// estimate in another, 1 km away, compared through WGS84 with hand-made offsets.
#include <gtest/gtest.h>

#include "odometry/types/geodetic.h"
#include "viewer/pipeline/stages/accuracy_stage.h"

namespace uf::pipeline {
namespace {

const GeodeticOrigin kTruthOrigin{49.0069, 8.4037, 115.0};

// A 100 m drive east in the truth's frame, a pose every 0.1 s.
Trajectory Drive() {
  Trajectory truth;
  for (int k = 0; k <= 100; ++k) {
    truth.stamps.push_back(1'700'000'000'000'000'000 + k * 100'000'000LL);
    truth.poses.emplace_back(SO3(), Eigen::Vector3d(1.0 * k, 0.5 * k, 0.01 * k));
  }
  return truth;
}

// The truth as the estimator would state it in the ENU frame at `run_origin`, offset by `error` (m, in the
// run's frame).
Trajectory InRunFrame(const Trajectory& truth, const GeodeticOrigin& run_origin,
                      const Eigen::Vector3d& error) {
  const auto truth_frame = EnuFrame::Create(kTruthOrigin);
  const auto run_frame = EnuFrame::Create(run_origin);
  Trajectory estimate = truth;
  for (SE3& pose : estimate.poses)
    pose =
        SE3(pose.so3(), run_frame->EnuFromGeodetic(truth_frame->GeodeticFromEnu(pose.translation())) + error);
  return estimate;
}

TEST(EnuAccuracy, ComparesThroughWgs84AndSplitsHorizontalAndVertical) {
  const Trajectory truth = Drive();
  // The estimator's origin: its first good fix, ~1 km north-east of the truth's origin and 20 m higher.
  const GeodeticOrigin run_origin{49.0150, 8.4150, 135.0};
  auto exact =
      EvaluateInEnu(truth, kTruthOrigin, InRunFrame(truth, run_origin, Eigen::Vector3d::Zero()), run_origin);
  ASSERT_TRUE(exact.ok()) << exact.error();
  EXPECT_EQ(exact->matched_poses, 101u);
  EXPECT_LT(exact->rmse_m, 1e-6);  // the frames differ by ~1 km: only the conversion's rounding is left

  auto offset = EvaluateInEnu(truth, kTruthOrigin,
                              InRunFrame(truth, run_origin, Eigen::Vector3d(0.3, -0.4, 1.2)), run_origin);
  ASSERT_TRUE(offset.ok()) << offset.error();
  EXPECT_NEAR(offset->horizontal_rmse_m, 0.5, 1e-6);
  EXPECT_NEAR(offset->vertical_rmse_m, 1.2, 1e-6);
  EXPECT_NEAR(offset->rmse_m, 1.3, 1e-6);
}

}  // namespace
}  // namespace uf::pipeline
