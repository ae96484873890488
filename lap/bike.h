// The motorcycle's parameters (the paper's Table A1 plus the power train of section 2.3), read from
// a bike.yaml file, and the figures derived from them (total mass, battery pack, equivalent motor).
//
// Everything is in SI units; temperatures are in degrees Celsius (an SI derived unit; only
// differences of temperature enter the model). The C++ members carry the paper's symbols with the
// unit in a comment; the YAML keys carry the unit in their names (see docs/bike.md and
// data/bx15.yaml). The model (lap/model/) reads these structs only through the functions below
// and never does I/O.
#pragma once

#include <string>
#include <vector>

namespace ttz::lap {

// Mono-wheel chassis and rider (section 2.2, Table A1).
struct ChassisParams {
  double base_mass;  // bike + rider without motors and battery pack [kg]; M is derived (TotalMass)
  double h;          // height of the centre of mass above the ground, upright [m]
  double I_xx;       // roll moment of inertia about the centre of mass [kg m^2]
  double I_yy;       // pitch moment of inertia about the centre of mass [kg m^2] (eq. 14)
  double I_zz;       // yaw moment of inertia about the centre of mass [kg m^2] (eq. 14)
  double I_gy;       // gyroscopic inertia 2 I_wy + gamma_c I_ey [kg m^2] (eq. 14)
  double I_wy;       // spin inertia of the wheel in the spin equation [kg m^2] (eq. 16)
};

// Linear tyre with adherence ellipse and toroidal cross-section (eq. 18-20).
struct TyreParams {
  double r;        // wheel radius (crown of the tyre to the wheel axis) [m]
  double r_t;      // radius of the tyre's toroidal cross-section [m]
  double K_kappa;  // longitudinal slip stiffness F_x / (N kappa_w) [1]
  double K_beta;   // sideslip stiffness F_y / (N beta) [1/rad]
  double K_phi;    // camber (roll) stiffness F_y / (N phi) [1/rad]
  double K_s;      // radial stiffness [N/m]
  double K_c;      // radial damping [N s/m]
  double mu_x;     // longitudinal adherence [1]
  double mu_y;     // lateral adherence [1]
  double mu_r;     // rolling-resistance coefficient [1] (eq. 18; see tyre.h for its unit)
};

// Aerodynamics (eq. 21).
struct AeroParams {
  double rho;  // air density [kg/m^3]
  double C_d;  // drag area C_d A [m^2] (Table A1 gives it in m^2)
  double C_l;  // lift area C_l A [m^2], lift positive upwards
};

// One brushed DC motor (eq. 24-29); `count` identical motors work in parallel (EquivalentMotor).
struct MotorParams {
  int count;             // number of motors [1]
  double mass;           // mass of one motor [kg]
  double R_m0;           // armature resistance at T_0 [ohm]
  double sigma_R;        // dR_m/dT [ohm/K]
  double k_V0;           // back-e.m.f. constant at T_0 [V s/rad]
  double k_tau0;         // torque constant at T_0 [N m/A]
  double sigma_m;        // -dk_V/dT = -dk_tau/dT [V s/(rad K)]
  double i_m0;           // current offset (no-load current) [A]
  double current_max;    // current limit of one motor [A] (eq. 39e)
  double voltage_max;    // motor voltage limit V_max [V] (section 5)
  double T_0;            // reference temperature of R_m0, k_V0, k_tau0 [degC]
  double C;              // thermal capacity of one motor [J/K] (eq. 27)
  double q_0;            // heat conduction of one motor at standstill [W/K] (eq. 29)
  double q_1;            // heat conduction of one motor at speed V_1 [W/K] (eq. 29)
  double V_1;            // speed of q_1 [m/s] (eq. 29)
};

// Motor controller, a DC-DC converter of constant efficiency (eq. 23).
struct ControllerParams {
  double eta_mc;  // efficiency [1]
};

// Battery pack of `cells_series` x `cells_parallel` cells (eq. 22, 33).
struct BatteryParams {
  int cells_series;         // cells in series [1]
  int cells_parallel;       // strings in parallel [1]
  double cell_ocv_full;     // open-circuit voltage of a cell, full [V]
  double cell_ocv_empty;    // open-circuit voltage of a cell, empty [V]
  double cell_resistance;   // internal resistance of a cell [ohm]
  double cell_energy;       // energy stored in a full cell [J]
  double energy_density;    // pack energy per pack mass [J/kg]
  double power_max;         // pack power limit P_b^max on V_bn i_b [W] (eq. 39f)
};

// Final drive (eq. 31).
struct DriveParams {
  double gamma_c;  // gear ratio motor speed / wheel speed [1]
  double eta_c;    // drive efficiency [1]
};

// Initial state x(s_0) (section 3: the initial state is fixed).
struct InitialParams {
  double V;                  // speed [m/s]
  double T;                  // motor temperature [degC]
  double state_of_charge;    // e(0) / e_i [1]
};

struct EnvironmentParams {
  double g;      // gravitational acceleration [m/s^2]
  double T_ext;  // ambient temperature [degC] (eq. 28)
};

// Path-constraint limits (eq. 39a-c) and the brake bound of the control set.
struct LimitParams {
  double omega_phi_max;   // roll-rate limit [rad/s] (eq. 39b)
  double Omega_z_max;     // yaw-rate limit [rad/s] (eq. 39c)
  double border_margin;   // keep the contact point this far inside each road border [m] (eq. 39a)
  double brake_torque_max;  // largest braking torque of the brakes at the wheel [N m]; bounds the
                            // control tau_w from below (the paper's min over u in U, eq. 38a)
  double yaw_accel_weight;    // c_y [s^4/rad^2], c_t [s^3/(N m)^2] and c_r [s^2/rad^2]: the rider's
  double torque_rate_weight;  // effort, the cost int 1 + c_y (dOmega_z/dt)^2 + c_t (dtau_w/dt)^2
  double roll_rate_weight;    // + c_r omega_phi^2 dt (cost.h)
};

struct BikeParams {
  ChassisParams chassis;
  TyreParams tyre;
  AeroParams aero;
  MotorParams motor;
  ControllerParams controller;
  BatteryParams battery;
  DriveParams drive;
  InitialParams initial;
  EnvironmentParams environment;
  LimitParams limits;
};

// ---- Derived figures ------------------------------------------------------------------------

// Battery pack figures (eq. 22).
struct PackFigures {
  double V_bn1;   // open-circuit voltage, full = series * cell OCV full [V]
  double V_bn0;   // open-circuit voltage, empty = series * cell OCV empty [V]
  double R_b;     // internal resistance = series * R_cell / parallel [ohm]
  double e_i;     // energy of the full pack = series * parallel * cell energy [J]
  double mass;    // pack mass = e_i / energy density [kg]
};
PackFigures Pack(const BikeParams& p);

// Total mass M = base + motors * motor mass + pack mass [kg] (Table A1: 290 kg for the BX-15).
double TotalMass(const BikeParams& p);

// The `count` motors, which share one shaft and one controller output, as one equivalent motor.
// n identical motors in parallel see the same voltage V_mm and speed omega_m; each carries i/n:
//   V_mm = (i/n) R_m + k_V omega_m   ->  R_m,eq = R_m / n (and sigma_R,eq = sigma_R / n)
//   tau_e = n k_tau f+(i/n - i_m0)   =  k_tau f+(i - n i_m0)  ->  i_m0,eq = n i_m0
// so k_V and k_tau are unchanged, the current limit is n times one motor's, and the n motors at
// one common temperature (the paper balances them) add their thermal capacities and conductions:
//   n C dT/dt = Q_in - n q (T - T_ext)   ->  C_eq = n C, q_eq = n q.
struct EquivalentMotor {
  double R_m0, sigma_R;        // [ohm], [ohm/K]
  double k_V0, k_tau0, sigma_m;  // [V s/rad], [N m/A], [V s/(rad K)]
  double i_m0;                 // [A]
  double current_max;          // [A]
  double voltage_max;          // [V] (parallel motors: same voltage)
  double T_0;                  // [degC]
  double C;                    // [J/K]
  double q_0, q_1, V_1;        // [W/K], [W/K], [m/s]
};
EquivalentMotor MotorsInParallel(const BikeParams& p);

// Initial battery energy e(0) = state_of_charge * e_i [J].
double InitialEnergy(const BikeParams& p);

// ---- bike.yaml ------------------------------------------------------------------------------

// Reads a bike.yaml. Every key is required; unknown, missing, mistyped or non-physical keys throw
// ttz::InputError whose `where` is "<file>:<line>: key 'section.key'". `overrides` are
// "section.key=value" strings applied before validation (an unknown key path throws an
// InputError naming the override).
BikeParams LoadBike(const std::string& yaml_path, const std::vector<std::string>& overrides = {});

// The same, from YAML text; `name` stands for the file in error messages.
BikeParams ParseBike(const std::string& yaml_text, const std::string& name,
                     const std::vector<std::string>& overrides = {});

// The parameters as bike.yaml text in the layout LoadBike reads; parsing it back gives identical
// parameters (doubles are written with enough digits to round-trip exactly). Derived figures
// are added as comments.
std::string BikeToYaml(const BikeParams& p);

// Every key path ("section.key") that bike.yaml must hold, in file order.
std::vector<std::string> BikeKeys();
// Those of them that hold a real number (not the integer counts of motors and cells), in file
// order, and the value of one of them in `p` (std::invalid_argument for any other path).
std::vector<std::string> RealBikeKeys();
double& RealBikeValue(BikeParams& p, const std::string& path);

}  // namespace ttz::lap
