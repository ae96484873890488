// The QSS lap (qss.h). At every node the bike is in the model's own quasi-steady state on the
// centre line (QuasiSteadyResidual below: eq. 10 and 13-16 solved for the attitude at a given
// speed and acceleration), so the QSS and the optimal solvers share every force. What keeps the
// QSS lap no faster than the model can go, on the same mesh:
// - Heat and charge: the motor temperature T (eq. 27-29) and the battery energy e (eq. 33) are
//   integrated along the profile and every node's limits use them: a hot motor has less torque per
//   ampere k_tau (eq. 26), a discharged pack a lower voltage V_bn (eq. 22b).
// - Wheel slip: the wheel spins at omega_w = V (1 + kappa_w) / R_e with kappa_w = F_x / (N K_kappa)
//   (eq. 18, 20), so the motor's back e.m.f. (eq. 24) meets the voltage limits earlier.
// - The model's own forces at the node: the load N with the aerodynamic lift (eq. 21) and the
//   road's vertical curvature, the rolling radius R_e at the lean (eq. 20), the rolling resistance
//   mu_r (N cos(phi) + F_y sin(phi)) R_e (eq. 18, larger in a lean), the tyre force lost to the
//   sideslip in a bend, the wheel's spin-up torque (eq. 16).
// - Speed step V_{i+1}^2 = V_i^2 + 2 h a_{i+1} with the acceleration a_{i+1} of the interval's end,
//   and T, e likewise with the end's rates: along an acceleration the limit falls with speed, heat
//   and discharge, so the step stays below the true profile, and the trapezoidal rule
//   V_{k+1} - V_k = h/2 (a_k / V_k + a_{k+1} / V_{k+1}) gains more speed from the same a.
// - Braking to the later speed caps with the braking limit of each interval's slower end.
// - Lap time by the trapezoidal rule of 1/V (eq. 38), the longer of the two usual rules (1/V is
//   convex): the solvers' midpoint rule times an interval by 1/sdot at the mean state, about
//   2 h / (V_i + V_{i+1}) on the centre line, so the QSS time of a profile is never the shorter.
// - Speed caps from the adherence, the yaw rate and the roll rate (SpeedCap), each at kSafety of
//   its limit; the pack's power capped so that its energy stays >= 0 (eq. 39g), all but the
//   ~50 W the smoothed motor current draws with the throttle shut (StepForward).
// - A pack too small for the lap at full power: the faster of full power until the pack is empty
//   and one pack-power limit for the whole lap, the largest that ends the lap with kChargeReserve
//   of the pack left (EnergyLimitedPass). On a long road the first can be a far slower guess (a
//   25 MJ pack on the TT course: 7031 s against 2156 s) and, through --dt-max, a finer mesh.
#include "lap/qss.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>

#include "lap/model/dynamics.h"

