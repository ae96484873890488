// Curves of solutions of the indirect solver's square system F(v; eps) = 0 (indirect.cc), followed
// by pseudo-arclength steps with Newton correctors on sparse LU (sparse_lu.h): the barrier
// continuation in (v, log eps), the Newton homotopy H(v, t) = F(v) - (1 - t) F(v0) at a fixed
// eps, which takes a start v0 near a solution to it where Levenberg-Marquardt creeps, and the node
// barriers' share of a fixed eps, from the midpoints' barriers alone to the answer's (docs/lap.md).
#pragma once

#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "lap/solver/staircase_lu.h"
#include "lap/solver/transcription.h"

namespace ttz::lap {

// The barrier weight eps with its relaxation delta = min(1e-3, 0.1 eps) (lap-solver notes).
BarrierWeight WeightFor(double eps);

// The square system F(v; eps) = 0 of the free unknowns v (tangent-space order of Ceres: costates
// of node 0, then every unknown of nodes 1..N-1, then the states of node N).
class CurveSystem {
 public:
  explicit CurveSystem(Transcription* tr);
  int size() const { return n_; }
  Transcription* transcription() const { return tr_; }
  Eigen::VectorXd Get() const;
  void Set(const Eigen::VectorXd& v);
  // F at the current unknowns and eps; with J: also dF/dv; with Fp: dF/dp, p = log(eps), by a
  // forward difference. False when an evaluation fails or is not finite. The same F and J as
  // Ceres' Problem::Evaluate of the transcription's problem (BuildProblem), assembled here: the
  // interval blocks on the transcription's threads, straight into J's fixed pattern, without
  // Ceres' CRS copy of J and its conversion to Eigen (first 10 km of the TT course: peak memory
  // 166 MB against 377 MB, the same time; docs/lap_log.md "The square system assembled in place").
  bool Evaluate(double eps, Eigen::VectorXd* F, Eigen::SparseMatrix<double>* J,
                Eigen::VectorXd* Fp);
  // Where a direction `d` of the unknowns (a tangent at a turning point: the direction in which
  // the solution changes while eps does not) moves the states (scaled): the node and state of its
  // largest part, and the stretch of road between the first and the last node of the parts
  // >= 10 % of it.
  std::string DescribeStateDirection(const Eigen::VectorXd& d) const;
  // The entries of dF/dv (Evaluate writes into a J that has as many): 2 kW per column, kW in
  // the columns of node 0's costates and node N's states.
  Eigen::Index JacobianEntries() const {
    return 2 * kW * (static_cast<Eigen::Index>(n_) - kNumStates);
  }
  // dF/dv's staircase form (staircase_lu.h): interval k's kW rows touch the unknowns of nodes k
  // and k + 1, of which node 0 has its kNumStates costates.
  static constexpr Staircase kJacobianForm{kW, kNumStates};

 private:
  // Position in v of unknown i of node k (node 0 contributes its costates, node N its states).
  static int Index(int k, int i);
  template <typename Visit>
  void ForEachUnknown(Visit visit) const;
  // F and, with J, dF/dv at the current unknowns and weight.
  bool Residuals(Eigen::VectorXd* F, Eigen::SparseMatrix<double>* J);
  // dF/dv's pattern, values zero: the column of unknown i of node k holds the 24 rows of
  // interval k - 1 (if k > 0), then those of interval k (if k < N), every entry of the blocks
  // (as Ceres' CRS).
  Eigen::SparseMatrix<double> Pattern() const;

