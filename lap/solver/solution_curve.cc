#include "lap/solver/solution_curve.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <sstream>

#include "lap/solver/parallel.h"
#include "lap/solver/sparse_lu.h"

namespace ttz::lap {

BarrierWeight WeightFor(double eps) { return {eps, std::min(1e-3, 0.1 * eps)}; }

CurveSystem::CurveSystem(Transcription* tr) : tr_(tr), n_((tr->NumNodes() - 1) * kW) {}

int CurveSystem::Index(int k, int i) { return (kW - kNumStates) + (k - 1) * kW + i; }

template <typename Visit>
void CurveSystem::ForEachUnknown(Visit visit) const {
  const int N = tr_->NumNodes() - 1;
  for (int k = 0; k <= N; ++k)
    for (int i = k == 0 ? kNumStates : 0; i < (k == N ? kNumStates : kW); ++i) visit(k, i);
}

Eigen::VectorXd CurveSystem::Get() const {
  Eigen::VectorXd v(n_);
  ForEachUnknown([&](int k, int i) { v[Index(k, i)] = tr_->W(k)[i]; });
  return v;
}

void CurveSystem::Set(const Eigen::VectorXd& v) {
  ForEachUnknown([&](int k, int i) { tr_->W(k)[i] = v[Index(k, i)]; });
}

std::string CurveSystem::DescribeStateDirection(const Eigen::VectorXd& d) const {
  const int N = tr_->NumNodes() - 1;
  auto part = [&](int k, int i) { return std::abs(d[Index(k, i)]); };
  int k_max = 1, i_max = 0;
  for (int k = 1; k < N; ++k)
    for (int i = 0; i < kNumStates; ++i)
      if (part(k, i) > part(k_max, i_max)) k_max = k, i_max = i;
  int first = k_max, last = k_max;
  for (int k = 1; k < N; ++k)
    for (int i = 0; i < kNumStates; ++i)
      if (part(k, i) >= 0.1 * part(k_max, i_max)) {
        first = std::min(first, k);
        last = std::max(last, k);
      }
  std::ostringstream o;
  o << "the solution moves most in " << kStateNames[i_max] << " at " << tr_->s[k_max]
    << " m, and by >= 10 % of that on " << tr_->s[first] << "-" << tr_->s[last] << " m";
  return o.str();
}

Eigen::SparseMatrix<double> CurveSystem::Pattern() const {
  const int N = tr_->NumNodes() - 1;
  std::vector<int> outer(n_ + 1, 0), inner;
  inner.reserve(static_cast<size_t>(n_) * 2 * kW);
  ForEachUnknown([&](int k, int i) {
    for (int interval : {k - 1, k})
      if (interval >= 0 && interval < N)
        for (int r = 0; r < kW; ++r) inner.push_back(interval * kW + r);
    outer[Index(k, i) + 1] = static_cast<int>(inner.size());
  });
  Eigen::SparseMatrix<double> J(N * kW, n_);
  J.resizeNonZeros(static_cast<Eigen::Index>(inner.size()));
  std::copy(outer.begin(), outer.end(), J.outerIndexPtr());
  std::copy(inner.begin(), inner.end(), J.innerIndexPtr());
  std::fill(J.valuePtr(), J.valuePtr() + inner.size(), 0.0);
  return J;
}

bool CurveSystem::Residuals(Eigen::VectorXd* F, Eigen::SparseMatrix<double>* J) {
  const int N = tr_->NumNodes() - 1;
  tr_->EvaluateMids(J != nullptr);
  if (!tr_->all_valid) return false;
  F->resize(static_cast<Eigen::Index>(N) * kW);
  if (J != nullptr && (J->cols() != n_ || J->nonZeros() != JacobianEntries())) *J = Pattern();
  return ForEachInterval(N, tr_->threads, [&](int k) {
    std::array<double, 2 * kW * kW> blocks;  // row-major, with respect to nodes k and k + 1
    double* jac[2] = {blocks.data(), blocks.data() + kW * kW};
    const double* p[2] = {tr_->W(k), tr_->W(k + 1)};
    if (!IntervalResidual(tr_, k).Evaluate(p, F->data() + k * kW, J != nullptr ? jac : nullptr))
      return false;
    if (J == nullptr) return true;
    for (int side = 0; side < 2; ++side) {
      const int m = k + side;
      for (int i = m == 0 ? kNumStates : 0; i < (m == N ? kNumStates : kW); ++i) {
        // interval k's rows: the column's second 24 at node k (when k > 0), its first at k + 1
        double* column = J->valuePtr() + J->outerIndexPtr()[Index(m, i)] +
                         (side == 0 && k > 0 ? kW : 0);
        for (int r = 0; r < kW; ++r) column[r] = jac[side][r * kW + i];
      }
    }
    return true;
  });
}

bool CurveSystem::Evaluate(double eps, Eigen::VectorXd* F, Eigen::SparseMatrix<double>* J,
                           Eigen::VectorXd* Fp) {
  tr_->weight = WeightFor(eps);
  if (!Residuals(F, J) || !F->allFinite()) return false;
  if (Fp == nullptr) return true;
  constexpr double hp = 1e-6;
  tr_->weight = WeightFor(eps * std::exp(hp));
  Eigen::VectorXd F1;
  const bool ok = Residuals(&F1, nullptr);
  tr_->weight = WeightFor(eps);
  if (!ok) return false;
  *Fp = (F1 - *F) / hp;
  return Fp->allFinite();
}

bool NewtonAtFixedEps(CurveSystem* sys, double eps, double tol, int max_its, double* max_residual,
                      int* its) {
  Eigen::VectorXd v = sys->Get(), F;
  Eigen::SparseMatrix<double> J;
  for (*its = 0;; ++*its) {
    sys->Set(v);
    if (!sys->Evaluate(eps, &F, *its < max_its ? &J : nullptr, nullptr)) return false;
    *max_residual = F.lpNorm<Eigen::Infinity>();
    if (*max_residual <= tol) return true;
    if (*its == max_its) return false;
    Eigen::VectorXd dv;
    if (!SolveSquare(J, CurveSystem::kJacobianForm, F, &dv)) return false;
    v -= dv;
    sys->transcription()->KeepControlsAsStarts();
  }
}

bool BarrierPath::Evaluate(double p, Eigen::VectorXd* G, Eigen::SparseMatrix<double>* J,
                           Eigen::VectorXd* Gp) {
  return sys_->Evaluate(std::exp(p), G, J, Gp);
}

double BarrierPath::Eps(double p) const { return std::exp(p); }

bool NewtonHomotopy::Start() { return sys_->Evaluate(eps_, &r0_, nullptr, nullptr); }

bool NewtonHomotopy::Evaluate(double t, Eigen::VectorXd* G, Eigen::SparseMatrix<double>* J,
                              Eigen::VectorXd* Gp) {
  if (!sys_->Evaluate(eps_, G, J, nullptr)) return false;
  *G -= (1.0 - t) * r0_;
  if (Gp != nullptr) *Gp = r0_;
  return true;
}

bool NodeBarrierPath::Evaluate(double theta, Eigen::VectorXd* G, Eigen::SparseMatrix<double>* J,
                               Eigen::VectorXd* Gp) {
  Eigen::VectorXd G1;
  constexpr double h = 1e-6;
  if (Gp != nullptr) {  // first, so that the midpoints' data are theta's when it returns
    Select(theta + h);
    if (!sys_->Evaluate(eps_, &G1, nullptr, nullptr)) return false;
  }
  Select(theta);
  if (!sys_->Evaluate(eps_, G, J, nullptr)) return false;
  if (Gp != nullptr) *Gp = (G1 - *G) / h;
  return Gp == nullptr || Gp->allFinite();
}

bool CorrectorStalled(const std::vector<double>& max_residuals) {
  const size_t k = max_residuals.size();
  return k >= 3 && !(max_residuals[k - 1] < max_residuals[k - 3]);
}

bool CorrectorDiverged(const std::vector<double>& max_residuals, double tolerance) {
  return !max_residuals.empty() &&
         !(max_residuals.back() <= 1e6 * std::max(max_residuals.front(), tolerance));
}

bool CorrectorNotContracting(const std::vector<double>& step_lengths, double max_contraction) {
  const size_t k = step_lengths.size();
  return k >= 2 && step_lengths[k - 1] > max_contraction * step_lengths[k - 2];
}

namespace {

// Newton corrector of a step of length ds from the predictor `yp` (tangent t): max |G| <= tol and on the
// hyperplane through yp normal to t; on success also the new unit tangent `tn`, oriented along t.
bool Correct(CurveSystem* sys, PathFamily* family, const Eigen::VectorXd& t,
             const Eigen::VectorXd& yp, double ds, const PathSettings& settings, Eigen::VectorXd* z,
             Eigen::VectorXd* tn, int* its, double* max_residual) {
  const int n = sys->size();
  Eigen::VectorXd G, Gp;
  Eigen::SparseMatrix<double> J;
  std::vector<double> residuals;
  std::vector<double> steps;  // |dz| of the Newton steps
  *z = yp;
  for (*its = 0; *its <= settings.corrector_iterations; ++*its) {
    sys->Set(z->head(n));
    if (!family->Evaluate((*z)[n], &G, &J, &Gp)) return false;
    *max_residual = G.lpNorm<Eigen::Infinity>();
    residuals.push_back(*max_residual);
    const double arc = t.dot(*z - yp);
    if (*max_residual <= settings.tolerance && std::abs(arc) <= 1e-9 * (1.0 + ds)) {
      // the new tangent: [J Gp; t^T] t_new = [0; 1]
      Eigen::VectorXd b = Eigen::VectorXd::Zero(n + 1);
      b[n] = 1.0;
      if (!SolveBordered(J, CurveSystem::kJacobianForm, Gp, t, b, tn)) return false;
      tn->normalize();
      if (tn->dot(t) < 0.0) *tn = -*tn;
      return true;
    }
    if (*its == settings.corrector_iterations) return false;
    if (settings.stop_stalled && CorrectorStalled(residuals)) return false;
    if (CorrectorDiverged(residuals, settings.tolerance)) return false;
    Eigen::VectorXd b(n + 1), dz;
    b.head(n) = -G;
    b[n] = -arc;
    if (!SolveBordered(J, CurveSystem::kJacobianForm, Gp, t, b, &dz)) return false;
    steps.push_back(dz.norm());
    if (CorrectorNotContracting(steps, settings.max_contraction)) return false;
    *z += dz;
    sys->transcription()->KeepControlsAsStarts();
  }
  return false;
}

}  // namespace

PathEnd FollowPath(CurveSystem* sys, PathFamily* family, double p0, const PathSettings& settings,
                   const std::function<void(const PathPoint&)>& report, Eigen::VectorXd* turn) {
  Transcription* tr = sys->transcription();
  const int n = sys->size();
  const double dir = settings.p_end >= p0 ? 1.0 : -1.0;
  Eigen::VectorXd G, Gp, y(n + 1), t(n + 1);
  Eigen::SparseMatrix<double> J;
  y.head(n) = sys->Get();
  y[n] = p0;
  if (!family->Evaluate(p0, &G, &J, &Gp)) return PathEnd::kFailed;
  {  // the first tangent, towards p_end: J dv/dp = -G_p
    Eigen::VectorXd dv_dp;
    if (!SolveSquare(J, CurveSystem::kJacobianForm, -Gp, &dv_dp)) return PathEnd::kFailed;
    t.head(n) = dir * dv_dp;
    t[n] = dir;
    t.normalize();
  }
  double ds = std::abs(settings.first_dp / t[n]);
  std::vector<NodeData> mids_y = tr->mids;
  int budget = settings.max_iterations;
  for (int attempt = 0; attempt < 400 && budget > 0; ++attempt) {
    const auto t0 = std::chrono::steady_clock::now();
    PathPoint point;
    point.last = dir * (y[n] + ds * t[n] - settings.p_end) >= 0.0;
    const double dsi = point.last ? (settings.p_end - y[n]) / t[n] : ds;
    const Eigen::VectorXd yp = y + dsi * t;
    Eigen::VectorXd z, tn;
    if (point.last) {
      sys->Set(yp.head(n));
      family->Select(settings.p_end);
      point.converged = NewtonAtFixedEps(sys, family->Eps(settings.p_end), settings.final_tolerance,
                                         12, &point.max_residual, &point.iterations);
    } else {
      point.converged = Correct(sys, family, t, yp, dsi, settings, &z, &tn, &point.iterations,
                                &point.max_residual);
    }
    point.p = point.last ? settings.p_end : point.converged ? z[n] : yp[n];
    point.slope = point.converged && !point.last ? tn[n] : 0.0;
    point.length = dsi;
    if (point.converged && !point.last) {
      const double along = tn.dot(t);  // the angle by atan2: acos loses small ones to rounding
      point.turn = std::atan2((tn - along * t).norm(), along);
      point.too_sharp = point.turn > settings.max_turn;
    }
    point.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    budget -= point.iterations;
    if (point.Accepted()) tr->KeepControlsAsStarts();
    report(point);
    if (!point.Accepted()) {
      tr->mids = mids_y;
      sys->Set(y.head(n));
      ds = 0.5 * dsi;
      if (ds * std::abs(t[n]) < 1e-6) return PathEnd::kFailed;
      continue;
    }
    if (point.last) return PathEnd::kReached;
    if (dir * tn[n] <= 0.0) {  // a turning point between y and z: stop at z
      *turn = tn.head(n);
      return PathEnd::kTurned;
    }
    y = z;
    t = tn;
    mids_y = tr->mids;
    if (point.iterations <= 3) ds = 1.5 * dsi;
    else if (point.iterations >= 6) ds = 0.7 * dsi;
  }
  return PathEnd::kFailed;
}

}  // namespace ttz::lap
