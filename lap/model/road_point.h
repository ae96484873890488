// The road at one arc length s, in the model's frame (state.h): the curvatures of eq. 12, their
// derivatives along s (which enter the time derivatives of Omega_x, Omega_y and v_z in eq. 13-15),
// the slope, the banking and the width. Built by lap/road_track.h from road.h5.
#pragma once

namespace ttz::lap {

struct RoadPoint {
  double s = 0.0;       // arc length [m]
  double kappa = 0.0;   // curvature in the road plane, right turn positive [1/m] (eq. 12)
  double nu = 0.0;      // normal curvature [1/m] (eq. 12; sigma' on a road without banking)
  double tau = 0.0;     // torsion [1/m] (eq. 12)
  double dkappa = 0.0, dnu = 0.0, dtau = 0.0;  // d/ds of the three [1/m^2]
  double sigma = 0.0;   // slope, uphill positive [rad]
  double xi = 0.0;      // banking, positive when the left border is the higher [rad] (eq. 2)
  double width = 0.0;   // r_w, border to border [m]
};

}  // namespace ttz::lap
