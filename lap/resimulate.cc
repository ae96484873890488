#include "lap/resimulate.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

#include "lap/model/dynamics.h"
#include "lap/solver/hamiltonian.h"

namespace ttz::lap {
namespace {

constexpr int kTime = kNumStates;      // t, integrated beside the states
constexpr int kNumY = kNumStates + 1;
using Y = std::array<double, kNumY>;

// Dormand-Prince 5(4) (Hairer, Norsett, Wanner, Solving ODE I, Table II.5.2): 7 stages, the
// last one the next step's first (FSAL); the 5th-order solution is propagated.
constexpr int kStages = 7;
constexpr double kC[kStages] = {0.0, 1.0 / 5, 3.0 / 10, 4.0 / 5, 8.0 / 9, 1.0, 1.0};
constexpr double kA[kStages][kStages - 1] = {
    {},
    {1.0 / 5},
    {3.0 / 40, 9.0 / 40},
    {44.0 / 45, -56.0 / 15, 32.0 / 9},
    {19372.0 / 6561, -25360.0 / 2187, 64448.0 / 6561, -212.0 / 729},
    {9017.0 / 3168, -355.0 / 33, 46732.0 / 5247, 49.0 / 176, -5103.0 / 18656},
    {35.0 / 384, 0.0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84}};
// 5th-order weights minus the embedded 4th-order ones: the local error estimate.
constexpr double kErr[kStages] = {71.0 / 57600,      0.0,          -71.0 / 16695, 71.0 / 1920,
                                  -17253.0 / 339200, 22.0 / 525, -1.0 / 40};

// Step-size control: the usual safety factor and bounds of the step's change.
constexpr double kSafety = 0.9, kMinFactor = 0.2, kMaxFactor = 5.0;
// Attempted steps in one mesh interval before the integration is declared stalled (a step of
// 1e-4 of the interval; the stiffest mode of a sane state, the wheel's slip at 5 m/s, needs ~1e-2).
constexpr int kMaxStepsPerInterval = 10000;
// Floor of the energy's scale, relative to the pack (see resimulate.h).
constexpr double kEnergyFloor = 0.01;

// dy/ds on mesh interval k: x' (eq. 36-37) and t' = 1 / sdot (eq. 38), with the interval's own
// control when the solution carries them, else the controls linear in s between u_k and u_{k+1}.
class Slope {
 public:
  Slope(const Vehicle& v, const RoadTrack& road, const LapSolution& sol) : v_(v), road_(road), sol_(sol) {}

  // False where the model is undefined (sdot <= 0, a non-finite derivative).
  bool operator()(size_t k, double s, const Y& y, Y* dy) const {
    const double w = (s - sol_.s[k]) / (sol_.s[k + 1] - sol_.s[k]);
    ControlVector<double> u;
    for (int i = 0; i < kNumControls; ++i)
      u[i] = sol_.u_interval.size() + 1 == sol_.s.size()
                 ? sol_.u_interval[k][i]
                 : (1.0 - w) * sol_.u[k][i] + w * sol_.u[k + 1][i];
    StateVector<double> x;
    std::copy_n(y.begin(), kNumStates, x.begin());
    const ModelPoint<double> m = EvaluateModel(v_, x, u, road_.At(s));
    if (!(m.kin.sdot > 0.0)) return false;
    std::copy(m.dx_ds.begin(), m.dx_ds.end(), dy->begin());
    (*dy)[kTime] = 1.0 / m.kin.sdot;
    return std::all_of(dy->begin(), dy->end(), [](double d) { return std::isfinite(d); });
  }

 private:
  const Vehicle& v_;
  const RoadTrack& road_;
  const LapSolution& sol_;
};

// The adaptive Dormand-Prince integration of one mesh interval after the other.
class Integrator {
 public:
  Integrator(const Slope& slope, const Vehicle& v, const ResimOptions& o) : slope_(slope), options_(o) {
    const Scales sc = DefaultScales(v);
    std::copy(sc.state.begin(), sc.state.end(), error_scale_.begin());
    error_scale_[kTime] = 1.0;  // [s]
  }

