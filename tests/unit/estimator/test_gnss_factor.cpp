// The GNSS position factor against independent truth: a hand-computed residual, analytic Jacobians against
// central numeric derivatives (poses through PoseManifold::Plus, the alignment block directly) for random
// poses, fractions and yaws, the ambient Jacobians Ceres sees, and a Ceres solve that recovers a known
// alignment. Also the shared interpolation's 3 x 12 Jacobian, the receiver-offset factors (the wrapped fix,
// the Gauss-Markov process against its own definition), and the configuration's checks.
#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <array>
#include <random>
#include <vector>

#include "odometry/estimator/config/gnss_factor_config.h"
#include "odometry/estimator/factors/gnss_factor.h"
#include "odometry/estimator/factors/gnss_offset_factor.h"
#include "odometry/estimator/factors/interpolated_point.h"
#include "odometry/estimator/state/nav_state.h"
#include "odometry/estimator/state/pose_manifold.h"

namespace uf::estimator {
namespace {

constexpr double kPi = 3.14159265358979323846;
using Matrix36 = Eigen::Matrix<double, 3, 6, Eigen::RowMajor>;
using Matrix3X = Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor>;
using Matrix37 = Eigen::Matrix<double, 3, 7, Eigen::RowMajor>;
using Matrix76 = Eigen::Matrix<double, 7, 6, Eigen::RowMajor>;

struct Random {
  std::mt19937_64 engine{29};
  std::normal_distribution<double> normal;
  Eigen::Vector3d Vector(double scale) {
    return Eigen::Vector3d(normal(engine), normal(engine), normal(engine)) * scale;
  }
  double Uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(engine); }
  // A random symmetric positive definite covariance with sigmas between 0.05 and 3 m.
  Eigen::Matrix3d Covariance() {
    const Eigen::Matrix3d V = SO3::Exp(Vector(2)).matrix();
    const Eigen::Vector3d sigma(Uniform(0.05, 3), Uniform(0.05, 3), Uniform(0.05, 3));
    return V * sigma.cwiseAbs2().asDiagonal() * V.transpose();
  }
};

Eigen::Vector3d Residual(const ceres::CostFunction& factor, const std::vector<const double*>& blocks) {
  Eigen::Vector3d r;
  factor.Evaluate(blocks.data(), r.data(), nullptr);
  return r;
}

// Numeric Jacobian (3 x tangent size) of block k by central differences: PoseManifold::Plus for the 7-wide
// pose blocks, plain addition for the others.
Eigen::MatrixXd NumericJacobian(const ceres::CostFunction& factor, std::vector<std::vector<double>> blocks,
                                int k) {
  const bool pose = blocks[k].size() == 7;
  const int size = pose ? 6 : static_cast<int>(blocks[k].size());
  const double h = 1e-6;
  Eigen::MatrixXd J(3, size);
  for (int i = 0; i < size; ++i) {
    Eigen::Vector3d r[2];
    for (int sign = 0; sign < 2; ++sign) {
      std::vector<std::vector<double>> moved = blocks;
      std::vector<double> delta(size, 0.0);
      delta[i] = sign == 0 ? h : -h;
      if (pose)
        PoseManifold().Plus(blocks[k].data(), delta.data(), moved[k].data());
      else
        moved[k][i] += delta[i];
      std::vector<const double*> pointers;
      for (const auto& block : moved) pointers.push_back(block.data());
      r[sign] = Residual(factor, pointers);
    }
    J.col(i) = (r[0] - r[1]) / (2 * h);
  }
  return J;
}

// The tangent Jacobians from EvaluateTangent, and the ambient ones from Evaluate times PlusJacobian.
struct AnalyticJacobians {
  std::vector<Eigen::MatrixXd> tangent, through_ambient;
};

AnalyticJacobians Analytic(const ceres::CostFunction& factor,
                           const std::vector<std::vector<double>>& blocks) {
  std::vector<const double*> pointers;
  for (const auto& block : blocks) pointers.push_back(block.data());
  const auto& tangent_cost = dynamic_cast<const TangentJacobianCost&>(factor);
  std::vector<std::vector<double>> tangent(blocks.size()), ambient(blocks.size());
  std::vector<double*> tangent_pointers, ambient_pointers;
  for (std::size_t k = 0; k < blocks.size(); ++k) {
    const int t = blocks[k].size() == 7 ? 6 : static_cast<int>(blocks[k].size());
    tangent[k].assign(3 * t, 0.0);
    ambient[k].assign(3 * blocks[k].size(), 0.0);
    tangent_pointers.push_back(tangent[k].data());
    ambient_pointers.push_back(ambient[k].data());
  }
  Eigen::Vector3d r_tangent, r_ambient;
  tangent_cost.EvaluateTangent(pointers.data(), r_tangent.data(), tangent_pointers.data());
  factor.Evaluate(pointers.data(), r_ambient.data(), ambient_pointers.data());
  EXPECT_EQ(r_tangent, r_ambient);
  AnalyticJacobians result;
  for (std::size_t k = 0; k < blocks.size(); ++k) {
    if (blocks[k].size() == 7) {
      result.tangent.push_back(Eigen::Map<const Matrix36>(tangent[k].data()));
      Matrix76 plus;
      PoseManifold().PlusJacobian(blocks[k].data(), plus.data());
      result.through_ambient.push_back(Eigen::Map<const Matrix37>(ambient[k].data()) * plus);
    } else {
      const auto size = static_cast<Eigen::Index>(blocks[k].size());
      result.tangent.push_back(Eigen::Map<const Matrix3X>(tangent[k].data(), 3, size));
      result.through_ambient.push_back(Eigen::Map<const Matrix3X>(ambient[k].data(), 3, size));
    }
  }
  return result;
}

std::vector<double> Block(const SE3& pose) {
  const auto block = PoseBlock(pose);
  return {block.begin(), block.end()};
}

std::vector<double> Block(const EnuAlignment& alignment) {
  const auto block = AlignmentBlock(alignment);
  return {block.begin(), block.end()};
}

double RelativeError(const Eigen::MatrixXd& analytic, const Eigen::MatrixXd& numeric) {
  return (analytic - numeric).norm() / std::max(numeric.norm(), 1e-12);
}

TEST(GnssFactor, ResidualIsTheWhitenedEnuError) {
  // Body at (10, 0, 1) with yaw 90 deg, antenna 1 m ahead (x) of the body: in the world (10, 1, 1). The
  // alignment turns the world by 90 deg and shifts it by (100, 200, 5): ENU (99, 210, 6). Fix at
  // (98, 212, 9) with sigmas (0.5, 2, 3): r = ((99 - 98) / 0.5, (210 - 212) / 2, (6 - 9) / 3) = (2, -1, -1).
  const SE3 body(SO3::Exp(Eigen::Vector3d(0, 0, kPi / 2)), Eigen::Vector3d(10, 0, 1));
  const EnuAlignment alignment{kPi / 2, Eigen::Vector3d(100, 200, 5)};
  const Eigen::Matrix3d covariance = Eigen::Vector3d(0.25, 4, 9).asDiagonal();
  const Eigen::Vector3d fix(98, 212, 9), lever(1, 0, 0);
  const auto pose = PoseBlock(body);
  const auto align = AlignmentBlock(alignment);
  const GnssFactorSinglePose single(fix, covariance, lever);
  EXPECT_LT((Residual(single, {pose.data(), align.data()}) - Eigen::Vector3d(2, -1, -1)).norm(), 1e-12);
  // The two-pose factor between this pose and one 2 m further north in the world (alpha 1/2 with equal
  // rotations: the antenna 1 m further north, ENU 1 m further west: x residual (98 - 98) / 0.5 = 0).
  const auto later = PoseBlock(SE3(body.so3(), Eigen::Vector3d(10, 2, 1)));
  const GnssFactor between(fix, covariance, lever, 0.5);
  EXPECT_LT(
      (Residual(between, {pose.data(), later.data(), align.data()}) - Eigen::Vector3d(0, -1, -1)).norm(),
      1e-12);
  // The sqrt-information whitens: L Sigma L^T = I.
  Random random;
  const Eigen::Matrix3d S = random.Covariance(), L = GnssSqrtInformation(S);
  EXPECT_LT((L * S * L.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-9);
}

TEST(GnssFactor, HorizontalOnlyCarriesTheHorizontalMarginalAndNoHeight) {
  // The same fix as above used horizontally: the residual keeps (2, -1) and loses the height (0).
  const SE3 body(SO3::Exp(Eigen::Vector3d(0, 0, kPi / 2)), Eigen::Vector3d(10, 0, 1));
  const auto pose = PoseBlock(body);
  const auto align = AlignmentBlock(EnuAlignment{kPi / 2, Eigen::Vector3d(100, 200, 5)});
  const GnssFactorSinglePose single(Eigen::Vector3d(98, 212, 9), Eigen::Vector3d(0.25, 4, 9).asDiagonal(),
                                    Eigen::Vector3d(1, 0, 0), GnssAxes::kHorizontal);
  EXPECT_LT((Residual(single, {pose.data(), align.data()}) - Eigen::Vector3d(2, -1, 0)).norm(), 1e-12);
  // With a full covariance, the first two rows whiten the horizontal marginal: Lh Sigma_h Lh^T = I, and the
  // vertical does not enter (third row zero).
  Random random;
  const Eigen::Matrix3d S = random.Covariance(), L = GnssSqrtInformation(S, GnssAxes::kHorizontal);
  const Eigen::Matrix2d Lh = L.topLeftCorner<2, 2>();
  EXPECT_LT((Lh * S.topLeftCorner<2, 2>() * Lh.transpose() - Eigen::Matrix2d::Identity()).norm(), 1e-9);
  EXPECT_EQ(L.row(2).norm(), 0.0);
  EXPECT_EQ(L.col(2).norm(), 0.0);
}

TEST(GnssFactor, JacobiansMatchNumericDerivatives) {
  Random random;
  for (int trial = 0; trial < 30; ++trial) {
    const SE3 T_a(SO3::Exp(random.Vector(1.5)), random.Vector(50));
    // Every fifth trial the rotations are equal (Log(R_a^T R_b) = 0).
    const SO3 R_b = trial % 5 == 0 ? T_a.so3() : T_a.so3() * SO3::Exp(random.Vector(0.4));
    const SE3 T_b(R_b, T_a.translation() + random.Vector(2));
    const EnuAlignment alignment{random.Uniform(-kPi, kPi), random.Vector(100)};
    const Eigen::Vector3d lever = random.Vector(1),
                          fix = alignment.Apply(T_a.translation()) + random.Vector(3);
    const Eigen::Matrix3d covariance = random.Covariance();
    const std::vector<std::vector<double>> blocks = {Block(T_a), Block(T_b), Block(alignment)};
    for (double alpha : {random.Uniform(0.01, 0.99), random.Uniform(0.01, 0.99), 0.0, 1.0}) {
      const GnssFactor factor(fix, covariance, lever, alpha);
      const AnalyticJacobians analytic = Analytic(factor, blocks);
      for (int k = 0; k < 3; ++k) {
        const Eigen::MatrixXd numeric = NumericJacobian(factor, blocks, k);
        EXPECT_LT(RelativeError(analytic.through_ambient[k], analytic.tangent[k]), 1e-12) << "block " << k;
        if ((k == 0 && alpha == 1) || (k == 1 && alpha == 0)) {  // the block has no say at this time
          EXPECT_LT(analytic.tangent[k].norm(), 1e-12);
          EXPECT_LT(numeric.norm(), 1e-6);
          continue;
        }
        EXPECT_LT(RelativeError(analytic.tangent[k], numeric), 1e-6)
            << "trial " << trial << " alpha " << alpha << " block " << k << "\nanalytic\n"
            << analytic.tangent[k] << "\nnumeric\n"
            << numeric;
      }
    }
    const GnssFactorSinglePose single(fix, covariance, lever);
    const std::vector<std::vector<double>> single_blocks = {Block(T_a), Block(alignment)};
    const AnalyticJacobians analytic = Analytic(single, single_blocks);
    for (int k = 0; k < 2; ++k) {
      EXPECT_LT(RelativeError(analytic.tangent[k], NumericJacobian(single, single_blocks, k)), 1e-6) << k;
      EXPECT_LT(RelativeError(analytic.through_ambient[k], analytic.tangent[k]), 1e-12) << k;
    }
    // The single-pose factor is the two-pose factor at alpha = 0.
    const GnssFactor at_a(fix, covariance, lever, 0.0);
    EXPECT_LT((Residual(single, {blocks[0].data(), blocks[2].data()}) -
               Residual(at_a, {blocks[0].data(), blocks[1].data(), blocks[2].data()}))
                  .norm(),
              1e-9);
  }
}

TEST(GnssFactor, CeresRecoversAKnownAlignment) {
  // Poses held fixed along an L-shaped path; fixes of the antenna through a known alignment with 2 cm noise.
  Random random;
  const EnuAlignment truth{0.7, Eigen::Vector3d(-350, 1200, 48)};
  const Eigen::Vector3d lever(0.3, -0.1, 1.2);
  const Eigen::Matrix3d covariance = Eigen::Vector3d(4e-4, 4e-4, 1.6e-3).asDiagonal();
  std::vector<std::array<double, 7>> poses;
  for (int i = 0; i < 30; ++i) {
    const Eigen::Vector3d p = i < 15 ? Eigen::Vector3d(i, 0, 0) : Eigen::Vector3d(14, i - 14, 0.1 * (i - 14));
    poses.push_back(PoseBlock(SE3(SO3::Exp(Eigen::Vector3d(0, 0, 0.1 * i)), p)));
  }
  auto alignment = AlignmentBlock(EnuAlignment{0.2, Eigen::Vector3d(-340, 1190, 40)});
  ceres::Problem problem;
  for (std::size_t i = 0; i + 1 < poses.size(); ++i) {
    const double alpha = 0.3;
    const SE3 at = Interpolate(PoseFromBlock(poses[i].data()), PoseFromBlock(poses[i + 1].data()), alpha);
    const Eigen::Vector3d fix =
        truth.Apply(at * lever) + Eigen::Vector3d(random.normal(random.engine) * 0.02,
                                                  random.normal(random.engine) * 0.02,
                                                  random.normal(random.engine) * 0.04);
    problem.AddResidualBlock(new GnssFactor(fix, covariance, lever, alpha), nullptr, poses[i].data(),
                             poses[i + 1].data(), alignment.data());
  }
  for (auto& pose : poses) {
    problem.SetManifold(pose.data(), new PoseManifold);
    problem.SetParameterBlockConstant(pose.data());
  }
  ceres::Solver::Options options;
  options.max_num_iterations = 50;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.BriefReport();
  const EnuAlignment solved = AlignmentFromBlock(alignment.data());
  EXPECT_NEAR(solved.yaw_rad, truth.yaw_rad, 2e-3);
  EXPECT_LT((solved.translation - truth.translation).norm(), 0.05);
}

TEST(GnssOffsetFactor, AddsTheWhitenedOffsetAndItsJacobiansMatchNumericDerivatives) {
  Random random;
  for (int trial = 0; trial < 10; ++trial) {
    const SE3 T_a(SO3::Exp(random.Vector(1.5)), random.Vector(50));
    const SE3 T_b(T_a.so3() * SO3::Exp(random.Vector(0.4)), T_a.translation() + random.Vector(2));
    const EnuAlignment alignment{random.Uniform(-kPi, kPi), random.Vector(100)};
    const Eigen::Vector3d lever = random.Vector(1), offset = random.Vector(2),
                          fix = alignment.Apply(T_a.translation()) + random.Vector(3);
    const Eigen::Matrix3d white = random.Covariance();
    const double alpha = random.Uniform(0.01, 0.99);
    for (GnssAxes axes : {GnssAxes::kAll, GnssAxes::kHorizontal}) {
      const GnssOffsetFactor factor(std::make_unique<GnssFactor>(fix, white, lever, alpha, axes), white,
                                    axes);
      const std::vector<std::vector<double>> blocks = {
          Block(T_a), Block(T_b), Block(alignment), {offset.x(), offset.y(), offset.z()}};
      ASSERT_EQ(factor.parameter_block_sizes(), (std::vector<int32_t>{7, 7, 4, 3}));
      // By hand: L_w (Rz p_w + t + b - f), p_w the antenna at the interpolated pose.
      const Eigen::Vector3d p_w = Interpolate(T_a, T_b, alpha) * lever;
      const Eigen::Vector3d expected =
          GnssSqrtInformation(white, axes) * (alignment.Apply(p_w) + offset - fix);
      EXPECT_LT((Residual(factor, {blocks[0].data(), blocks[1].data(), blocks[2].data(), blocks[3].data()}) -
                 expected)
                    .norm(),
                1e-9 * std::max(1.0, expected.norm()));
      const AnalyticJacobians analytic = Analytic(factor, blocks);
      for (int k = 0; k < 4; ++k) {
        EXPECT_LT(RelativeError(analytic.tangent[k], NumericJacobian(factor, blocks, k)), 1e-6)
            << "trial " << trial << " block " << k;
        EXPECT_LT(RelativeError(analytic.through_ambient[k], analytic.tangent[k]), 1e-12) << k;
      }
    }
    const GnssOffsetFactor single(std::make_unique<GnssFactorSinglePose>(fix, white, lever), white,
                                  GnssAxes::kAll);
    const std::vector<std::vector<double>> single_blocks = {
        Block(T_a), Block(alignment), {offset.x(), offset.y(), offset.z()}};
    const AnalyticJacobians analytic = Analytic(single, single_blocks);
    for (int k = 0; k < 3; ++k)
      EXPECT_LT(RelativeError(analytic.tangent[k], NumericJacobian(single, single_blocks, k)), 1e-6) << k;
  }
}

// Against the process's own definition: a first-order Gauss-Markov sequence drawn with the correlation
// time and sigmas the factors are given whitens to unit-variance, uncorrelated residuals; the stationary
// prior whitens the draws themselves.
TEST(GnssOffsetProcess, WhitensAGaussMarkovSequence) {
  std::mt19937_64 engine(7);
  std::normal_distribution<double> normal;
  const double tau = 30.0;
  const Eigen::Vector3d sigma(1.5, 1.5, 3.0);
  Eigen::Vector3d b(normal(engine) * sigma.x(), normal(engine) * sigma.y(), normal(engine) * sigma.z());
  Eigen::Vector3d sum_sq = Eigen::Vector3d::Zero(), prior_sum_sq = Eigen::Vector3d::Zero();
  double lag_product = 0;
  Eigen::Vector3d last_r = Eigen::Vector3d::Zero();
  const int steps = 20000;
  for (int k = 0; k < steps; ++k) {
    const double dt = 0.05 + 0.95 * (k % 7) / 6.0;  // uneven node spacing, 0.05 to 1 s
    const double a = std::exp(-dt / tau);
    Eigen::Vector3d next;
    for (int i = 0; i < 3; ++i) next[i] = a * b[i] + std::sqrt(1 - a * a) * sigma[i] * normal(engine);
    const auto process = MakeGnssOffsetProcessFactor(dt, tau, sigma);
    const double* blocks[2] = {b.data(), next.data()};
    Eigen::Vector3d r;
    ASSERT_TRUE(process->Evaluate(blocks, r.data(), nullptr));
    sum_sq += r.cwiseAbs2();
    lag_product += r.dot(last_r);
    last_r = r;
    const auto prior = MakeGnssOffsetPrior(sigma);
    const double* prior_block[1] = {next.data()};
    ASSERT_TRUE(prior->Evaluate(prior_block, r.data(), nullptr));
    prior_sum_sq += r.cwiseAbs2();
    b = next;
  }
  // A mean of n squared unit normals has a standard error of sqrt(2 / n) = 0.01; the prior sees correlated
  // draws (about 2 tau / mean dt = 114 per independent one), so its mean has one of about 0.1.
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(sum_sq[i] / steps, 1.0, 0.05) << i;
    EXPECT_NEAR(prior_sum_sq[i] / steps, 1.0, 0.3) << i;
  }
  EXPECT_NEAR(lag_product / (3.0 * steps), 0.0, 0.02);  // uncorrelated in time (standard error 0.004)
}

TEST(GnssInterpolatedPoint, JacobianMatchesNumericDerivatives) {
  Random random;
  for (int trial = 0; trial < 10; ++trial) {
    const auto b = PoseBlock(SE3(SO3::Exp(random.Vector(1)), random.Vector(5)));
    const auto e = PoseBlock(SE3(SO3::Exp(random.Vector(1)), random.Vector(5)));
    const Eigen::Vector3d p = random.Vector(3);
    const double alpha = random.Uniform(0, 1);
    PoseInterpolationTerms terms;
    ComputePoseInterpolationTerms(b.data(), e.data(), terms);
    const Eigen::Matrix<double, 3, 12> J = InterpolatedPoint(terms, b.data(), e.data(), alpha, p).Jacobian();
    const double h = 1e-6;
    for (int i = 0; i < 12; ++i) {
      Eigen::Vector3d moved[2];
      for (int sign = 0; sign < 2; ++sign) {
        std::array<double, 7> b2 = b, e2 = e;
        double delta[6] = {0, 0, 0, 0, 0, 0};
        delta[i % 6] = sign == 0 ? h : -h;
        if (i < 6)
          PoseManifold().Plus(b.data(), delta, b2.data());
        else
          PoseManifold().Plus(e.data(), delta, e2.data());
        PoseInterpolationTerms t2;
        ComputePoseInterpolationTerms(b2.data(), e2.data(), t2);
        moved[sign] = InterpolatedPoint(t2, b2.data(), e2.data(), alpha, p).world();
      }
      const Eigen::Vector3d numeric = (moved[0] - moved[1]) / (2 * h);
      EXPECT_LT((J.col(i) - numeric).norm(), 1e-6 * std::max(1.0, numeric.norm()))
          << trial << " column " << i;
    }
  }
}

TEST(GnssFactorConfig, DefaultsAreValidAndBadFieldsAreNamed) {
  EXPECT_TRUE(GnssFactorConfig().Validate().ok());
  EXPECT_DOUBLE_EQ(GnssFactorConfig().integrity_gate, 16.27);
  auto message = [](auto change) {
    GnssFactorConfig config;
    change(config);
    return config.Validate().message();
  };
  EXPECT_EQ(message([](GnssFactorConfig& c) { c.min_status = GnssFixStatus::kNoFix; }),
            "lio.gnss.min_status: must be fix, sbas, rtk_float or rtk_fixed, got no_fix");
  EXPECT_EQ(message([](GnssFactorConfig& c) { c.integrity_gate = -1; }),
            "lio.gnss.integrity_gate: must be > 0, got -1");
  EXPECT_EQ(message([](GnssFactorConfig& c) { c.rtk_fixed.min_sigma_m = 0; }),
            "lio.gnss.rtk_fixed.min_sigma_m: must be > 0, got 0");
  EXPECT_EQ(message([](GnssFactorConfig& c) { c.fix.sigma_scale = 0.5; }),
            "lio.gnss.fix.sigma_scale: must be finite and >= 1, got 0.5");
  EXPECT_EQ(message([](GnssFactorConfig& c) { c.prediction_sigma_m = -1; }),
            "lio.gnss.prediction_sigma_m: must be finite and >= 0, got -1");
  EXPECT_EQ(message([](GnssFactorConfig& c) { c.min_alignment_baseline_m = 0; }),
            "lio.gnss.min_alignment_baseline_m: must be > 0, got 0");
  EXPECT_EQ(message([](GnssFactorConfig& c) { c.min_alignment_fixes = 1; }),
            "lio.gnss.min_alignment_fixes: must be >= 2, got 1");
  EXPECT_EQ(message([](GnssFactorConfig& c) { c.max_snap_s = -0.1; }),
            "lio.gnss.max_snap_s: must be finite and >= 0, got -0.1");
}

}  // namespace
}  // namespace uf::estimator