namespace ttz::lap {
namespace {

// Share of the tyre's adherence and of the yaw- and roll-rate limits that the QSS uses: strictly
// inside, so the guess is feasible and the optimum has room to be faster.
constexpr double kSafety = 0.95;
// Speed floor [m/s]: the model needs V > 0 (eq. 37); a climb too steep for the bike holds it here.
constexpr double kMinSpeed = 1.0;
// Speed cap where nothing else caps the speed [m/s].
constexpr double kMaxSpeed = 150.0;
// Share of the pack's energy that a QSS lap limited by its pack keeps at the end, so that its guess
// is strictly inside the charge constraint (eq. 39g).
constexpr double kChargeReserve = 0.01;

// ---- The model's quasi-steady state at one node ----------------------------------------------

// Unknowns of the quasi-steady state at a given speed.
enum QuasiIndex : int { kQAlpha = 0, kQBeta, kQZ, kQPhi, kQOmegaW, kQTauW, kQOmegaZ, kNumQuasi };
using QuasiVector = Eigen::Matrix<double, kNumQuasi, 1>;

// Speed, longitudinal acceleration dV/dt, motor temperature and battery energy at a node.
struct Motion {
  double V, a, T, e;
};

// The model's state on the centre line (n = 0) with no roll, vertical or yaw-rate change.
template <typename J>
StateVector<J> StateOf(const Motion& mo, const std::array<J, kNumQuasi>& q) {
  StateVector<J> x;
  x[kN] = Cst<J>(0.0);
  x[kAlpha] = q[kQAlpha];
  x[kV] = Cst<J>(mo.V);
  x[kBeta] = q[kQBeta];
  x[kZ] = q[kQZ];
  x[kPhi] = q[kQPhi];
  x[kOmegaW] = q[kQOmegaW];
  x[kT] = Cst<J>(mo.T);
  x[kE] = Cst<J>(mo.e);
  x[kOmegaPhi] = Cst<J>(0.0);
  x[kZdot] = Cst<J>(0.0);
  x[kOmegaZ] = q[kQOmegaZ];
  x[kTauW] = q[kQTauW];
  return x;
}

// The conditions of quasi-steady motion (eq. 10, 13-16), zero at the solution: the speed changes
// at the rate a; sideslip, tyre compression and lean hold still; the wheel keeps its spin per unit
// speed (slip and rolling radius frozen: domega_w/dt = a omega_w / V); the contact point follows
// the centre line (dn/dt = dalpha/dt = 0, so tan(alpha) = beta). Also returns the tyre force F_x.
template <typename J>
std::array<J, kNumQuasi> QuasiSteadyResidual(const Vehicle& v, const RoadPoint& rp,
                                             const Motion& mo, const std::array<J, kNumQuasi>& q,
                                             J* F_x) {
  const ControlVector<J> u = {Cst<J>(0.0), Cst<J>(0.0)};
  const ModelPoint<J> m = EvaluateModel(v, StateOf(mo, q), u, rp);
  *F_x = m.tyre.F_x;
  return {m.acc[kVdot] - mo.a,
          m.acc[kBetadot],
          m.acc[kZddot],
          m.acc[kPhiddot],
          m.acc[kOmegaWdot] - mo.a * q[kQOmegaW] / mo.V,
          m.kin.ndot,
          m.kin.alphadot};
}

StateVector<double> StateAt(const Motion& mo, const QuasiVector& q) {
  std::array<double, kNumQuasi> qd;
  std::copy(q.data(), q.data() + kNumQuasi, qd.begin());
  return StateOf(mo, qd);
}

// A solved node: the quasi-steady unknowns q at `mo`, the model there, and how the wheel torque,
// wheel speed and tyre force move with the acceleration at fixed speed (implicit-function theorem
// on the conditions above), which the limits below use to search the acceleration.
struct NodePoint {
  Motion mo{};
  QuasiVector q = QuasiVector::Zero();
  QuasiVector dq_da = QuasiVector::Zero();
  double dFx_da = 0.0;
  ModelPoint<double> m;
  bool solved = false;
};

// An upright start for the Newton: load from weight, the road's normal curvature and lift
// (eq. 13c, 21), the lean of a toroidal tyre tan(phi) = (V^2 kappa - g sin(xi)) / (g cos(xi) +
// V^2 nu) h / (h - r_t) (the banking xi takes its share of the turn, lap/model/chassis.h), slip
// from the force M a + D (eq. 13a, 18, 20).
QuasiVector UprightStart(const Vehicle& v, const RoadPoint& rp, const Motion& mo) {
  const double V2 = mo.V * mo.V, lateral = V2 * rp.kappa - v.g * std::sin(rp.xi);
  const double normal = v.g * std::cos(rp.xi) + V2 * rp.nu;  // per unit mass, without the lift
  const double N = v.M * normal - v.lift_k * V2, z = N / v.K_s, R_e = v.r - z;
  const double F_x = v.M * mo.a + v.drag_k * mo.V * mo.V;
  QuasiVector q = QuasiVector::Zero();
  q[kQZ] = z;
  q[kQPhi] = std::atan(lateral / normal * v.h / (v.h - v.r_t));
  q[kQOmegaW] = mo.V * (1.0 + F_x / (N * v.K_kappa)) / R_e;
  q[kQTauW] = (F_x + v.mu_r * N) * R_e;
  q[kQOmegaZ] = mo.V * rp.kappa;
  return q;
}

// Newton from np->q; on success fills np (the model, the sensitivities) and returns true, else
// leaves np as it was.
bool Newton(const Vehicle& v, const RoadPoint& rp, const Motion& mo, NodePoint* np) {
  using J = ceres::Jet<double, kNumQuasi>;
  QuasiVector q = np->q;
  for (int it = 0; it < 30; ++it) {
    std::array<J, kNumQuasi> qj;
    for (int i = 0; i < kNumQuasi; ++i) qj[i] = J(q[i], i);
    J F_x;
    const std::array<J, kNumQuasi> r = QuasiSteadyResidual(v, rp, mo, qj, &F_x);
    Eigen::Matrix<double, kNumQuasi, kNumQuasi> jac;
    QuasiVector res;
    for (int i = 0; i < kNumQuasi; ++i) {
      res[i] = r[i].a;
      jac.row(i) = r[i].v.transpose();
    }
    if (!res.allFinite()) return false;
    const Eigen::PartialPivLU<Eigen::Matrix<double, kNumQuasi, kNumQuasi>> lu(jac);
    if (res.cwiseAbs().maxCoeff() <= 1e-9) {
      QuasiVector dr_da = QuasiVector::Zero();  // d(residual)/da
      dr_da[0] = -1.0;
      dr_da[4] = -q[kQOmegaW] / mo.V;
      np->mo = mo;
      np->q = q;
      np->dq_da = -lu.solve(dr_da);
      np->dFx_da = F_x.v.dot(np->dq_da);
      np->m = EvaluateModel(v, StateAt(mo, q), ControlVector<double>{}, rp);
      return true;
    }
    q -= lu.solve(res);
    if (!q.allFinite() || std::abs(q[kQPhi]) > 1.4) return false;
  }
  return false;
}

// Solves the node at `mo`, from np->q (the previous node's answer) and else from upright. Should
// both fail (no steady state exists, e.g. a start faster than the bend allows), np keeps the
// upright estimate, evaluated by the model, with the sensitivities of a point mass.
void Solve(const Vehicle& v, const RoadPoint& rp, const Motion& mo, NodePoint* np) {
  if (np->solved && Newton(v, rp, mo, np)) return;
  np->q = UprightStart(v, rp, mo);
  np->solved = Newton(v, rp, mo, np);
  if (np->solved) return;
  np->mo = mo;
  np->dq_da.setZero();
  np->dq_da[kQTauW] = v.M * (v.r - np->q[kQZ]) + v.I_wy * np->q[kQOmegaW] / mo.V;
  np->dFx_da = v.M;
  np->m = EvaluateModel(v, StateAt(mo, np->q), ControlVector<double>{}, rp);
}

// ---- Limits on the acceleration at a node ----------------------------------------------------

// Wheel torque, wheel speed and tyre force at acceleration a, to first order about the solved
// point (exact at the acceleration it was solved for).
struct Drive {
  double tau_w, omega_w, F_x;
};

Drive DriveAt(const NodePoint& np, double a) {
  const double da = a - np.mo.a;
  return {np.q[kQTauW] + np.dq_da[kQTauW] * da, np.q[kQOmegaW] + np.dq_da[kQOmegaW] * da,
          np.m.tyre.F_x + np.dFx_da * da};
}

Powertrain<double> PowertrainAt(const Vehicle& v, const NodePoint& np, const Drive& d) {
  return ComputePowertrain(v, d.tau_w, d.omega_w, np.mo.V, np.mo.T, np.mo.e);
}

// The longitudinal force the tyre has left beside the lateral force, kSafety of eq. 19 [N].
double LongitudinalBudget(const Vehicle& v, const NodePoint& np) {
  const double N = np.m.tyre.N, lateral = np.m.tyre.F_y / (N * v.mu_y);
  return kSafety * v.mu_x * N * std::sqrt(std::max(0.0, 1.0 - lateral * lateral));
}

// The acceleration with the throttle shut: the controller's demand zero, the wheel torque the
// motor's friction drag -eta_c gamma_c k_tau i_m0 (eq. 25, 26, 31; powertrain.h).
double CoastAcceleration(const Vehicle& v, const NodePoint& np) {
  const double k_tau = v.motor.k_tau0 - v.motor.sigma_m * (np.mo.T - v.motor.T_0);
  const double tau = -v.eta_c * v.gamma_c * k_tau * v.motor.i_m0;
  return np.mo.a + (tau - np.q[kQTauW]) / np.dq_da[kQTauW];
}

// Traction within the tyre and every power-train limit (eq. 19, 39e-f, section 5), with the pack's
// power capped at power_cap [W].
bool WithinDriveLimits(const Vehicle& v, const NodePoint& np, double a, double power_cap) {
  const Drive d = DriveAt(np, a);
  const Powertrain<double> p = PowertrainAt(v, np, d);
  return d.F_x <= LongitudinalBudget(v, np) && p.i_m <= v.motor.current_max &&
         p.P_b <= power_cap && p.V_mm <= v.motor.voltage_max && p.V_mm <= p.V_mb;
}

// The largest acceleration within the limits, by bisection (every limit grows with the wheel
// torque and, through the slip, with the wheel speed, both increasing in a); the coasting
// acceleration if even that breaks a limit (the back e.m.f. alone above the voltage limit).
double MaxAcceleration(const Vehicle& v, const NodePoint& np, double power_cap) {
  double lo = CoastAcceleration(v, np), hi = lo + 2.0 * v.mu_x * v.g;
  if (!WithinDriveLimits(v, np, lo, power_cap)) return lo;
  for (int i = 0; i < 50; ++i) {
    const double mid = 0.5 * (lo + hi);
    (WithinDriveLimits(v, np, mid, power_cap) ? lo : hi) = mid;
  }
  return lo;
}

// The smallest (most negative) acceleration: the tyre's braking force (eq. 19) or the brake's
// torque, whichever binds first.
double MinAcceleration(const Vehicle& v, const NodePoint& np) {
  const double a = np.mo.a;
  const double by_tyre = a + (-LongitudinalBudget(v, np) - np.m.tyre.F_x) / np.dFx_da;
  const double by_brake = a + (-v.brake_torque_max - np.q[kQTauW]) / np.dq_da[kQTauW];
  return std::max(by_tyre, by_brake);
}

// ---- The speed profile -----------------------------------------------------------------------

// The speed above which the QSS may not go at a road point, each limit at kSafety:
// - lateral adherence |F_y| <= mu_y N (eq. 19) with F_y = M (V^2 kappa - g sin(xi)), the banking
//   xi pulling to the right (lap/model/chassis.h), and N = M (g cos(xi) + V^2 nu) - L (eq. 13c,
//   21), on either side: V^2 (+-M kappa + kSafety mu_y (lift_k - M nu)) <= M g (kSafety mu_y
//   cos(xi) +- sin(xi)) (a bank steeper than the tyre holds caps at kMinSpeed); the model's F_y
//   is ~1 % less (the centre of mass leans into the bend);
// - yaw rate |Omega_z| = V |kappa| <= Omega_z_max (eq. 39c);
// - roll rate (eq. 39b) as the lean follows the curvature: with tan(phi) = k V^2 kappa / g,
//   |omega_phi| = V |dphi/ds| <= k V^3 |dkappa/ds| / g. The lean factor k is largest upright,
//   where the toroidal tyre makes it h / (h - r_t) (1.2 for the bx15, whose model lean is 1.22
//   times atan(V^2 kappa / g) with the gyroscopic moment); 1.1 h / (h - r_t) bounds it.
double SpeedCap(const Vehicle& v, const RoadPoint& rp) {
  double cap = kMaxSpeed;
  const double k = std::abs(rp.kappa);
  for (const double side : {1.0, -1.0}) {
    const double a = side * v.M * rp.kappa + kSafety * v.mu_y * (v.lift_k - v.M * rp.nu);
    const double b = v.M * v.g * (kSafety * v.mu_y * std::cos(rp.xi) + side * std::sin(rp.xi));
    if (a > 0.0) cap = std::min(cap, std::sqrt(std::max(b / a, kMinSpeed * kMinSpeed)));
  }
  if (k > 0.0) cap = std::min(cap, kSafety * v.Omega_z_max / k);
  const double lean = 1.1 * v.h / (v.h - v.r_t);
  if (rp.dkappa != 0.0)
    cap = std::min(cap, std::cbrt(kSafety * v.omega_phi_max * v.g / (lean * std::abs(rp.dkappa))));
  return cap;
}

// Backward pass: the largest speed at each node from which the bike can still brake to every later
// cap, V_{i-1}^2 = V_i^2 - 2 h a_min with the braking limit of node i, the slower end (the
// mechanics do not depend on T and e; they are held at T0 and e0).
std::vector<double> BrakingEnvelope(const Vehicle& v, const std::vector<RoadPoint>& rp,
                                    const std::vector<double>& mesh,
                                    const std::vector<double>& cap) {
  const int n = static_cast<int>(mesh.size());
  std::vector<double> envelope = cap;
  NodePoint np;
  double a = 0.0;
  for (int i = n - 1; i > 0; --i) {
    Solve(v, rp[i], Motion{envelope[i], a, v.T0, v.e0}, &np);
    a = MinAcceleration(v, np);
    const double h = mesh[i] - mesh[i - 1];
    const double V2 = envelope[i] * envelope[i] - 2.0 * h * a;
    envelope[i - 1] = std::min(cap[i - 1], std::sqrt(std::max(kMinSpeed * kMinSpeed, V2)));
  }
  return envelope;
}

// Node i + 1 from node i: full throttle within every limit, or the envelope's speed where that is
// lower. The fixed point of
//   V^2 = V_i^2 + 2 h a,   T = T_i + T_dot dt,   e = e_i + e_dot dt,   dt = h/2 (1/V_i + 1/V)
// with a, T_dot and e_dot of node i + 1; the pack's power is capped at power_limit [W] and so that
// e >= 0 (eq. 39g), but never below what it draws with the throttle shut (the smoothed motor
// current, smooth.h).
NodePoint StepForward(const Vehicle& v, const RoadPoint& rp, const NodePoint& prev, double h,
                      double envelope, double power_limit) {
  NodePoint np = prev;
  Motion mo = prev.mo;
  for (int it = 0; it < 30; ++it) {
    Solve(v, rp, mo, &np);
    const double dt = 0.5 * h * (1.0 / prev.mo.V + 1.0 / mo.V);
    Motion next = mo;
    next.T = prev.mo.T + np.m.power.T_dot * dt;
    next.e = prev.mo.e + np.m.power.e_dot * dt;
    const double idle = PowertrainAt(v, np, DriveAt(np, CoastAcceleration(v, np))).P_b;
    const double power_cap = std::max(std::min(power_limit, prev.mo.e / dt), idle);
    const double V2 = prev.mo.V * prev.mo.V + 2.0 * h * MaxAcceleration(v, np, power_cap);
    next.V = std::clamp(std::sqrt(std::max(0.0, V2)), kMinSpeed, std::max(kMinSpeed, envelope));
    next.a = (next.V * next.V - prev.mo.V * prev.mo.V) / (2.0 * h);
    const bool settled = std::abs(next.V - mo.V) <= 1e-10 * mo.V &&
                         std::abs(next.T - mo.T) <= 1e-9 && std::abs(next.e - mo.e) <= 1e-6;
    mo = next;
    if (settled) break;
  }
  Solve(v, rp, mo, &np);
  return np;
}

// Forward pass from the bike's initial state with the pack's power at most power_limit [W]. Node 0
// takes the first interval's acceleration (the step rule uses only the later node's).
std::vector<NodePoint> ForwardPass(const Vehicle& v, const std::vector<RoadPoint>& rp,
                                   const std::vector<double>& mesh,
                                   const std::vector<double>& envelope, double power_limit) {
  const int n = static_cast<int>(mesh.size());
  std::vector<NodePoint> nodes(n);
  Solve(v, rp[0], Motion{v.V0, 0.0, v.T0, v.e0}, &nodes[0]);
  for (int i = 0; i + 1 < n; ++i)
    nodes[i + 1] =
        StepForward(v, rp[i + 1], nodes[i], mesh[i + 1] - mesh[i], envelope[i + 1], power_limit);
  if (n > 1) Solve(v, rp[0], Motion{v.V0, nodes[1].mo.a, v.T0, v.e0}, &nodes[0]);
  return nodes;
}

// Time at every node of a forward pass by the trapezoidal rule of 1/V, from 0 [s].
std::vector<double> PassTimes(const std::vector<double>& mesh, const std::vector<NodePoint>& nodes) {
  std::vector<double> t(mesh.size(), 0.0);
  for (size_t i = 1; i < mesh.size(); ++i)
    t[i] = t[i - 1] + 0.5 * (mesh[i] - mesh[i - 1]) * (1.0 / nodes[i - 1].mo.V + 1.0 / nodes[i].mo.V);
  return t;
}

// The forward pass at full power, or, when that empties the pack, the faster of it and the pass
// under the largest pack-power limit that ends the lap with at least kChargeReserve of the pack.
// Neither strategy wins everywhere: on the 60.8 km course a 25 MJ pack spent at full power and
// then a crawl take 7031 s against 2156 s under one limit, while on a 200 m sprint spending the
// pack first and coasting is the faster (analytic_test, 9.55 s against 10.43 s). The limit is
// found by bisection to 0.1 % of it: the final energy grows as the limit falls, down to limits
// near the ~50 W idle draw, where the lap's time and its idle drain grow without bound.
std::vector<NodePoint> EnergyLimitedPass(const Vehicle& v, const std::vector<RoadPoint>& rp,
                                         const std::vector<double>& mesh,
                                         const std::vector<double>& envelope) {
  const double reserve = kChargeReserve * v.e0;
  std::vector<NodePoint> full = ForwardPass(v, rp, mesh, envelope, v.P_b_max);
  if (full.back().mo.e >= reserve) return full;
  double lo = 0.0, hi = v.P_b_max;
  std::vector<NodePoint> limited;
  while (hi - lo > 1e-3 * hi) {
    const double mid = 0.5 * (lo + hi);
    std::vector<NodePoint> nodes = ForwardPass(v, rp, mesh, envelope, mid);
    if (nodes.back().mo.e >= reserve) {
      lo = mid;
      limited = std::move(nodes);
    } else {
      hi = mid;
    }
  }
  return !limited.empty() && PassTimes(mesh, limited).back() < PassTimes(mesh, full).back() ? limited
                                                                                          : full;
}

// d f / ds at node i by differences (central inside, one-sided at the ends).
double Slope(const std::vector<double>& s, const std::vector<double>& f, int i) {
  const int n = static_cast<int>(s.size());
  if (n < 2) return 0.0;
  const int lo = std::max(0, i - 1), hi = std::min(n - 1, i + 1);
  return (f[hi] - f[lo]) / (s[hi] - s[lo]);
}

// The lap from the nodes: time by the trapezoidal rule, states and controls, the roll and
// vertical rates from the lean and the compression along s (omega_phi = V dphi/ds, eq. 34), the
// controls from the yaw rate and the wheel torque along s (dOmega_z/dt = V dOmega_z/ds, ...).
QssLap Assemble(const std::vector<double>& mesh, const std::vector<NodePoint>& nodes) {
  const int n = static_cast<int>(mesh.size());
  QssLap q;
  q.s = mesh;
  q.V.resize(n);
  q.t = PassTimes(mesh, nodes);
  q.x.resize(n);
  q.u.resize(n);
  std::vector<double> phi(n), z(n), yaw_rate(n), torque(n);
  for (int i = 0; i < n; ++i) {
    const NodePoint& np = nodes[i];
    q.V[i] = np.mo.V;
    phi[i] = np.q[kQPhi];
    z[i] = np.q[kQZ];
    yaw_rate[i] = np.q[kQOmegaZ];
    torque[i] = np.q[kQTauW];
    q.x[i] = StateAt(np.mo, np.q);
  }
  for (int i = 0; i < n; ++i) {
    q.x[i][kOmegaPhi] = q.V[i] * Slope(mesh, phi, i);
    q.x[i][kZdot] = q.V[i] * Slope(mesh, z, i);
    q.u[i] = {q.V[i] * Slope(mesh, yaw_rate, i), q.V[i] * Slope(mesh, torque, i)};
  }
  q.lap_time = q.t.back();
  return q;
}

// The QSS lap through the road points rp at the mesh nodes.
QssLap QssOn(const Vehicle& v, const std::vector<RoadPoint>& rp, const std::vector<double>& mesh) {
  std::vector<double> cap(rp.size());
  for (size_t i = 0; i < rp.size(); ++i) cap[i] = SpeedCap(v, rp[i]);
  return Assemble(mesh, EnergyLimitedPass(v, rp, mesh, BrakingEnvelope(v, rp, mesh, cap)));
}

}  // namespace

double MaxTractionForce(const Vehicle& v, double V, double e, double T) {
  const RoadPoint level{};
  NodePoint np;
  Motion mo{V, 0.0, T, e};
  for (int it = 0; it < 30; ++it) {
    Solve(v, level, mo, &np);
    const double a = MaxAcceleration(v, np, v.P_b_max);
    const bool settled = std::abs(a - mo.a) <= 1e-12 * (1.0 + std::abs(a));
    mo.a = a;
    if (settled) break;
  }
  Solve(v, level, mo, &np);
  return np.q[kQTauW] / np.m.tyre.R_e;
}

QssLap ComputeQss(const Vehicle& v, const RoadTrack& road, const std::vector<double>& mesh) {
  std::vector<RoadPoint> rp(mesh.size());
  for (size_t i = 0; i < mesh.size(); ++i) rp[i] = road.At(mesh[i]);
  return QssOn(v, rp, mesh);
}

double QssChargePrice(const Vehicle& v, const RoadTrack& road, const std::vector<double>& mesh,
                      const QssLap& qss) {
  constexpr double kLess = 0.05;  // share of e0 taken out
  Vehicle less = v;
  less.e0 = (1.0 - kLess) * v.e0;
  return (ComputeQss(less, road, mesh).lap_time - qss.lap_time) / (kLess * v.e0);
}

QssLap ComputeQss(const Vehicle& v, const RoadTrack& road, const std::vector<double>& mesh,
                  const RacingLine& line) {
  const int n = static_cast<int>(mesh.size());
  std::vector<RoadPoint> rp(n);
  std::vector<double> road_kappa(n);
  for (int i = 0; i < n; ++i) {
    rp[i] = road.At(mesh[i]);
    road_kappa[i] = rp[i].kappa;
    rp[i].kappa = line.kappa[i];
    rp[i].dkappa = Slope(mesh, line.kappa, i);
  }
  QssLap q = QssOn(v, rp, mesh);
  for (int i = 1; i < n; ++i) {
    q.x[i][kN] = line.n[i];
    q.x[i][kAlpha] += std::atan(line.dn_ds[i] / (1.0 - line.n[i] * road_kappa[i]));
  }
  return q;
}

double PeriodicQssSpeed(const Vehicle& v, const RoadTrack& road, const std::vector<double>& mesh,
                        bool* settled) {
  constexpr double kAgree = 1e-3;  // [m/s]
  constexpr int kMaxPasses = 20;
  Vehicle from = v;
  *settled = false;
  for (int pass = 0; pass < kMaxPasses && !*settled; ++pass) {
    const double end = ComputeQss(from, road, mesh).V.back();
    *settled = std::abs(end - from.V0) <= kAgree;
    from.V0 = end;
  }
  return from.V0;
}

QssLap ComputeQssFrom(const Vehicle& v, const RoadTrack& road, const std::vector<double>& mesh,
                      const StateVector<double>& start) {
  Vehicle from = v;
  from.V0 = start[kV];
  from.T0 = start[kT];
  from.e0 = start[kE];
  RacingLineOptions line;
  line.start_offset_m = start[kN];
  QssLap q = ComputeQss(from, road, mesh, ComputeRacingLine(road, mesh, v.border_margin, line));
  q.x.front() = start;
  return q;
}

WindowGuess QssWindowGuess(const Vehicle& v, const RoadTrack& road) {
  return [&v, &road](const StateVector<double>& start, const std::vector<double>& mesh,
                     std::vector<StateVector<double>>* x, std::vector<ControlVector<double>>* u) {
    QssLap q = ComputeQssFrom(v, road, mesh, start);
    *x = std::move(q.x);
    *u = std::move(q.u);
  };
}

}  // namespace ttz::lap
