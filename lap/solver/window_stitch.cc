#include "lap/solver/window_stitch.h"

namespace ttz::lap {

void CarrySlowCostatesUpstream(const std::vector<WindowJunction>& junctions,
                               std::vector<StateVector<double>>* lambda) {
  for (const WindowJunction& j : junctions)
    for (int k = 0; k <= j.node; ++k)
      for (int i : {kE, kT}) (*lambda)[k][i] += j.jump[i];
}

}  // namespace ttz::lap
