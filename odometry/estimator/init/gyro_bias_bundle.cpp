#include "odometry/estimator/init/gyro_bias_bundle.h"

#include <Eigen/Dense>
#include <cmath>

#include "odometry/estimator/init/imu_chain.h"

namespace uf::estimator {
namespace {

constexpr int kMaxIterations = 10;
// Huber's threshold in normalized image units: 2 px at a focal length of 400 px (KLT tracks are good to
// 0.2-1 px; the front end's RANSAC has removed the gross outliers).
constexpr double kHuber = 0.005;
constexpr double kInitialDamping = 1e-4;  // Levenberg-Marquardt: H + mu diag(H)

struct Estimate {
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> c, P;
};

// The normal equations over x = [b_g, c_1 .. c_last] after the points' elimination, and per point what its
// back-substitution needs.
struct Normal {
  Eigen::MatrixXd H;
  Eigen::VectorXd g;
  std::vector<Eigen::Matrix3d> Hpp;
  std::vector<Eigen::Vector3d> gp;
  std::vector<Eigen::MatrixXd> Hpx;
};

double Huber(double r) { return r <= kHuber ? r * r : 2 * kHuber * r - kHuber * kHuber; }

class Problem {
 public:
  Problem(std::span<const ImuPreintegration> preintegrations, std::span<const TrackObservations> tracks,
          const SE3& T_body_camera)
      : preintegrations_(preintegrations), tracks_(tracks), R_bc_(T_body_camera.so3().matrix()) {}

  long unknowns(const Estimate& e) const { return 3 * static_cast<long>(e.c.size()); }  // b_g and c_1..

  // The cost at e and, with `normal`, its Gauss-Newton normal equations (Huber's weights at e).
  double Evaluate(const Estimate& e, Normal* normal, int* observations) const {
    const ImuChain chain = ChainPreintegrations(preintegrations_, e.b);
    const long nx = unknowns(e);
    if (normal) *normal = {Eigen::MatrixXd::Zero(nx, nx), Eigen::VectorXd::Zero(nx), {}, {}, {}};
    double cost = 0;
    int count = 0;
    for (std::size_t f = 0; f < tracks_.size(); ++f) {
      Eigen::Matrix3d Hpp = Eigen::Matrix3d::Zero();
      Eigen::Vector3d gp = Eigen::Vector3d::Zero();
      Eigen::MatrixXd Hpx = Eigen::MatrixXd::Zero(3, nx);
      for (const auto& [k, xy] : tracks_[f]) {
        const Eigen::Matrix3d M = chain.R[k].matrix() * R_bc_;  // the camera's orientation in "lo"
        const Eigen::Vector3d w = e.P[f] - e.c[k];
        const Eigen::Vector3d q = M.transpose() * w;
        ++count;
        if (!(q.z() > 1e-6 * w.norm())) {  // behind the camera: the largest cost a residual of 1 has
          cost += Huber(1);
          continue;
        }
        const Eigen::Vector2d residual = q.head<2>() / q.z() - xy;
        const double r = residual.norm();
        cost += Huber(r);
        if (!normal) continue;
        const double weight = r <= kHuber ? 1 : kHuber / r;
        Eigen::Matrix<double, 2, 3> projection;
        projection << 1 / q.z(), 0, -q.x() / (q.z() * q.z()), 0, 1 / q.z(), -q.y() / (q.z() * q.z());
        // dq/dP = M^T, dq/dc_k = -M^T; R_k(b + d)^T w ~= R_k^T w + Hat(R_k^T w) dR_dbg_k d.
        const Eigen::Matrix<double, 2, 3> J_point = projection * M.transpose();
        Eigen::MatrixXd J_x = Eigen::MatrixXd::Zero(2, nx);
        J_x.leftCols<3>() = projection * R_bc_.transpose() * Hat(chain.R[k].inverse() * w) * chain.dR_dbg[k];
        if (k > 0) J_x.middleCols<3>(3 * static_cast<long>(k)) = -J_point;
        normal->H += weight * J_x.transpose() * J_x;
        normal->g += weight * J_x.transpose() * residual;
        Hpp += weight * J_point.transpose() * J_point;
        gp += weight * J_point.transpose() * residual;
        Hpx += weight * J_point.transpose() * J_x;
      }
      if (!normal) continue;
      normal->Hpp.push_back(Hpp);
      normal->gp.push_back(gp);
      normal->Hpx.push_back(std::move(Hpx));
    }
    if (observations) *observations = count;
    return cost;
  }

