// YADE backend on two small in-place packings (40 spheres): exact cell deformation despite
// YADE's one-step velGrad lag, consolidation to RveInit's stress, lost contacts, checkpoint,
// the stiffness estimate against the measured constrained modulus, and the velGrad left
// pending after a burst (its mean rate).
#include <gtest/gtest.h>

#include <set>
#include <string>

// The tests of this file, by name: a build without the YADE backend registers the same names,
// each skipped, so that the test list is the same on every machine (and CTest reports them
// skipped, not passed); YadeBackendTestList keeps the list equal to the tests.
#define MPMDEM_YADE_BACKEND_TESTS(X)             \
  X(InitialStateIsConsolidatedToRveInitPressure) \
  X(StiffnessBoundsMeasuredConstrainedModulus)   \
  X(CellTransformationEqualsProductOfIncrements) \
  X(RateRuleTakesTheUpdatesDtOverTheDemStep)     \
  X(ThinCellIsTiledAndStaysExact)                \
  X(RestoreReproducesStressesAfterCheckpoint)    \
  X(LostContactsGiveZeroStressAndFlagNeverNaN)

#ifdef MPMDEM_HAVE_YADE
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <random>

#include "backends/yade_backend.hpp"
#include "coupling_schema.hpp"

namespace {

using namespace mpmdem;
using protocol::RveReply;
using protocol::RveRequest;
using Mat = std::array<double, 9>;

constexpr double kP0 = 1.0e4;  // consolidation pressure [Pa]

Mat mul(const Mat& a, const Mat& b) {
  Mat c{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) c[3 * i + j] += a[3 * i + k] * b[3 * k + j];
  return c;
}

class YadeBackend : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    cfg_ = std::make_unique<config::Config>(config::Config::from_string(
        "config_version: 1\ncoupling:\n  backend: yade\n  yade:\n    inline_spheres: 40\n"
        "    ns_rule: fixed\n    ns: 10\n",
        coupling_schema(), "<test>", "coupling"));
    dem::BackendContext ctx;
    ctx.n_rve = 2;
    ctx.first_rve = 7;
    ctx.run_dir = std::filesystem::temp_directory_path();
    backend_ = dem::make_yade_backend(*cfg_, ctx);
    backend_->setup(ctx);
    protocol::RveInit init[2] = {};
    for (int k = 0; k < 2; ++k) {
      init[k].stress[0] = init[k].stress[4] = init[k].stress[8] = -kP0;
      init[k].point = ctx.first_rve + static_cast<std::uint64_t>(k);  // the packing's seed
    }
    backend_->initialise(init, init_reply_);
  }
  static void TearDownTestSuite() { backend_.reset(); }

  // One step: RVE 0 gets dF0, RVE 1 gets dF1 (or a query when dF1 is null).
  static void step(const Mat& dF0, const Mat* dF1, RveReply* reply, std::int64_t n = 1,
                   double dt = 0.0) {
    RveRequest req[2] = {};
    for (int i = 0; i < 9; ++i) {
      req[0].dF[i] = dF0[i];
      req[1].dF[i] = dF1 ? (*dF1)[i] : 0.0;
    }
    req[0].dt = req[1].dt = dt;
    req[1].flags = dF1 ? 0u : protocol::kFlagQueryOnly;
    protocol::ControlHeader h{};
    h.step = n;
    backend_->step(h, req, reply);
  }

  // Cell transformation of local RVE k since its preparation, from mpmdem_rve.
  static Mat trsf(int k) {
    PyObject* mod = PyImport_ImportModule("mpmdem_rve");
    PyObject* sets = PyObject_GetAttrString(mod, "_sets");
    PyObject* t = PyObject_CallMethod(PyList_GetItem(sets, 0), "trsf", "i", k);
    Mat m{};
    for (int i = 0; i < 9; ++i) m[i] = PyFloat_AsDouble(PyList_GetItem(t, i));
    Py_DECREF(t);
    Py_DECREF(sets);
    Py_DECREF(mod);
    return m;
  }

  // Measured constrained modulus of local RVE k along `axis` (mpmdem_rve.probe_modulus: two
  // copies of the scene get dF = I -+ eps e_axis e_axis over ns substeps).
  static double probe_modulus(int k, int axis, int ns, double eps = 1e-5) {
    PyObject* mod = PyImport_ImportModule("mpmdem_rve");
    PyObject* sets = PyObject_GetAttrString(mod, "_sets");
    PyObject* m =
        PyObject_CallMethod(PyList_GetItem(sets, 0), "probe_modulus", "idii", k, eps, ns, axis);
    const double v = m ? PyFloat_AsDouble(m) : std::nan("");
    Py_XDECREF(m);
    Py_DECREF(sets);
    Py_DECREF(mod);
    return v;
  }

  static inline std::unique_ptr<config::Config> cfg_;
  static inline std::unique_ptr<dem::RveBackend> backend_;
  static inline RveReply init_reply_[2];
};

