// Calibration on metamodels: recovering known parameters, bounds, and bad options.
#include "sobol/calibration.hpp"
#include "sobol/design.hpp"
#include "sobol/error.hpp"
#include "sobol/metamodel.hpp"

#include <gtest/gtest.h>

namespace demsa::sobol {
namespace {

struct Models {
  std::unique_ptr<Metamodel> f, g;
};

/// f = 1 + 2u1 + u2², g = u1 - u2 + u1 u2, both exact for a quadratic RSM.
Models fitted() {
  const Eigen::MatrixXd x = latin_hypercube(30, 2, 1);
  Eigen::VectorXd f(30), g(30);
  for (int i = 0; i < 30; ++i) {
    f(i) = 1 + 2 * x(i, 0) + x(i, 1) * x(i, 1);
    g(i) = x(i, 0) - x(i, 1) + x(i, 0) * x(i, 1);
  }
  Models m{make_metamodel("rsm2"), make_metamodel("rsm2")};
  m.f->fit(x, f);
  m.g->fit(x, g);
  return m;
}

TEST(Calibration, RecoversKnownParameters) {
  const Models m = fitted();
  const double u1 = 0.3, u2 = 0.8;
  std::vector<CalibrationTarget> targets{{"f", m.f.get(), 1 + 2 * u1 + u2 * u2, 1.0, 1.0},
                                         {"g", m.g.get(), u1 - u2 + u1 * u2, 1.0, 1.0}};
  for (const GlobalAlgorithm global : {GlobalAlgorithm::direct_l, GlobalAlgorithm::crs2}) {
    CalibrationOptions o;
    o.global = global;
    o.seed = 3;
    const CalibrationResult r = calibrate(targets, o);
    ASSERT_EQ(r.x.size(), 2u);
    EXPECT_NEAR(r.x[0], u1, 1e-4) << to_string(global);
    EXPECT_NEAR(r.x[1], u2, 1e-4);
    EXPECT_LT(r.misfit, 1e-10);
    EXPECT_LE(r.misfit, r.global_misfit);
    EXPECT_NEAR(r.predictions[0], targets[0].value, 1e-5);
    EXPECT_EQ(r.names[1], "g");
    EXPECT_EQ(r.seed, 3u);
  }
}

TEST(Calibration, StaysInsideTheBox) {
  const Models m = fitted();
  // The unconstrained optimum of f alone at value 1 is u1 = 0, u2 = 0; the box keeps u1 >= 0.5.
  std::vector<CalibrationTarget> targets{{"f", m.f.get(), 1.0, 1.0, 1.0}};
  CalibrationOptions o;
  o.lower = {0.5, 0.0};
  o.upper = {1.0, 1.0};
  const CalibrationResult r = calibrate(targets, o);
  EXPECT_NEAR(r.x[0], 0.5, 1e-6);
  EXPECT_NEAR(r.x[1], 0.0, 1e-3);
  EXPECT_NEAR(r.misfit, 1.0, 1e-5);  // (f(0.5, 0) - 1)² = 1
}

TEST(CalibrationErrors, BadTargetsAndOptions) {
  const Models m = fitted();
  EXPECT_THROW(calibrate({}, CalibrationOptions{}), InputError);
  auto unfitted = make_metamodel("rsm2");
  EXPECT_THROW(calibrate({{"f", unfitted.get(), 1.0, 1.0, 1.0}}, CalibrationOptions{}), InputError);
  EXPECT_THROW(calibrate({{"f", m.f.get(), 1.0, -1.0, 1.0}}, CalibrationOptions{}), InputError);
  EXPECT_THROW(calibrate({{"f", m.f.get(), 1.0, 1.0, 0.0}}, CalibrationOptions{}), InputError);
  CalibrationOptions o;
  o.lower = {0.6, 0.0};
  o.upper = {0.5, 1.0};
  try {
    calibrate({{"f", m.f.get(), 1.0, 1.0, 1.0}}, o);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("lower (0.6) must be less than upper (0.5)"), std::string::npos);
  }
  try {
    global_algorithm_from_string("pso");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("valid: direct-l, crs2, isres, mlsl-lds, none"), std::string::npos);
  }
  EXPECT_THROW(local_algorithm_from_string("lbfgs"), InputError);
}

}  // namespace
}  // namespace demsa::sobol
