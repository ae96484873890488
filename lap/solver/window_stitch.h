// Stitching the indirect solver's first step, solved window by window (IndirectOptions::window_m,
// indirect.cc), into one guess for the whole road.
#pragma once

#include <vector>

#include "lap/model/state.h"

namespace ttz::lap {

// Where a window starts (its first node on the whole road's mesh, which keeps the previous
// window's costates: indirect.cc) and the jump of the costates there: the window's own costates at
// that node less the previous window's.
struct WindowJunction {
  int node = 0;
  StateVector<double> jump{};
};

// The costates of the charge e and of the motor temperature T hardly change along the road
// (lambda' = -H_x is small for both): each holds the price of its state over the rest of the lap,
// which a window with a free end prices at zero at its end. So each window's lambda_e and lambda_T
// miss what the road after it adds, and the stitched costates jump at every window's start. This
// adds each junction's jump in lambda_e and lambda_T to its node and every node upstream of it,
// which makes them continuous and priced over the whole road; the other costates are left as they
// are (their windows' free ends are cut off with the overlap). Measured on the whole TT course
// (docs/lap_log.md "The banded LU, and the charge's price across the windows"): the largest residuals
// of the stitched guess were those jumps, and the whole road's first step took 238 iterations
// instead of 336 with them carried (190 with the junction's costates from the previous window).
void CarrySlowCostatesUpstream(const std::vector<WindowJunction>& junctions,
                               std::vector<StateVector<double>>* lambda);

}  // namespace ttz::lap