const Mat kI = {1, 0, 0, 0, 1, 0, 0, 0, 1};

TEST_F(YadeBackend, InitialStateIsConsolidatedToRveInitPressure) {
  for (const RveReply& r : init_reply_) {
    const double p = (r.stress[0] + r.stress[4] + r.stress[8]) / 3.0;
    EXPECT_NEAR(p, -kP0, 0.02 * kP0);  // compression is negative
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) EXPECT_EQ(r.stress[3 * i + j], r.stress[3 * j + i]);
    EXPECT_EQ(r.status, 0);
    EXPECT_GT(r.stiffness, 0.0);
    // Outputs not requested (ctx.outputs == 0) are exactly zero.
    EXPECT_EQ(r.porosity, 0.0);
    EXPECT_EQ(r.coordination, 0.0);
    EXPECT_EQ(r.unbalanced_force, 0.0);
    EXPECT_EQ(r.rotation[0], 0.0);
  }
}

// The stiffness in the replies is for the MPM's critical time step: it must not be below the
// RVE's incremental constrained modulus d sigma_ii / d eps_ii, neither at the coupling rate
// (ns = 10 substeps for 1e-5: nearly affine, the stiffest response) nor quasi-statically
// (ns = 400: several wave crossings), and should not be a useless bound (< 10x). Runs on the
// freshly consolidated RVE (defined before the tests that deform it): the probes work on
// copies and leave the RVE untouched.
TEST_F(YadeBackend, StiffnessBoundsMeasuredConstrainedModulus) {
  RveRequest req[2] = {};
  req[0].flags = req[1].flags = protocol::kFlagQueryOnly;
  RveReply reply[2];
  protocol::ControlHeader h{};
  backend_->step(h, req, reply);
  ASSERT_EQ(reply[0].status, 0);
  const double M = reply[0].stiffness;
  double fast_max = 0.0, slow_max = 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    const double fast = probe_modulus(0, axis, 10);
    const double slow = probe_modulus(0, axis, 400);
    ASSERT_TRUE(std::isfinite(fast) && std::isfinite(slow)) << "probe failed, axis " << axis;
    EXPECT_GT(slow, 0.0) << "axis " << axis;
    EXPECT_GE(M, fast) << "axis " << axis << ": stiffness below the response at ns = 10";
    EXPECT_GE(M, slow) << "axis " << axis << ": stiffness below the quasi-static response";
    fast_max = std::max(fast_max, fast);
    slow_max = std::max(slow_max, slow);
  }
  EXPECT_LT(M, 10.0 * slow_max) << "bound " << M << " vs quasi-static modulus " << slow_max;
  std::printf("stiffness %.4g Pa; measured max over axes: ns=10 %.4g, ns=400 %.4g\n", M, fast_max,
              slow_max);
}

TEST_F(YadeBackend, CellTransformationEqualsProductOfIncrements) {
  std::mt19937 gen(42);
  std::normal_distribution<double> n01(0.0, 1.0);
  Mat product = trsf(0);
  RveReply reply[2];
  for (int s = 0; s < 12; ++s) {
    Mat dF = kI;
    for (double& v : dF) v += 2e-4 * n01(gen);  // stretch, shear and rotation
    const double th = 1e-3 * n01(gen);          // plus an explicit rotation about z
    const Mat R = {std::cos(th), -std::sin(th), 0, std::sin(th), std::cos(th), 0, 0, 0, 1};
    dF = mul(R, dF);
    product = mul(dF, product);
    step(dF, nullptr, reply, s);
    EXPECT_EQ(reply[0].n_substeps, 10);
    const Mat t = trsf(0);
    for (int i = 0; i < 9; ++i) ASSERT_NEAR(t[i], product[i], 1e-10) << "step " << s;
  }
  for (int i = 0; i < 9; ++i) EXPECT_TRUE(std::isfinite(reply[0].stress[i]));
  EXPECT_EQ(reply[1].n_substeps, 0);  // query only
  // Then increments that alternate in sign: the velGrad left pending after each burst (for
  // the next burst's first substep) is that burst's mean rate (dF - I)/(ns dt), whatever came
  // before, so pending / (dF - I) is the same 1/(ns dt) every step. The old rule (the last
  // exact correction stays pending) made the rate grow without bound at ns = 2
  // (docs/dem_backend.md, "velGrad lag at ns = 2").
  double ratio0 = 0.0;
  for (int s = 0; s < 8; ++s) {
    Mat dF = kI;
    dF[8] += (s % 2 ? 1e-5 : -1e-5);
    product = mul(dF, product);
    step(dF, nullptr, reply, 100 + s);
    const Mat t = trsf(0);
    for (int i = 0; i < 9; ++i) ASSERT_NEAR(t[i], product[i], 1e-10) << "step " << s;
    PyObject* mod = PyImport_ImportModule("mpmdem_rve");
    PyObject* sets = PyObject_GetAttrString(mod, "_sets");
    PyObject* state = PyObject_GetAttrString(PyList_GetItem(sets, 0), "state");
    PyObject* pending = PyDict_GetItemString(PyList_GetItem(state, 0), "pending");  // borrowed
    ASSERT_NE(pending, nullptr);
    Mat L{};
    for (int i = 0; i < 9; ++i) {
      PyObject* v = PySequence_GetItem(pending, i);
      L[i] = PyFloat_AsDouble(v);
      Py_DECREF(v);
    }
    Py_DECREF(state);
    Py_DECREF(sets);
    Py_DECREF(mod);
    for (int i = 0; i < 8; ++i) EXPECT_EQ(L[i], 0.0) << "component " << i;
    const double ratio = L[8] / (dF[8] - 1.0);  // 1 / (ns dt)
    EXPECT_GT(ratio, 0.0);
    if (s == 0) ratio0 = ratio;
    EXPECT_NEAR(ratio, ratio0, 1e-9 * ratio0) << "step " << s;
  }
}