  Transcription* tr_;
  int n_;
};

// Newton with sparse LU at fixed eps from the current unknowns; true when max |F| <= tol.
bool NewtonAtFixedEps(CurveSystem* sys, double eps, double tol, int max_its, double* max_residual,
                      int* its);

// A one-parameter family G(v, p) = 0 of square systems whose member at the path's end is
// F(v; Eps(p_end)) = 0.
class PathFamily {
 public:
  virtual ~PathFamily() = default;
  // G, dG/dv and dG/dp at the unknowns of the system and p.
  virtual bool Evaluate(double p, Eigen::VectorXd* G, Eigen::SparseMatrix<double>* J,
                        Eigen::VectorXd* Gp) = 0;
  virtual double Eps(double p) const = 0;  // the barrier weight at p
  // Makes the member at p the system F that NewtonAtFixedEps(Eps(p)) solves (FollowPath's last
  // step), where that is not eps alone.
  virtual void Select(double p) {}
};

// The barrier continuation: p = log eps, G = F(v; e^p).
class BarrierPath : public PathFamily {
 public:
  explicit BarrierPath(CurveSystem* sys) : sys_(sys) {}
  bool Evaluate(double p, Eigen::VectorXd* G, Eigen::SparseMatrix<double>* J,
                Eigen::VectorXd* Gp) final;
  double Eps(double p) const final;

 private:
  CurveSystem* sys_;
};

// Newton's homotopy at a fixed eps: p = t, G = F(v; eps) - (1 - t) r0 with r0 = F(v0; eps) at the
// unknowns v0 where it is built (t = 0); G = F at t = 1.
class NewtonHomotopy : public PathFamily {
 public:
  NewtonHomotopy(CurveSystem* sys, double eps) : sys_(sys), eps_(eps) {}
  bool Start();  // r0 = F(v0; eps); false when F cannot be evaluated
  const Eigen::VectorXd& r0() const { return r0_; }
  bool Evaluate(double t, Eigen::VectorXd* G, Eigen::SparseMatrix<double>* J,
                Eigen::VectorXd* Gp) final;
  double Eps(double) const final { return eps_; }

 private:
  CurveSystem* sys_;
  double eps_;
  Eigen::VectorXd r0_;
};

// The node barriers switched on at a fixed eps: p = theta, their share of eps
// (Transcription::node_share), from the midpoints' barriers alone (0) to the answer's split (1);
// G = F(v; eps, theta), dG/dtheta by a forward difference.
class NodeBarrierPath : public PathFamily {
 public:
  NodeBarrierPath(CurveSystem* sys, double eps) : sys_(sys), eps_(eps) {}
  bool Evaluate(double theta, Eigen::VectorXd* G, Eigen::SparseMatrix<double>* J,
                Eigen::VectorXd* Gp) final;
  double Eps(double) const final { return eps_; }
  void Select(double theta) final { sys_->transcription()->node_share = theta; }

