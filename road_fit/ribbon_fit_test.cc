// The road fit on synthetic roads of known geometry (the acceptance figures of the road_fit issue).
#include "road_fit/ribbon_fit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <ostream>

#include "road_fit/road_profile.h"
#include "tests/support/synthetic_road.h"

namespace ttz::road {
namespace {

struct FitErrors {
  double length_error_rel = 0.0;
  double kappa_rms = 0.0, kappa_range = 0.0;  // [1/m]
  double slope_rms_deg = 0.0;
  double width_rms_m = 0.0;
  double banking_rms_deg = 0.0;
};

// Compares the fitted profile with the truth at the truth's nearest point to each sample. On an
// open road the first and last `end_margin_m` are left out: there the fit extrapolates.
FitErrors Compare(const RoadProfile& fit, const testing::TrueRoad& truth, double end_margin_m) {
  FitErrors e;
  double k2 = 0, s2 = 0, w2 = 0, b2 = 0, kmin = 1e9, kmax = -1e9;
  long count = 0;
  for (size_t j = 0; j < fit.s.size(); ++j) {
    const size_t i = truth.Nearest(fit.x[j], fit.y[j]);
    if (!truth.closed && (truth.s[i] < end_margin_m || truth.s[i] > truth.length() - end_margin_m)) continue;
    k2 += std::pow(fit.kappa[j] - truth.kappa[i], 2);
    s2 += std::pow(fit.sigma[j] - truth.sigma[i], 2);
    w2 += std::pow(fit.width[j] - truth.width[i], 2);
    b2 += std::pow(fit.banking[j] - truth.banking[i], 2);
    kmin = std::min(kmin, truth.kappa[i]);
    kmax = std::max(kmax, truth.kappa[i]);
    ++count;
  }
  e.kappa_rms = std::sqrt(k2 / count);
  e.slope_rms_deg = std::sqrt(s2 / count) * 180 / M_PI;
  e.width_rms_m = std::sqrt(w2 / count);
  e.banking_rms_deg = std::sqrt(b2 / count) * 180 / M_PI;
  // A circle has no curvature range: judge its curvature error against the curvature itself.
  e.kappa_range = truth.closed && kmax - kmin < 1e-9 ? std::abs(kmax) : kmax - kmin;
  const double true_length = truth.closed ? truth.length()
                                          : truth.s[truth.Nearest(fit.x.back(), fit.y.back())] -
                                                truth.s[truth.Nearest(fit.x.front(), fit.y.front())];
  e.length_error_rel = fit.length() / true_length - 1.0;
  return e;
}

struct Case {
  testing::RoadSpec (*spec)();
  double noise_sd_m;
};

// How ctest and gtest name a case: "climbing curve, noise 0.3 m", not the struct's bytes.
void PrintTo(const Case& c, std::ostream* os) { *os << c.spec().name << ", noise " << c.noise_sd_m << " m"; }

class SyntheticFit : public ::testing::TestWithParam<Case> {};

TEST_P(SyntheticFit, MeetsTheAccuracyTargets) {
  const testing::RoadSpec spec = GetParam().spec();
  const testing::TrueRoad truth = testing::Integrate(spec);
  testing::SamplingOptions sampling;
  sampling.noise_sd_m = GetParam().noise_sd_m;
  const RoadInput input = testing::SampleBorders(truth, sampling);
  FitOptions options;
  // Without noise there is nothing to smooth: a user would lower the smoothing weight, so do we.
  const bool noisy = GetParam().noise_sd_m > 0;
  if (!noisy) options.smoothing_weight = 1e-3;
  FitSummary summary;
  const Ribbon ribbon = FitRibbon(input, options, &summary);
  const RoadProfile profile = SampleRibbon(ribbon, 1.0);
  const FitErrors e = Compare(profile, truth, 30.0);
  RecordProperty("length_error_rel", std::to_string(e.length_error_rel));
  std::printf("%s, noise %.1f m: %s\n  length error %.4f %%, kappa rms %.2e 1/m (%.2f %% of range), slope rms %.3f deg, "
              "width rms %.3f m, banking rms %.3f deg\n",
              spec.name.c_str(), GetParam().noise_sd_m, summary.BriefReport().c_str(), 100 * e.length_error_rel,
              e.kappa_rms, 100 * e.kappa_rms / e.kappa_range, e.slope_rms_deg, e.width_rms_m, e.banking_rms_deg);
  EXPECT_TRUE(summary.converged) << summary.termination;
  EXPECT_EQ(ribbon.closed, spec.closed);
  // Targets of the issue with 0.3 m noise; without noise ("near exact") ten times tighter, but
  // curvature and length only three times: linear interpolation between 1 m nodes limits the
  // curvature, and the extrapolated ends of an open road the length.
  EXPECT_LT(std::abs(e.length_error_rel), noisy ? 5e-4 : 1.5e-4);
  EXPECT_LT(e.kappa_rms, (noisy ? 0.05 : 0.015) * e.kappa_range);
  EXPECT_LT(e.slope_rms_deg, noisy ? 0.2 : 0.02);
  EXPECT_LT(e.width_rms_m, noisy ? 0.2 : 0.02);
  // Banking from the two borders' elevations: 0.3 m of noise on each, 6-8 m apart, is ~3.5 deg of
  // noise per pair; the fit's smoothing brings it to 0.7-1.2 deg (measured, FitOptions's u_xi).
  EXPECT_LT(e.banking_rms_deg, noisy ? 1.5 : 0.05);
}

INSTANTIATE_TEST_SUITE_P(Roads, SyntheticFit,
                         ::testing::Values(Case{testing::ClimbingCurve, 0.3}, Case{testing::ClothoidSBend, 0.3},
                                           Case{testing::Circle, 0.3}, Case{testing::ClimbingCurve, 0.0},
                                           Case{testing::ClothoidSBend, 0.0}, Case{testing::Circle, 0.0},
                                           Case{testing::BankedClimbingCurve, 0.3},
                                           Case{testing::BankedClimbingCurve, 0.0}));

}  // namespace
}  // namespace ttz::road