// ns_rule rate (set on the resident RVE set, then put back): an update of dt takes
// ceil(dt / O.dt) substeps within [ns_min, ns_max], as the native backend's rule; each RVE
// its own O.dt.
TEST_F(YadeBackend, RateRuleTakesTheUpdatesDtOverTheDemStep) {
  PyObject* mod = PyImport_ImportModule("mpmdem_rve");
  PyObject* sets = PyObject_GetAttrString(mod, "_sets");
  PyObject* set = PyList_GetItem(sets, 0);  // borrowed
  PyObject* p = PyObject_GetAttrString(set, "p");
  double dt_dem[2];
  for (int k = 0; k < 2; ++k) {
    PyObject* v = PyObject_CallMethod(set, "dem_dt", "i", k);
    dt_dem[k] = PyFloat_AsDouble(v);
    Py_DECREF(v);
    ASSERT_GT(dt_dem[k], 0.0);
  }
  PyObject* rate = PyUnicode_FromString("rate");
  PyObject* fixed = PyUnicode_FromString("fixed");
  PyDict_SetItemString(p, "ns_rule", rate);
  Mat dF = kI;
  dF[2] = 1e-5;
  RveReply reply[2];
  struct Case {
    double dt_over_dem;
    int ns;
  };
  for (const Case c : {Case{37.5, 38}, Case{0.4, 2}, Case{1000.0, 100}}) {  // ns_min 2, max 100
    RveRequest req[2] = {};
    for (int k = 0; k < 2; ++k) {
      for (int i = 0; i < 9; ++i) req[k].dF[i] = dF[i];
      req[k].dt = c.dt_over_dem * dt_dem[0];
    }
    protocol::ControlHeader h{};
    h.step = 500;
    backend_->step(h, req, reply);
    EXPECT_EQ(reply[0].n_substeps, c.ns) << "dt / dt_dem = " << c.dt_over_dem;
    const int ns1 = std::clamp(
        static_cast<int>(std::ceil(std::min(c.dt_over_dem * dt_dem[0] / dt_dem[1], 100.0))), 2,
        100);
    EXPECT_EQ(reply[1].n_substeps, ns1);  // its own O.dt
  }
  {  // a dt that is not a time: the Python error comes back as a typed error
    RveRequest req[2] = {};
    for (int k = 0; k < 2; ++k) {
      for (int i = 0; i < 9; ++i) req[k].dF[i] = dF[i];
      req[k].dt = std::nan("");
    }
    protocol::ControlHeader h{};
    h.step = 501;
    EXPECT_THROW(backend_->step(h, req, reply), std::exception);
  }
  PyDict_SetItemString(p, "ns_rule", fixed);
  Py_DECREF(rate);
  Py_DECREF(fixed);
  Py_DECREF(p);
  Py_DECREF(sets);
  Py_DECREF(mod);
}

