#include "lap/solver/collocation.h"

#include <stdexcept>

namespace ttz::lap {

ButcherTableau ImplicitMidpoint() { return {"midpoint", {0.5}, {1.0}, {{0.5}}, 2}; }

ButcherTableau RadauIIA(int stages) {
  if (stages == 2)
    return {"radau2", {1.0 / 3.0, 1.0}, {0.75, 0.25}, {{5.0 / 12.0, -1.0 / 12.0}, {0.75, 0.25}}, 3};
  if (stages != 3) throw std::invalid_argument("RadauIIA: 2 or 3 stages, not " + std::to_string(stages));
  const double r = std::sqrt(6.0);
  const std::vector<double> b = {(16.0 - r) / 36.0, (16.0 + r) / 36.0, 1.0 / 9.0};
  return {"radau3",
          {(4.0 - r) / 10.0, (4.0 + r) / 10.0, 1.0},
          b,
          {{(88.0 - 7.0 * r) / 360.0, (296.0 - 169.0 * r) / 1800.0, (-2.0 + 3.0 * r) / 225.0},
           {(296.0 + 169.0 * r) / 1800.0, (88.0 + 7.0 * r) / 360.0, (-2.0 - 3.0 * r) / 225.0},
           b},
          5};
}

ButcherTableau TableauByName(const std::string& name) {
  if (name == "midpoint") return ImplicitMidpoint();
  if (name == "radau2") return RadauIIA(2);
  if (name == "radau3") return RadauIIA(3);
  throw std::invalid_argument("unknown collocation scheme '" + name +
                              "' (expected midpoint, radau2 or radau3)");
}

}  // namespace ttz::lap