  // The damped step from `normal`, the points eliminated; |c_last| is held (the scale's gauge).
  Estimate Step(const Estimate& e, const Normal& normal, double mu) const {
    Eigen::MatrixXd S = normal.H;
    S.diagonal() *= 1 + mu;
    Eigen::VectorXd rhs = -normal.g;
    std::vector<Eigen::Matrix3d> Hpp_inverse(normal.Hpp.size());
    for (std::size_t f = 0; f < normal.Hpp.size(); ++f) {
      Eigen::Matrix3d Hpp = normal.Hpp[f];
      Hpp.diagonal() *= 1 + mu;
      Hpp.diagonal().array() += 1e-12;
      Hpp_inverse[f] = Hpp.inverse();
      S -= normal.Hpx[f].transpose() * Hpp_inverse[f] * normal.Hpx[f];
      rhs += normal.Hpx[f].transpose() * Hpp_inverse[f] * normal.gp[f];
    }
    const Eigen::Vector3d u = e.c.back().normalized();
    S.bottomRightCorner<3, 3>() += 1e6 * (S.diagonal().maxCoeff() + 1) * u * u.transpose();
    const Eigen::VectorXd dx = S.ldlt().solve(rhs);
    Estimate next = e;
    next.b += dx.head<3>();
    for (std::size_t k = 1; k < e.c.size(); ++k) next.c[k] += dx.segment<3>(3 * static_cast<long>(k));
    for (std::size_t f = 0; f < e.P.size(); ++f)
      next.P[f] += Hpp_inverse[f] * (-normal.gp[f] - normal.Hpx[f] * dx);
    const double norm = next.c.back().norm();
    for (Eigen::Vector3d& c : next.c) c /= norm;
    for (Eigen::Vector3d& P : next.P) P /= norm;
    return next;
  }

 private:
  std::span<const ImuPreintegration> preintegrations_;
  std::span<const TrackObservations> tracks_;
  Eigen::Matrix3d R_bc_;
};

bool Finite(const Estimate& e) {
  bool finite = e.b.allFinite();
  for (const Eigen::Vector3d& c : e.c) finite = finite && c.allFinite();
  for (const Eigen::Vector3d& P : e.P) finite = finite && P.allFinite();
  return finite;
}

}  // namespace

GyroBiasBundle AdjustWithGyroBias(std::span<const ImuPreintegration> preintegrations,
                                  std::span<const TrackObservations> tracks, const SE3& T_body_camera,
                                  std::vector<Eigen::Vector3d> centres, std::vector<Eigen::Vector3d> points) {
  const Problem problem(preintegrations, tracks, T_body_camera);
  Estimate e{Eigen::Vector3d::Zero(), std::move(centres), std::move(points)};
  Normal normal;
  int observations = 0;
  double cost = problem.Evaluate(e, &normal, &observations);
  double mu = kInitialDamping;
  for (int iteration = 0; iteration < kMaxIterations; ++iteration) {
    const Estimate next = problem.Step(e, normal, mu);
    const double next_cost = Finite(next) ? problem.Evaluate(next, nullptr, nullptr) : INFINITY;
    if (!(next_cost < cost)) {  // too long a step: damp more, or stop
      mu *= 10;
      if (mu > 1e4) break;
      continue;
    }
    const double decrease = (cost - next_cost) / cost;
    e = next;
    cost = problem.Evaluate(e, &normal, nullptr);
    mu = std::max(mu / 10, 1e-8);
    if (decrease < 1e-6) break;
  }
  return {e.b, std::move(e.c), std::move(e.P), std::sqrt(cost / std::max(observations, 1))};
}

}  // namespace uf::estimator
