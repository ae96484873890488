#include "lap/solver/staircase_lu.h"

#include <algorithm>
#include <cmath>

namespace ttz::lap {

Eigen::Map<Eigen::MatrixXd> StaircaseLU::Block(int k) {
  const Step& st = steps_[k];
  return {values_.data() + st.offset, st.rows, st.width + st.next_width};
}

Eigen::Map<const Eigen::MatrixXd> StaircaseLU::Block(int k) const {
  const Step& st = steps_[k];
  return {values_.data() + st.offset, st.rows, st.width + st.next_width};
}

// The steps of J's size; false when it has none.
bool StaircaseLU::Layout(const Eigen::SparseMatrix<double>& J) {
  if (R_ <= 0 || g_ < 0 || g_ > R_ || J.rows() != J.cols() || J.rows() % R_ != 0) return false;
  const int N = static_cast<int>(J.rows() / R_);
  auto width = [&](int k) { return k == 0 ? g_ : k == N ? R_ - g_ : R_; };
  steps_.assign(N + 1, Step{});
  size_t offset = 0;
  for (int k = 0, carry = 0, column = 0; k <= N; ++k) {
    Step& st = steps_[k];
    st.carry = carry;
    st.rows = carry + (k < N ? R_ : 0);
    st.width = width(k);
    st.next_width = k < N ? width(k + 1) : 0;
    st.column = column;
    st.offset = offset;
    offset += static_cast<size_t>(st.rows) * (st.width + st.next_width);
    carry = st.rows - st.width;
    column += st.width;
  }
  values_.assign(offset, 0.0);
  pivots_.assign(J.cols(), 0);
  return N > 0;
}

// J's entries into the steps' blocks (block k's rows below the carry); false for an entry outside
// the staircase.
bool StaircaseLU::Scatter(const Eigen::SparseMatrix<double>& J) {
  const int N = static_cast<int>(steps_.size()) - 1;
  for (int k = 0; k <= N; ++k) {
    const Step& st = steps_[k];
    for (int j = 0; j < st.width; ++j) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(J, st.column + j); it; ++it) {
        const int b = static_cast<int>(it.row()) / R_, r = static_cast<int>(it.row()) % R_;
        if (b == k) {
          Block(k)(st.carry + r, j) = it.value();
        } else if (b == k - 1) {
          Block(k - 1)(steps_[k - 1].carry + r, steps_[k - 1].width + j) = it.value();
        } else if (it.value() != 0.0) {
          return false;
        }
      }
    }
  }
  return true;
}

// Step k: the carry from step k - 1, then partial pivoting on group k's columns, each swap and
// update over the block's whole rows (so its right part becomes U's and the next carry).
bool StaircaseLU::Eliminate(int k) {
  const Step& st = steps_[k];
  Eigen::Map<Eigen::MatrixXd> A = Block(k);
  if (k > 0) {
    const Step& prev = steps_[k - 1];
    A.topLeftCorner(st.carry, st.width) =
        Block(k - 1).block(prev.width, prev.width, st.carry, st.width);
  }
  const int cols = st.width + st.next_width;
  for (int j = 0; j < st.width; ++j) {
    Eigen::Index p;
    const double magnitude = A.col(j).tail(st.rows - j).cwiseAbs().maxCoeff(&p);
    if (!(magnitude > 0.0) || !std::isfinite(magnitude)) return false;
    p += j;
    pivots_[st.column + j] = static_cast<int>(p);
    if (p != j) A.row(j).swap(A.row(p));
    const int below = st.rows - j - 1, right = cols - j - 1;
    A.col(j).tail(below) /= A(j, j);
    A.bottomRightCorner(below, right).noalias() -= A.col(j).tail(below) * A.row(j).tail(right);
  }
  return true;
}

bool StaircaseLU::Compute(const Eigen::SparseMatrix<double>& J) {
  if (!Layout(J) || !Scatter(J)) return false;
  for (int k = 0; k < static_cast<int>(steps_.size()); ++k)
    if (!Eliminate(k)) return false;
  return true;
}

Eigen::VectorXd StaircaseLU::Solve(const Eigen::VectorXd& b) const {
  const int N = static_cast<int>(steps_.size()) - 1;
  Eigen::VectorXd x(b.size()), v(2 * R_), carry;
  for (int k = 0; k <= N; ++k) {  // L y = P b, step by step; y of group k into x's group k
    const Step& st = steps_[k];
    const auto A = Block(k);
    v.head(st.carry) = carry;
    v.segment(st.carry, st.rows - st.carry) =
        b.segment(static_cast<Eigen::Index>(k) * R_, st.rows - st.carry);
    for (int j = 0; j < st.width; ++j) std::swap(v[j], v[pivots_[st.column + j]]);
    auto y = v.head(st.width);
    A.topLeftCorner(st.width, st.width).triangularView<Eigen::UnitLower>().solveInPlace(y);
    carry = v.segment(st.width, st.rows - st.width) -
            A.bottomLeftCorner(st.rows - st.width, st.width) * y;
    x.segment(st.column, st.width) = y;
  }
  for (int k = N; k >= 0; --k) {  // U x = y, backwards
    const Step& st = steps_[k];
    const auto A = Block(k);
    auto xk = x.segment(st.column, st.width);
    if (st.next_width > 0)
      xk -= A.block(0, st.width, st.width, st.next_width) *
            x.segment(st.column + st.width, st.next_width);
    A.topLeftCorner(st.width, st.width).triangularView<Eigen::Upper>().solveInPlace(xk);
  }
  return x;
}

}  // namespace ttz::lap
