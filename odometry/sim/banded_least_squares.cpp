#include "odometry/sim/banded_least_squares.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <cassert>
#include <string>

namespace uf::spline {

BandedLeastSquares::BandedLeastSquares(int blocks, int block_size, int rhs_columns)
    : blocks_(blocks),
      block_size_(block_size),
      band_(static_cast<std::size_t>(blocks) * kMaxBlocksPerResidual,
            Eigen::MatrixXd::Zero(block_size, block_size)),
      rhs_(Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(blocks) * block_size, rhs_columns)) {}

void BandedLeastSquares::Add(int first_block, const Eigen::MatrixXd& J, const Eigen::MatrixXd& y,
                             double weight) {
  const int count = static_cast<int>(J.cols()) / block_size_;
  assert(count * block_size_ == J.cols() && count <= kMaxBlocksPerResidual);
  assert(first_block >= 0 && first_block + count <= blocks_ && y.rows() == J.rows() &&
         y.cols() == rhs_.cols());
  for (int a = 0; a < count; ++a) {
    const auto Ja = J.middleCols(a * block_size_, block_size_);
    rhs_.middleRows((first_block + a) * block_size_, block_size_) += weight * Ja.transpose() * y;
    for (int b = a; b < count; ++b) {
      Band(first_block + a, b - a) += weight * Ja.transpose() * J.middleCols(b * block_size_, block_size_);
    }
  }
}

Expected<Eigen::MatrixXd> BandedLeastSquares::Solve() const {
  // Lower triangle of the symmetric normal matrix: block (i + offset, i) is the transpose of band (i,
  // offset).
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(band_.size() * block_size_ * block_size_);
  for (int i = 0; i < blocks_; ++i) {
    for (int offset = 0; offset < kMaxBlocksPerResidual && i + offset < blocks_; ++offset) {
      const Eigen::MatrixXd& block = band_[i * kMaxBlocksPerResidual + offset];
      for (int r = 0; r < block_size_; ++r) {
        for (int c = 0; c < block_size_; ++c) {
          const int row = (i + offset) * block_size_ + c;
          const int col = i * block_size_ + r;
          if (row >= col) triplets.emplace_back(row, col, block(r, c));
        }
      }
    }
  }
  const Eigen::Index size = static_cast<Eigen::Index>(blocks_) * block_size_;
  Eigen::SparseMatrix<double> normal(size, size);
  normal.setFromTriplets(triplets.begin(), triplets.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::NaturalOrdering<int>> solver(
      normal);
  if (solver.info() != Eigen::Success) {
    return Status::Error("least-squares normal matrix is singular (" + std::to_string(size) + " unknowns)");
  }
  Eigen::MatrixXd solution = solver.solve(rhs_);
  if (solver.info() != Eigen::Success || !solution.allFinite()) {
    return Status::Error("least-squares solve failed (" + std::to_string(size) + " unknowns)");
  }
  return solution;
}

}  // namespace uf::spline