// A strong isochoric stretch (F_zz -> 0.45) thins the cell below 2.2 diameters: the packing
// must be tiled (more spheres), keep its contacts and stress, and the cell must still follow
// the product of the increments exactly.
TEST_F(YadeBackend, ThinCellIsTiledAndStaysExact) {
  PyObject* mod = PyImport_ImportModule("mpmdem_rve");
  PyObject* sets = PyObject_GetAttrString(mod, "_sets");
  auto spheres = [&] {
    PyObject* n = PyObject_CallMethod(PyList_GetItem(sets, 0), "n_spheres", "i", 0);
    const long v = n ? PyLong_AsLong(n) : -1;
    Py_XDECREF(n);
    return v;
  };
  const long before = spheres();
  const Mat dF = {1.01, 0, 0, 0, 1, 0, 0, 0, 1 / 1.01};
  Mat product = trsf(0);
  RveReply reply[2];
  for (int s = 1; s <= 80; ++s) {
    product = mul(dF, product);
    step(dF, nullptr, reply, s);
    ASSERT_NE(reply[0].status, static_cast<int>(protocol::RveStatus::kBackendError));
    const Mat t = trsf(0);
    for (int i = 0; i < 9; ++i) ASSERT_NEAR(t[i], product[i], 1e-10) << "step " << s;
  }
  EXPECT_GE(spheres(), 2 * before);
  EXPECT_EQ(reply[0].status, static_cast<int>(protocol::RveStatus::kOk));
  EXPECT_LT(reply[0].stress[8], 0.0);  // still a compressed contact network
  Py_DECREF(sets);
  Py_DECREF(mod);
}

TEST_F(YadeBackend, RestoreReproducesStressesAfterCheckpoint) {
  const auto dir = std::filesystem::temp_directory_path() / "mpmdem_yade_ckpt_test";
  std::filesystem::remove_all(dir);
  const Mat dF = {1 - 1e-4, 5e-5, 0, 0, 1 - 1e-4, 0, 0, 0, 1 + 5e-5};
  RveReply reply[2], first[2], again[2];
  for (int s = 0; s < 3; ++s) step(dF, nullptr, reply, s);
  backend_->checkpoint(dir);
  EXPECT_TRUE(std::filesystem::exists(dir / "rve_7.yade"));  // per RVE, not per rank
  for (int s = 0; s < 4; ++s) step(dF, nullptr, first, s);
  backend_->restore(dir);
  for (int s = 0; s < 4; ++s) step(dF, nullptr, again, s);
  for (int k = 0; k < 2; ++k)
    for (int i = 0; i < 9; ++i) EXPECT_NEAR(first[k].stress[i], again[k].stress[i], 1e-10);
  std::filesystem::remove_all(dir);
}

TEST_F(YadeBackend, LostContactsGiveZeroStressAndFlagNeverNaN) {
  const Mat expand = {1.2, 0, 0, 0, 1.2, 0, 0, 0, 1.2};
  RveReply reply[2];
  step(kI, &expand, reply);
  EXPECT_EQ(reply[1].status, static_cast<int>(protocol::RveStatus::kNoContacts));
  for (double s : reply[1].stress) EXPECT_EQ(s, 0.0);
  EXPECT_TRUE(backend_->last_fault_message().empty());
  step(kI, &kI, reply);  // stays finite and flagged while apart
  EXPECT_EQ(reply[1].status, static_cast<int>(protocol::RveStatus::kNoContacts));
}

// Its own suite (a plain TEST cannot join the fixture's), so that it does not start YADE.
TEST(YadeBackendTestList, EqualsTheBuildWithoutYade) {
  const testing::TestSuite* suite = nullptr;
  const auto* unit = testing::UnitTest::GetInstance();
  for (int i = 0; i < unit->total_test_suite_count(); ++i) {
    if (std::string(unit->GetTestSuite(i)->name()) == "YadeBackend") suite = unit->GetTestSuite(i);
  }
  ASSERT_NE(suite, nullptr);
  std::set<std::string> registered, listed;
  for (int i = 0; i < suite->total_test_count(); ++i)
    registered.insert(suite->GetTestInfo(i)->name());
#define MPMDEM_LIST_NAME(name) listed.insert(#name);
  MPMDEM_YADE_BACKEND_TESTS(MPMDEM_LIST_NAME)
#undef MPMDEM_LIST_NAME
  EXPECT_EQ(registered, listed) << "add the test's name to MPMDEM_YADE_BACKEND_TESTS";
}

}  // namespace

#else
#define MPMDEM_SKIPPED_TEST(name)                                                 \
  TEST(YadeBackend, name) {                                                       \
    GTEST_SKIP() << "dem_app was built without the YADE backend (configure with " \
                    "-DMPMDEM_WITH_YADE=ON; needs python3.11-dev and yade)";      \
  }
MPMDEM_YADE_BACKEND_TESTS(MPMDEM_SKIPPED_TEST)
TEST(YadeBackendTestList, EqualsTheBuildWithoutYade) {
  GTEST_SKIP() << "no YADE backend: nothing to compare";
}
#endif
