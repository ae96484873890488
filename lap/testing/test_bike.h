// The motor voltage limit of the lap tests' bike, as a `--set` override: 90 V, the value of
// data/bx15.yaml until session 20, with which the tests' saved reference solutions (lap times,
// iteration counts) were measured. data/bx15.yaml has 80 V since (docs/bike.md); at 80 V the
// tests' uncalibrated 600 A bike rides the voltage limit on fast roads and the indirect solver
// fails two of them (docs/lap_log.md "The reference bike's motor voltage limit of 80 V"). Used by
// Bx15() (problem.h) and by the command-line test whose saved figures depend on it
// (tests/lap_cli_test.cc).
// Likewise the price on rolling: 0, data/bx15.yaml's value until session 43 (the paper's model),
// with which the lap tests' saved figures were measured; data/bx15.yaml has 0.1 since
// (docs/lap_log.md "A price on rolling the bike"). Used by Bx15() and the same command-line test.
#pragma once

namespace ttz::lap::testing {

inline constexpr const char* kTestVoltageMaxSetting = "motor.voltage_max_v=90";
inline constexpr const char* kTestRollPriceSetting = "limits.roll_rate_weight_s2_per_rad2=0";

}  // namespace ttz::lap::testing