 private:
  CurveSystem* sys_;
  double eps_;
};

struct PathSettings {
  double p_end = 0.0;                 // where the path ends
  double first_dp = 0.1;              // the first step's change of p
  double tolerance = 1e-7;            // max |G| at the points before the end
  double final_tolerance = 1e-8;      // max |F| at the end (Newton at Eps(p_end), <= 12 its)
  int corrector_iterations = 8;       // Newton iterations of a step's corrector before it is halved
  bool stop_stalled = true;           // a corrector that stalled (CorrectorStalled) fails at once
  // A corrector fails at once when a Newton step |dz| (scaled unknowns and p) is longer than this
  // times the step before (CorrectorNotContracting); infinity: never.
  double max_contraction = std::numeric_limits<double>::infinity();
  int max_iterations = std::numeric_limits<int>::max();  // over all steps
  // A step whose corrector converged but whose tangent turned by more than this [rad] is retried
  // at half its length, as a failed one: the curve bends too sharply there for the step to say
  // where it goes (a turning point among them); infinity: never.
  double max_turn = std::numeric_limits<double>::infinity();
};

// Whether a Newton corrector has stalled: its last max |G| (of iterates 0, 1, ...) is no smaller
// than two iterates before, a floor or a cycle (at a kink of G). On the TT course's first 10 km
// (20 m, at most 0.5 s, 3 km windows) the failed correctors' iterates had sat at such floors
// (6.4e-2, 6.5e-2, 6.2e-2, ...) or cycled (2.1e-2, 3.2e-2, 2.1e-2, ...) for up to 8 iterations,
// and no corrector that converged had done this (docs/lap_log.md "Stalled correctors"). FollowPath
// stops such a corrector with PathSettings::stop_stalled.
bool CorrectorStalled(const std::vector<double>& max_residuals);

// Whether a Newton corrector has diverged: its last max |G| is above 1e6 times its predictor's (or
// the tolerance, if larger) or not finite. On the whole TT course the barrier continuation's
// failed correctors below eps 2e-3 ran to max |G| of 1e9-1e16 before failing, and at such an
// iterate the bordered solve, its block elimination missing its accuracy, fell back to UMFPACK on
// the bordered matrix (15-23 s, 2.8 GB). With the rule the whole course's 1,219 steps converged
// or failed as without it, 12 failed ones sooner (docs/lap_log.md "Two chains and diverged
// correctors"). FollowPath stops such a corrector on every path.
bool CorrectorDiverged(const std::vector<double>& max_residuals, double tolerance);

// Whether a Newton corrector does not contract: its last step |dz| is longer than
// max_contraction times the step before (Deuflhard's monotonicity test; the steps of a Newton
// iteration that converges shrink, quadratically near the solution). On the whole TT course (20
// m, at most 0.5 s) the converged correctors of the barrier continuation had shrunk each step 3 to
// 100 times (|dz| 0.18, 0.0076, 0.0014, 5.3e-5), the failed ones had stopped shrinking after their
// first step and spent their 8 iterations at 0.2-1.6 (0.85, 0.46, 0.67, 0.92, 1.0, 1.0, 1.4, 1.6)
// (docs/lap_log.md "Correctors that do not contract"). FollowPath stops such a corrector with
// PathSettings::max_contraction.
bool CorrectorNotContracting(const std::vector<double>& step_lengths, double max_contraction);

// One step of FollowPath: p where it converged (the predictor's p when it failed).
struct PathPoint {
  double p = 0.0;
  int iterations = 0;
  double seconds = 0.0;
  bool converged = false;
  bool last = false;           // at p_end
  double max_residual = 0.0;   // max |G| at its last iterate
  double slope = 0.0;          // dp/ds of the new tangent (not at the last step)
  double length = 0.0;         // the step's arclength ds (scaled unknowns and p)
  double turn = 0.0;           // angle between the tangents before and after it [rad] (not at a
                               // failed or the last step: 0)
  bool too_sharp = false;      // converged, but turned by more than max_turn: retried shorter
  bool Accepted() const { return converged && !too_sharp; }
};

enum class PathEnd { kReached, kTurned, kFailed };

// Follows the solution curve of `family` from the solution at p0 in `sys` (G(v, p0) = 0) towards
// settings.p_end: predictor along the unit tangent of (v, p), Newton corrector on
// [G; t^T (y - y_pred)] = 0 (the bordered system), the step grown after an easy corrector (<= 3
// iterations) and shrunk after a hard one (>= 6), halved after a failed one (one that spent
// corrector_iterations, diverged, did not contract (max_contraction) or, with stop_stalled,
// stalled) or one that turned by more than max_turn (the unknowns and the controls' Newton
// starts back at the last point, after the step is reported with the unknowns at its last
// iterate); the last step lands on p_end and converges there by Newton on F. Reports every step;
// stops at a turning point (p starts to go back: kTurned, with the tangent there in `turn`), after
// 400 steps, when a step shrinks below 1e-6 in p or the iterations exceed their budget (kFailed).
// The unknowns are left at the last converged point.
PathEnd FollowPath(CurveSystem* sys, PathFamily* family, double p0, const PathSettings& settings,
                   const std::function<void(const PathPoint&)>& report, Eigen::VectorXd* turn);

}  // namespace ttz::lap
