// Linear least squares whose residuals each touch at most four consecutive blocks of unknowns, as spline
// fitting produces: every pose involves the four control points of its segment. The normal matrix is then
// block-banded (three blocks either side of the diagonal), accumulated in O(blocks) memory and solved with
// a sparse LDL^T in natural order, which for a band has no fill-in beyond the band.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "odometry/types/status.h"

namespace uf::spline {

class BandedLeastSquares {
 public:
  static constexpr int kMaxBlocksPerResidual = 4;

  // `blocks` unknown blocks of `block_size` rows each; the right-hand side has `rhs_columns` columns (one
  // per independent problem sharing the same Jacobian, e.g. the x, y and z of positions).
  BandedLeastSquares(int blocks, int block_size, int rhs_columns);

  // Adds weight * |J x - y|^2 where J's columns are the blocks first_block .. first_block + k - 1
  // (J has k * block_size columns, k <= 4) and y has rhs_columns columns.
  void Add(int first_block, const Eigen::MatrixXd& J, const Eigen::MatrixXd& y, double weight = 1.0);

  // The x minimising the sum, one column per right-hand-side column (blocks * block_size rows). Fails
  // when the normal matrix is singular, i.e. the residuals leave some unknowns free.
  Expected<Eigen::MatrixXd> Solve() const;

 private:
  Eigen::MatrixXd& Band(int block, int offset) { return band_[block * kMaxBlocksPerResidual + offset]; }

  int blocks_;
  int block_size_;
  std::vector<Eigen::MatrixXd> band_;  // J^T J block (i, i + offset), offset 0..3, row-block-major
  Eigen::MatrixXd rhs_;                // J^T y
};

}  // namespace uf::spline
