// The LU with partial pivoting of a square sparse matrix in staircase form, the form of the
// indirect solver's J (solution_curve.h): its rows come in blocks of R, its columns in groups
// 0..N (group 0 of g columns, groups 1..N-1 of R, group N of R - g), and row block k touches only
// the columns of groups k and k + 1 (interval k's residuals touch the unknowns of nodes k and
// k + 1; node 0 contributes its costates alone, node N its states).
//
// Gaussian elimination with partial pivoting in the columns' order is then a sequence of small
// dense steps: at group k the candidate rows are the R - g rows left over from block k - 1 (which
// by then touch group k alone) and the R rows of block k, and eliminating group k's columns leaves
// R - g rows that touch group k + 1 alone. A step eliminates group k's columns in a dense block of
// 2R - g rows and the two groups' columns: about 54,000 flops for J's R = 26, g = 13 (39 x 52),
// where a band LU with J's bandwidths (38 below and above) would do about 150,000 per 26 columns
// and a general sparse LU adds its symbolic work (docs/lap_log.md "The staircase LU"). The pivots are
// those of partial pivoting on the whole matrix in its own order, so the factors are as stable as
// that.
#pragma once

#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace ttz::lap {

// The form's sizes: R = block_rows > 0, g = first_width in [0, R].
struct Staircase {
  int block_rows = 0;
  int first_width = 0;
};

class StaircaseLU {
 public:
  explicit StaircaseLU(Staircase form) : R_(form.block_rows), g_(form.first_width) {}

  // Factorises J; false when J is not square, not in this staircase form, singular (an exact zero
  // pivot) or not finite.
  bool Compute(const Eigen::SparseMatrix<double>& J);
  // x with J x = b, by the last successful Compute.
  Eigen::VectorXd Solve(const Eigen::VectorXd& b) const;

 private:
  // Step k eliminates the columns of group k from its candidate rows: `carry` rows left from
  // block k - 1, then block k's R rows (none at k = N). Its dense block, rows x (width +
  // next_width) column-major from `offset`, holds L below its diagonal and U on and above it.
  struct Step {
    int carry = 0;
    int rows = 0;
    int width = 0;
    int next_width = 0;
    int column = 0;      // J's first column of group k
    size_t offset = 0;   // in values_
  };
  Eigen::Map<Eigen::MatrixXd> Block(int k);
  Eigen::Map<const Eigen::MatrixXd> Block(int k) const;
  bool Layout(const Eigen::SparseMatrix<double>& J);
  bool Scatter(const Eigen::SparseMatrix<double>& J);
  bool Eliminate(int k);

  int R_;
  int g_;
  std::vector<Step> steps_;
  std::vector<double> values_;
  std::vector<int> pivots_;  // per step, its `width` row swaps (row j with row pivots[j])
};

}  // namespace ttz::lap
