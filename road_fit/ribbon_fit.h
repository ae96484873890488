// Fitting the ribbon of eq. 4-8 to measured road points by Ceres least squares.
#pragma once

#include <string>
#include <vector>

#include "road_fit/road_input.h"
#include "road_fit/ribbon.h"

namespace ttz::road {

enum class Topology { kAuto, kClosed, kOpen };

struct FitOptions {
  double ds_m = 1.0;                 // node spacing along the road [m]
  double smoothing_weight = 1.0;     // w_u of eq. 4a, multiplying the normalised U(u) (eq. 6b)
  // Reference control magnitudes normalising U(u): u_theta [1/m^2], u_sigma [1/m^2], u_w [1], u_s [1],
  // u_xi [1/m^2]. For u_xi, on the synthetic roads of ribbon_fit_test.cc with 0.3 m noise, 1e-4 held
  // the banking of a banked curve 1.6 deg off (too smooth) and 1e-3 let noise through (1.0-1.4 deg
  // on every road); 3e-4 gave 0.7-1.2 deg.
  std::array<double, kNumRibbonControls> control_reference = {1e-3, 1e-4, 1e-1, 1e-2, 3e-4};
  double sigma_lateral_m = 0.5;      // sigma_e of eq. 6a across the road [m]
  double sigma_vertical_m = 1.0;     // sigma_e of eq. 6a in elevation [m]
  double sigma_along_m = 2.0;        // sigma_e of eq. 6a along the road [m] (see BorderDistance)
  double sigma_width_m = 0.5;        // for measured widths of centre-line inputs [m]
  double sigma_banking_rad = 0.01;   // for measured bankings of centre-line inputs [rad]
  // Collocation defect that counts as one unit of residual, per metre of road: x, y, z [m/m],
  // theta, sigma [rad/m], theta-hat, sigma-hat [1/m per m], r_w [m/m], s [m/m], xi [rad/m],
  // xi-hat [1/m per m].
  // Tighter tolerances square into the normal equations' condition number and slow the solver
  // (measured on 5 km of the TT course: 100x tighter took 5x the iterations); the defects reached
  // are about 1 % of these.
  RibbonScales defect_tolerance = {1e-3, 1e-3, 1e-3, 1e-4, 1e-4, 1e-5, 1e-5, 1e-3, 1e-3, 1e-4, 1e-5};
  // Hold the banking at zero (the paper's xi = 0) even when the input carries it.
  bool level = false;
  Topology topology = Topology::kAuto;
  // A circuit is taken as closed (kAuto) when its ends are closer than this [m].
  double closure_gap_m = 30.0;
  // kClosed bridges a gap between the ends up to this (with a warning beyond closure_gap_m) [m];
  // beyond it the input is not a circuit, and FitRibbon throws InputError: a Spa centre line cut
  // at 1.5 km, its ends 682 m apart, had been closed by a made-up straight (session 53).
  double max_closing_gap_m = 300.0;
  bool robust = false;               // Cauchy loss on the point distances (outliers)
  double robust_scale = 3.0;         // in units of sigma_e
  int projection_passes = 3;         // re-estimations of each point's abscissa (outer loop)
  double first_pass_coarsening = 4;  // the first pass uses nodes this many times ds apart
  int max_iterations = 200;          // Ceres iterations per pass
  int num_threads = 2;
};

// The fitted nodes: states at nodes 0..N (zeta_k = k h), controls on intervals 0..N-1.
struct Ribbon {
  double h = 1.0;  // node spacing in zeta [m]
  bool closed = false;
  std::vector<std::array<double, kNumRibbonStates>> x;
  std::vector<std::array<double, kNumRibbonControls>> u;
  double length() const { return x.back()[kS] - x.front()[kS]; }
};

// Sets the controls that reproduce the states' rate and width changes between nodes (forward
// differences of theta-hat, sigma-hat, r_w and xi-hat over h; u_s = 0): the controls of a guess built from
// states alone.
void SetControlsFromStates(Ribbon* ribbon);

// Where each measured point sits on the ribbon after the fit and how far it is from it.
struct PointResidual {
  long line = 0;            // input line of the point
  Side side = Side::kCentre;
  double s_m = 0.0;         // abscissa of its projection on the ribbon
  double lateral_m = 0.0;   // signed, positive when the point is left of the fitted border/centre
  double vertical_m = 0.0;  // point minus ribbon elevation
  double along_m = 0.0;     // point ahead of its projection (small once the fit has converged)
};

struct FitSummary {
  bool converged = false;     // every pass ended in Ceres CONVERGENCE and the defects are small
  int iterations = 0;         // Ceres iterations, all passes
  int passes = 0;
  double solve_seconds = 0.0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  double max_defect_position_m = 0.0;  // largest collocation defect of x, y, z (eq. 8d)
  double max_defect_angle_rad = 0.0;   // largest collocation defect of theta, sigma (eq. 8a), xi
  double rms_distance_m = 0.0;  // of the 3-D point-to-ribbon distances
  double max_distance_m = 0.0;
  long max_distance_line = 0;
  std::string termination;      // Ceres' message of the last pass
  std::vector<PointResidual> residuals;
  std::string BriefReport() const;
};

// Fits the ribbon to `input` (local metres). Throws InputError when the points cannot make a
// road (e.g. too short for the node spacing).
Ribbon FitRibbon(const RoadInput& input, const FitOptions& options, FitSummary* summary);

}  // namespace ttz::road
