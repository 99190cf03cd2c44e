// The rolling models with real LIGGGHTS: one sphere rolling on a plane under each model, the stability of the viscous
// model at the paper's upper bounds, and tiny pile and oedometer cases with the viscous model. The viscous tests need
// the LIGGGHTS of scripts/build-liggghts.sh (the model is not in stock LIGGGHTS): $DEMSA_LIGGGHTS when it lists the
// model, else the prefix the script prints for this checkout.
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace demsa {
namespace {

namespace fs = std::filesystem;

/// $DEMSA_LIGGGHTS when it has the viscous rolling model, else this checkout's build by scripts/build-liggghts.sh; ""
/// (with the reason in `why`) when neither is there.
std::string patched_liggghts(std::string& why) {
  if (const char* env = std::getenv("DEMSA_LIGGGHTS"); env != nullptr && *env != '\0') {
    const test::CommandResult h = test::run_command({env, "-h"});
    if (h.out.find("viscous") != std::string::npos) return env;
  }
  return test::project_liggghts(why);
}

#define REQUIRE_PATCHED(exe)                     \
  std::string why;                               \
  const std::string exe = patched_liggghts(why); \
  ASSERT_FALSE(exe.empty()) << why

/// The property lines and model words of one rolling model with the same coefficient for every type pair.
struct Rolling {
  std::string model;       ///< cdt, epsd, epsd2, epsd3, viscous
  std::string properties;  ///< fix property/global lines
  std::string options;     ///< after the model words (exactDecay off)
};

Rolling rolling(const std::string& model, double coefficient, const std::string& options = "") {
  const auto pair = [](const std::string& name, double v) {
    std::ostringstream s;
    s << "fix r_" << name << " all property/global " << name << " peratomtypepair 2 " << v << " " << v << " " << v
      << " " << v << "\n";
    return s.str();
  };
  std::string p = model == "viscous" ? pair("coefficientRollingViscosity", coefficient)
                                     : pair("coefficientRollingFriction", coefficient);
  if (model == "epsd" || model == "epsd3") p += pair("coefficientRollingViscousDamping", 0.3);
  if (model == "epsd3") p += "fix r_k all property/global rollingStiffness scalar 2.25\n";
  return {model, p, options};
}

/// The contact setup of every test input: hertz, history, the rolling model; a floor at z = 0.
std::string contact_lines(const Rolling& r, double E) {
  std::ostringstream s;
  s << "fix m1 all property/global youngsModulus peratomtype " << E << " " << E << "\n"
    << "fix m2 all property/global poissonsRatio peratomtype 0.3 0.3\n"
    << "fix m3 all property/global coefficientRestitution peratomtypepair 2 0.4 0.4 0.4 0.4\n"
    << "fix m4 all property/global coefficientFriction peratomtypepair 2 1.0 1.0 1.0 1.0\n"
    << r.properties << "pair_style gran model hertz tangential history rolling_friction " << r.model << " " << r.options
    << "\npair_coeff * *\n"
    // A wall/gran fix takes the model's keywords after its geometry.
    << "fix floor all wall/gran model hertz tangential history rolling_friction " << r.model
    << " primitive type 2 zplane 0.0 " << r.options << "\n";
  return s.str();
}

const char* const k_header =
    "atom_style sphere\natom_modify map array\nboundary f f f\nnewton off\ncommunicate single vel yes\nunits si\n"
    "processors * * 1\n";

/// Runs `input` in `dir` and returns the rows of numbers of `table` (whitespace-separated, '#' lines skipped).
std::vector<std::vector<double>> run_and_read(const std::string& exe, const fs::path& dir, const std::string& input,
                                              const std::string& table) {
  fs::create_directories(dir);
  test::write_file(dir / "in.liggghts", input);
  const test::CommandResult r =
      test::run_command({exe, "-in", "in.liggghts", "-log", "log.liggghts", "-screen", "screen.txt"}, dir);
  EXPECT_EQ(r.exit_code, 0) << test::read_file(dir / "log.liggghts").substr(0, 4000);
  std::vector<std::vector<double>> rows;
  std::istringstream in(fs::exists(dir / table) ? test::read_file(dir / table) : std::string());
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream words(line);
    std::vector<double> row;
    double v = 0;
    while (words >> v) row.push_back(v);
    if (!row.empty()) rows.push_back(row);
  }
  return rows;
}

constexpr double k_radius = 0.005;  // d = 10 mm
constexpr double k_density = 2500;
constexpr double k_g = 9.81;
constexpr double k_speed = 0.5;
constexpr double k_dt = 1e-6;

/// One sphere rolling without slip along x from 0.5 m/s on the floor for 0.2 s; rows: time, vx.
std::vector<std::vector<double>> roll_one_sphere(const std::string& exe, const fs::path& dir, const Rolling& r) {
  std::ostringstream in;
  in << k_header << "region domain block -0.1 0.3 -0.05 0.05 -0.01 0.05 units box\ncreate_box 2 domain\n"
     << "neighbor 0.002 bin\nneigh_modify delay 0\n"
     << contact_lines(r, 1e8) << "timestep " << k_dt << "\nfix gravi all gravity " << k_g << " vector 0 0 -1\n"
     << "create_atoms 1 single 0 0 " << k_radius - 1.3e-6 << " units box\n"
     << "set atom 1 diameter " << 2 * k_radius << " density " << k_density
     << "\n"
     // Rolling without slip along +x: omega_y = v / r.
     << "velocity all set " << k_speed << " 0 0 units box\nset atom 1 omegay " << k_speed / k_radius << "\n"
     << "fix integr all nve/sphere\n"
     << "variable t equal step*dt\nvariable vx equal vx[1]\n"
     << "fix out all print 1000 \"${t} ${vx}\" file roll.txt screen no\n"
     << "thermo 10000\nrun 200000\n";
  return run_and_read(exe, dir, in.str(), "roll.txt");
}

double speed_at(const std::vector<std::vector<double>>& rows, double t) {
  for (const auto& row : rows)
    if (row.size() >= 2 && std::abs(row[0] - t) < 0.5e-3) return row[1];
  ADD_FAILURE() << "no sample at t = " << t;
  return NAN;
}

// The stock models run on Debian's LIGGGHTS (`liggghts` on PATH), as demsa's `cdt`, `epsd`, `epsd2` and `epsd3` cases
// do.
const std::string k_stock = "liggghts";

TEST(RollingModelsReal, CdtSlowsASphereLinearly) {
  const std::string exe = k_stock;
  test::TempDir tmp;
  const auto rows = roll_one_sphere(exe, tmp / "cdt", rolling("cdt", 0.05));
  // Rolling without slip against the torque mu_r m g r: a = -mu_r g / (1 + 2/5) (solid sphere).
  const double a = -0.05 * k_g / 1.4;
  for (const double t : {0.05, 0.1, 0.15, 0.2})
    EXPECT_NEAR(speed_at(rows, t), k_speed + a * t, 0.01 * k_speed) << "t = " << t;
  EXPECT_NEAR(speed_at(rows, 0.2), 0.43, 0.005);
}

TEST(RollingModelsReal, ViscousSlowsASphereExponentially) {
  REQUIRE_PATCHED(exe);
  test::TempDir tmp;
  const double mu_R = 1e-5;  // s*m
  const auto rows = roll_one_sphere(exe, tmp / "viscous", rolling("viscous", mu_R));
  // Torque mu_R m g omega, omega = v / r: m (1 + 2/5) dv/dt = -mu_R m g v / r^2, so v decays by
  // exp(-mu_R g dt / (1.4 r^2)) every dt (0.869 per 0.05 s).
  const double expected = std::exp(-mu_R * k_g * 0.05 / (1.4 * k_radius * k_radius));
  for (const double t : {0.05, 0.1, 0.15}) {
    const double ratio = speed_at(rows, t + 0.05) / speed_at(rows, t);
    EXPECT_NEAR(std::log(ratio), std::log(expected), 0.02 * std::abs(std::log(expected))) << "t = " << t;
  }
}

TEST(RollingModelsReal, EpsdModelsSlowASphereLikeTheirMobilisedTorque) {
  const std::string exe = k_stock;
  test::TempDir tmp;
  // Rolling on, the spring of epsd, epsd2 and epsd3 is at its cap mu_r |F_n| R*: the cdt torque.
  const double at_end = k_speed - 0.05 * k_g / 1.4 * 0.2;
  for (const std::string model : {"epsd", "epsd2", "epsd3"}) {
    const auto rows = roll_one_sphere(exe, tmp / model, rolling(model, 0.05));
    EXPECT_NEAR(speed_at(rows, 0.2), at_end, 0.03 * k_speed) << model;
    EXPECT_LT(speed_at(rows, 0.2), speed_at(rows, 0.1)) << model;
  }
}

/// The smallest particles of set 1 (r = 1 mm), E = 1e9 Pa, dt = 0.15 Rayleigh time: one hits a resting particle
/// obliquely at 3 m/s, another the floor obliquely. Rows: time, rotational KE, translational KE.
std::vector<std::vector<double>> hard_impacts(const std::string& exe, const fs::path& dir, const Rolling& r) {
  const double radius = 1e-3;
  const double E = 1e9, nu = 0.3;
  const double G = E / (2 * (1 + nu));
  const double rayleigh = M_PI * radius * std::sqrt(k_density / G) / (0.1631 * nu + 0.8766);
  std::ostringstream in;
  in << k_header << "region domain block -0.02 0.02 -0.02 0.02 -0.005 0.03 units box\ncreate_box 2 domain\n"
     << "neighbor 0.0005 bin\nneigh_modify delay 0\n"
     << contact_lines(r, E) << "timestep " << 0.15 * rayleigh << "\nfix gravi all gravity " << k_g << " vector 0 0 -1\n"
     << "create_atoms 1 single 0 0 " << radius << " units box\n"
     << "create_atoms 1 single 0.0012 0 0.0032 units box\n"
     << "create_atoms 1 single 0.01 0 0.002 units box\n"
     << "set group all diameter " << 2 * radius << " density " << k_density << "\n"
     << "velocity all set 0 0 0 units box\n"
     << "group hitter id 2\ngroup wallhit id 3\n"
     << "velocity hitter set 0 0 -3 units box\nvelocity wallhit set 2 0 -3 units box\n"
     << "fix integr all nve/sphere\n"
     << "compute rot all erotate/sphere\nvariable t equal step*dt\nvariable erot equal c_rot\n"
     << "variable etr equal ke\n"
     << "thermo_style custom step atoms ke c_rot\nthermo_modify lost ignore norm no\nthermo 1000\n"
     << "fix out all print 10 \"${t} ${erot} ${etr}\" file energy.txt screen no\n"
     << "run 20000\n";
  return run_and_read(exe, dir, in.str(), "energy.txt");
}

TEST(RollingModelsReal, ViscousStaysStableAtThePapersUpperBounds) {
  REQUIRE_PATCHED(exe);
  test::TempDir tmp;
  const double radius = 1e-3;
  const double mass = k_density * 4.0 / 3.0 * M_PI * radius * radius * radius;
  // The translational KE the rotation comes from: the two impacts (3 m/s, and 2 m/s along the floor + 3 m/s down),
  // plus what gravity adds over the drop (a few mm).
  const double ke0 = 0.5 * mass * (9.0 + 13.0) + 3 * mass * k_g * 0.005;
  // The paper's upper bounds 4.5e-6 (particle-particle) and 5e-6 s*m (particle-wall): the larger for both.
  for (const double mu_R : {4.5e-6, 5e-6}) {
    const auto rows = hard_impacts(exe, tmp / ("stable-" + std::to_string(mu_R)), rolling("viscous", mu_R));
    ASSERT_GT(rows.size(), 100u);
    double max_rot = 0;
    for (const auto& row : rows) {
      ASSERT_EQ(row.size(), 3u);
      ASSERT_TRUE(std::isfinite(row[1]) && std::isfinite(row[2]));
      max_rot = std::max(max_rot, row[1]);
    }
    EXPECT_GT(max_rot, 0.0) << "the impacts must spin the particles";
    EXPECT_LE(max_rot, ke0) << "mu_R = " << mu_R;
  }
  // The same impacts with the plain explicit torque: the rotation gains energy it never had (the failure the exact
  // decay removes), so this test can tell the two apart.
  const auto rows = hard_impacts(exe, tmp / "explicit", rolling("viscous", 5e-6, "exactDecay off"));
  double max_rot = 0;
  bool finite = true;
  for (const auto& row : rows) {
    if (row.size() < 3 || !std::isfinite(row[1])) {
      finite = false;
      break;
    }
    max_rot = std::max(max_rot, row[1]);
  }
  EXPECT_TRUE(!finite || max_rot > ke0) << "explicit model B stayed stable: max rotational KE " << max_rot;
}

/// `demsa case` sample 0 of a study in tests/data/cases, run by its run.sh.
void write_and_run(const std::string& study, const fs::path& dir) {
  const test::CommandResult w =
      test::run_demsa({"case", test::data_path("cases/" + study).string(), "--sample", "0", "-o", dir.string()});
  ASSERT_EQ(w.exit_code, 0) << w.out << w.err;
  const test::CommandResult r = test::run_command({(dir / "run.sh").string()}, dir.parent_path());
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err << test::read_file(dir / "screen.txt");
}

TEST(RollingModelsReal, TinyViscousPileAndOedometerRun) {
  REQUIRE_PATCHED(exe);
  test::TempDir tmp;
  // demsa finds the same build (its cache, or $DEMSA_LIGGGHTS) for the viscous model.
  write_and_run("tiny_pile_viscous.toml", tmp / "pile");
  EXPECT_NE(test::read_file(tmp / "pile" / "contact.liggghts").find("coefficientRollingViscosity"), std::string::npos);
  EXPECT_NE(test::read_file(tmp / "pile" / "in.liggghts").find("rolling_friction viscous"), std::string::npos);
  EXPECT_TRUE(fs::exists(tmp / "pile" / "pile_final.dump"));
  write_and_run("tiny_oedometer_viscous.toml", tmp / "oedometer");
  EXPECT_TRUE(fs::exists(tmp / "oedometer" / "plate_states.txt"));
}

TEST(RollingModelsReal, TinyViscousTrialStepOedometerDrivesThePatchedLibrary) {
  REQUIRE_PATCHED(exe);
  test::TempDir tmp;
  // The trial-step plate runs inside demsa, which loads libliggghts.so.3 at run time: run.sh puts the patched build's
  // lib/ on LD_LIBRARY_PATH, and Debian's library would stop at `rolling_friction viscous`.
  write_and_run("tiny_oedometer_trial_viscous.toml", tmp / "trial");
  // The folder exported is a build of scripts/build-liggghts.sh (its marker file beside lib/): the one the locator
  // chose, which need not be `exe` when the cache holds builds of several recipes.
  const std::string run_sh = test::read_file(tmp / "trial" / "run.sh");
  const std::string key = "export LD_LIBRARY_PATH='";
  const std::size_t at = run_sh.find(key);
  ASSERT_NE(at, std::string::npos) << run_sh;
  const std::size_t end = run_sh.find('\'', at + key.size());
  ASSERT_NE(end, std::string::npos) << run_sh;
  const fs::path lib = run_sh.substr(at + key.size(), end - at - key.size());
  EXPECT_TRUE(fs::exists(lib / "libliggghts.so.3")) << lib;
  EXPECT_TRUE(fs::exists(lib.parent_path() / "demsa-liggghts.txt")) << lib;
  EXPECT_NE(test::read_file(tmp / "trial" / "log.liggghts").find("rolling_friction viscous"), std::string::npos);
  const std::string states = test::read_file(tmp / "trial" / "plate_states.txt");
  EXPECT_NE(states.find("\n100 "), std::string::npos) << states;
  EXPECT_NE(states.find("\n400 "), std::string::npos) << states;
}

}  // namespace
}  // namespace demsa