  // Advances y from s_k to s_{k+1} of `sol` (y holds the value at s_k); false if the model
  // became undefined or the integration stalled (kMaxStepsPerInterval).
  bool Interval(const LapSolution& sol, size_t k, Y* y) {
    const double a = sol.s[k], b = sol.s[k + 1], h_max = (b - a) / options_.min_substeps;
    double s = a, h = step_ > 0.0 ? std::min(step_, h_max) : h_max;
    std::array<Y, kStages> f;
    if (!slope_(k, s, *y, &f[0])) return false;
    for (int attempt = 0; s < b; ++attempt) {
      if (attempt == kMaxStepsPerInterval) return false;
      const bool last = s + h >= b;
      if (last) h = b - s;
      Y next;
      const double error = Step(k, s, h, *y, &f, &next);
      if (error <= 1.0) {
        s = last ? b : s + h;
        *y = next;
        f[0] = f[kStages - 1];
      }
      const double factor =
          error == 0.0 ? kMaxFactor : std::clamp(kSafety * std::pow(error, -0.2), kMinFactor, kMaxFactor);
      h = std::min(h * factor, h_max);
    }
    step_ = h;
    return true;
  }

  // Forgets the step size (a new window starts from another state).
  void Restart() { step_ = 0.0; }

 private:
  // One step from (s, y) with f[0] = dy/ds there: the 5th-order result in *next, the stages in
  // f, and the scaled local error (<= 1 accepts; infinite where the model is undefined).
  double Step(size_t k, double s, double h, const Y& y, std::array<Y, kStages>* f, Y* next) const {
    for (int j = 1; j < kStages; ++j) {
      Y stage = y;
      for (int l = 0; l < j; ++l)
        for (int i = 0; i < kNumY; ++i) stage[i] += h * kA[j][l] * (*f)[l][i];
      if (!slope_(k, s + kC[j] * h, stage, &(*f)[j])) return std::numeric_limits<double>::infinity();
      if (j == kStages - 1) *next = stage;  // the last stage is at the 5th-order solution
    }
    double error = 0.0;
    for (int i = 0; i < kNumY; ++i) {
      double e = 0.0;
      for (int j = 0; j < kStages; ++j) e += kErr[j] * (*f)[j][i];
      const double tolerance = options_.step_tolerance * std::max(error_scale_[i], std::abs((*next)[i]));
      error = std::max(error, std::abs(h * e) / tolerance);
    }
    return error;
  }

