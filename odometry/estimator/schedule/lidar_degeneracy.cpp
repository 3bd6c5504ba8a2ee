#include "odometry/estimator/schedule/lidar_degeneracy.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace uf::estimator {
namespace {

// One 3x3 diagonal block of H (0: translation, 1: rotation): its eigen-decomposition (eigenvalues
// ascending) and its mean eigenvalue, trace / 3 (0 when not positive and finite: no information).
struct BlockSpectrum {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen;
  double mean = 0;
};
BlockSpectrum Spectrum(const Matrix6d& information, int block) {
  const Eigen::Matrix3d H = information.block<3, 3>(3 * block, 3 * block);
  const double mean = H.trace() / 3.0;
  if (!(mean > 0) || !std::isfinite(mean)) return {};
  return {Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(H), mean};
}

// lambda_min / mean eigenvalue, in [0, 1]; 0 without information.
double Isotropy(const BlockSpectrum& s) {
  return s.mean > 0 ? std::clamp(s.eigen.eigenvalues()(0) / s.mean, 0.0, 1.0) : 0.0;
}

// The block's projector off its eigenvectors below kHealthyIsotropy of its mean for which `drop` (given
// the eigenvector and its eigenvalue) holds too.
template <typename Drop>
Eigen::Matrix3d BlockProjector(const BlockSpectrum& s, Drop drop) {
  Eigen::Matrix3d P = Eigen::Matrix3d::Identity();
  if (!(s.mean > 0)) return P;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d v = s.eigen.eigenvectors().col(i);
    if (s.eigen.eigenvalues()(i) < kHealthyIsotropy * s.mean && drop(v, s.eigen.eigenvalues()(i)))
      P -= v * v.transpose();
  }
  return P;
}

}  // namespace

LidarDegeneracy AnalyzeLidarInformation(const Matrix6d& information, int matches) {
  LidarDegeneracy d;
  d.matches = matches;
  if (matches < 6 || !information.allFinite()) return d;
  const BlockSpectrum translation = Spectrum(information, 0);
  d.translation_isotropy = Isotropy(translation);
  if (translation.mean > 0) d.weak_translation = translation.eigen.eigenvectors().col(0);
  d.rotation_isotropy = Isotropy(Spectrum(information, 1));
  const double worst = std::min(d.translation_isotropy, d.rotation_isotropy);
  d.score = 1.0 - std::min(1.0, worst / kHealthyIsotropy);
  return d;
}

Matrix6d WeakDirectionProjector(const Matrix6d& information) {
  Matrix6d P = Matrix6d::Identity();
  if (!information.allFinite()) return P;
  const auto always = [](const Eigen::Vector3d&, double) { return true; };
  for (int block = 0; block < 2; ++block)
    P.block<3, 3>(3 * block, 3 * block) = BlockProjector(Spectrum(information, block), always);
  return P;
}

Matrix6d LooseTranslationProjector(const Matrix6d& information, const Eigen::Matrix3d& other_information) {
  Matrix6d P = Matrix6d::Identity();
  if (!information.allFinite() || !other_information.allFinite()) return P;
  P.block<3, 3>(0, 0) = BlockProjector(
      Spectrum(information, 0),
      [&](const Eigen::Vector3d& u, double lambda) { return lambda < u.dot(other_information * u); });
  return P;
}

}  // namespace uf::estimator