  const Slope& slope_;
  const ResimOptions& options_;
  Y error_scale_;
  double step_ = 0.0;  // the last accepted step's successor [m]; 0 at a window's start
};

// Records the scaled differences of the re-simulated x at node k; returns the state with the
// largest.
int Record(const LapSolution& sol, size_t k, const Y& y, ResimReport* r) {
  StateVector<double>& d = r->state_difference[k];
  for (int i = 0; i < kNumStates; ++i) d[i] = std::abs(y[i] - sol.x[k][i]) / r->scale[i];
  return static_cast<int>(std::max_element(d.begin(), d.end()) - d.begin());
}

// Each state's largest difference, the largest of all and where it is, from the nodes reached.
void Summarise(const LapSolution& sol, ResimReport* r) {
  for (size_t k = 0; k < sol.s.size(); ++k)
    for (int i = 0; i < kNumStates; ++i) {
      const double d = r->state_difference[k][i];  // NaN where not reached: no comparison holds
      if (d > r->max_state_difference[i]) r->max_state_difference[i] = d;
      if (d > r->max_state_difference_all) {
        r->max_state_difference_all = d;
        r->worst_state = i;
        r->worst_s = sol.s[k];
      }
    }
}

// The last node of the window that starts at node `first`: the last within `window` seconds of
// the solution's time, at least the next one.
size_t WindowEnd(const std::vector<double>& t, size_t first, double window) {
  size_t last = first + 1;
  while (last + 1 < t.size() && t[last + 1] <= t[first] + window) ++last;
  return last;
}

// Integrates the window of nodes [first, last] from the solution's state at `first`; returns
// the window's time, or NaN (with r->message) when it diverged.
double Window(const LapSolution& sol, size_t first, size_t last, const ResimOptions& o,
              Integrator* integrator, ResimReport* r) {
  Y y;
  std::copy(sol.x[first].begin(), sol.x[first].end(), y.begin());
  y[kTime] = 0.0;
  integrator->Restart();
  for (size_t k = first; k < last; ++k) {
    const bool defined = integrator->Interval(sol, k, &y);
    const int worst = defined ? Record(sol, k + 1, y, r) : 0;
    const double largest = r->state_difference[k + 1][worst];
    if (!defined || !(largest <= o.abandon_difference)) {
      std::ostringstream m;
      m << "re-simulation diverged: ";
      if (defined)
        m << kStateNames[worst] << " off by " << 100.0 * largest << " % of its scale";
      else
        m << "the model is undefined or the integration stalls";
      m << " at s = " << sol.s[k + 1] << " m, in the window from s = " << sol.s[first] << " m";
      r->message = m.str();
      return std::numeric_limits<double>::quiet_NaN();
    }
  }
  return y[kTime];
}

// Why the differences fail the criterion ("" when they pass; NaN fails).
std::string Verdict(const ResimReport& r, double tolerance) {
  std::ostringstream m;
  if (!(r.lap_time_relative <= tolerance))
    m << "re-simulated lap time differs by " << 100.0 * r.lap_time_relative << " % (> " << 100.0 * tolerance
      << " %)";
  if (!(r.max_state_difference_all <= tolerance)) {
    m << (m.tellp() > 0 ? "; " : "") << "re-simulated " << kStateNames[r.worst_state] << " differs by "
      << 100.0 * r.max_state_difference_all << " % of its scale at s = " << r.worst_s << " m (> "
      << 100.0 * tolerance << " %); the states over it:";
    for (int i = 0; i < kNumStates; ++i)
      if (!(r.max_state_difference[i] <= tolerance)) m << " " << kStateNames[i];
  }
  return m.str();
}

}  // namespace

StateVector<double> ResimStateScales(const Vehicle& v, const LapSolution& sol) {
  StateVector<double> floor = DefaultScales(v).state, scale;
  floor[kE] = kEnergyFloor * v.pack.e_i;
  for (int i = 0; i < kNumStates; ++i) {
    const auto [lo, hi] = std::minmax_element(sol.x.begin(), sol.x.end(), [i](const auto& a, const auto& b) {
      return a[i] < b[i];
    });
    scale[i] = std::max((*hi)[i] - (*lo)[i], floor[i]);
  }
  return scale;
}

ResimReport Resimulate(const Vehicle& v, const RoadTrack& road, const LapSolution& sol,
                       const ResimOptions& options) {
  ResimReport r;
  const size_t n = sol.s.size();
  if (n < 2 || sol.x.size() != n || sol.u.size() != n || sol.t.size() != n) {
    r.lap_time = r.lap_time_difference = r.lap_time_relative = std::numeric_limits<double>::quiet_NaN();
    r.message = "no solution to re-simulate (fewer than two nodes with states, controls and times)";
    return r;
  }
  r.scale = ResimStateScales(v, sol);
  StateVector<double> unreached;
  unreached.fill(std::numeric_limits<double>::quiet_NaN());
  r.state_difference.assign(n, unreached);
  r.state_difference.front().fill(0.0);  // the start: the solution's own state
  const Slope slope(v, road, sol);
  Integrator integrator(slope, v, options);
  for (size_t first = 0; first + 1 < sol.s.size() && r.message.empty(); ++r.windows) {
    const size_t last = WindowEnd(sol.t, first, options.window_seconds);
    r.lap_time += Window(sol, first, last, options, &integrator, &r);
    first = last;
  }
  Summarise(sol, &r);
  r.lap_time_difference = r.lap_time - sol.t.back();
  r.lap_time_relative = std::abs(r.lap_time_difference) / sol.t.back();
  if (r.message.empty()) r.message = Verdict(r, options.tolerance);
  r.passed = r.message.empty();
  return r;
}

}  // namespace ttz::lap
