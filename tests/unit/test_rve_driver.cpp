// The per-RVE driver (dem_app/src/rve_driver.hpp) with a stepper that is only a periodic cell
// (native::PeriodicCell, YADE's velGrad lag): what a new DEM backend gets without writing it.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "backends/native/periodic_cell.hpp"
#include "rve_driver.hpp"

namespace {

using namespace mpmdem;
using protocol::RveReply;
using protocol::RveRequest;
using RowMajor3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;

// Each RVE is a cell stepped as the native integrator steps it, with a kinetic energy the
// test sets; its reply's stress is its trsf (row-major).
struct CellStepper final : dem::RveStepper {
  explicit CellStepper(std::size_t n) : cells(n), kinetic(n, 0.0), substeps(n, 0) {}
  double dem_dt(std::size_t) const override { return 1e-3; }
  Eigen::Matrix3d trsf(std::size_t k) const override { return cells[k].trsf; }
  Eigen::Matrix3d pending_vel_grad(std::size_t k) const override {
    return cells[k].pending_vel_grad();
  }
  void set_vel_grad(std::size_t k, const Eigen::Matrix3d& l) override { cells[k].set_vel_grad(l); }
  void substep(std::size_t k) override {
    cells[k].integrate_and_update(dem_dt(k));
    cells[k].activate_next();
    ++substeps[k];
  }
  dem::RveEnergy energy(std::size_t k) const override {
    return {kinetic[k], cells[k].volume(), 1.0};
  }
  void measure(std::size_t k, std::uint64_t, std::int32_t status, std::int32_t ns,
               RveReply& reply) override {
    std::memset(&reply, 0, sizeof reply);
    Eigen::Map<RowMajor3>(reply.stress) = cells[k].trsf;
    reply.status = status;
    reply.n_substeps = ns;
  }
  std::vector<dem::native::PeriodicCell> cells;
  std::vector<double> kinetic;
  std::vector<int> substeps;
};

RveRequest request(const RowMajor3& dF, std::uint32_t flags = 0, double dt = 0.0) {
  RveRequest r{};
  Eigen::Map<RowMajor3>(r.dF) = dF;
  r.flags = flags;
  r.dt = dt;
  return r;
}

dem::SubstepRule proportional() {
  dem::SubstepRule rule;
  rule.kind = dem::SubstepRule::Kind::kProportional;
  rule.ns_factor = 1e5;
  rule.ns_min = 2;
  rule.ns_max = 50;
  return rule;
}

TEST(SubstepRule, FixedProportionalAndRateClampedToTheirBounds) {
  dem::SubstepRule rule = proportional();
  RowMajor3 f = RowMajor3::Identity();
  f(2, 2) = 1.0 - std::ldexp(1.0, -13);  // 1e5 max|dF - I| = 12.207...: 13 substeps
  EXPECT_EQ(rule.count(request(f), 1e-3), 13);
  EXPECT_EQ(rule.count(request(RowMajor3::Identity()), 1e-3), 2);  // raised to ns_min
  f(0, 1) = 1.0;                                                   // a huge increment
  EXPECT_EQ(rule.count(request(f), 1e-3), 50);                     // ns_max, no overflow
  rule.kind = dem::SubstepRule::Kind::kRate;
  EXPECT_EQ(rule.count(request(f, 0, 7.5e-3), 1e-3), 8);
  EXPECT_THROW(rule.count(request(f, 0, std::nan("")), 1e-3), std::runtime_error);
  EXPECT_THROW(rule.count(request(f, 0, -1.0), 1e-3), std::runtime_error);
  rule.kind = dem::SubstepRule::Kind::kFixed;
  rule.ns = 7;
  EXPECT_EQ(rule.count(request(f), 1e-3), 7);
}

// The cell ends each update at dF trsf_before, whatever the lag left pending; a skip repeats
// the last reply without stepping; a query steps nothing; the status comes from the energy.
TEST(RveDriver, SplitsSkipsQueriesAndDecidesTheStatus) {
  dem::RveDriver driver(proportional(), 10.0);
  CellStepper s(2);
  RveReply reply[2];
  protocol::ControlHeader h{};
  RowMajor3 a = RowMajor3::Identity(), b = RowMajor3::Identity();
  a(0, 2) = std::ldexp(1.0, -12);        // simple shear, 1e5 2^-12 = 24.4: 25 substeps
  b(1, 1) = 1.0 - std::ldexp(1.0, -15);  // 3.05: 4 substeps
  Eigen::Matrix3d product = Eigen::Matrix3d::Identity();
  for (int n = 1; n <= 4; ++n) {
    h.step = static_cast<std::uint64_t>(n);
    const RowMajor3 dF = n % 2 ? a : b;
    const RveRequest req[2] = {request(dF), request(dF)};
    driver.step(h, req, reply, 2, 0, s, 1);
    product = Eigen::Matrix3d(dF) * product;
    for (int k = 0; k < 2; ++k) {
      EXPECT_LT((Eigen::Map<RowMajor3>(reply[k].stress) - product).cwiseAbs().maxCoeff(), 1e-14);
      EXPECT_EQ(reply[k].n_substeps, n % 2 ? 25 : 4);
      EXPECT_EQ(reply[k].status, 0);
    }
  }
  const int before = s.substeps[0];
  const RveReply last = reply[0];
  h.step = 5;
  RveRequest req[2] = {request(a, protocol::kFlagSkip), request(a, protocol::kFlagQueryOnly)};
  s.kinetic[1] = 1e9;  // above ke_threshold p0 volume
  driver.step(h, req, reply, 2, 7, s, 1);
  // RVE 7 has no reply cached yet (the first steps were RVEs 0 and 1): it is measured.
  EXPECT_EQ(s.substeps[0], before);
  EXPECT_EQ(reply[0].n_substeps, 0);
  EXPECT_EQ(std::memcmp(reply[0].stress, last.stress, sizeof last.stress), 0);
  EXPECT_EQ(reply[1].status, static_cast<std::int32_t>(protocol::RveStatus::kExploding));
  EXPECT_NE(driver.last_fault().find("RVE 8 step 5: exploding kinetic energy"), std::string::npos);
  // Now served from the cache, nothing measured: the energy no longer matters.
  s.kinetic[0] = std::nan("");
  req[0].flags = protocol::kFlagSkip;
  driver.step(h, req, reply, 1, 7, s, 1);
  EXPECT_EQ(reply[0].status, 0);
  EXPECT_TRUE(driver.last_fault().empty());
  driver.forget();  // after a checkpoint: measured again
  driver.step(h, req, reply, 1, 7, s, 1);
  EXPECT_EQ(reply[0].status, static_cast<std::int32_t>(protocol::RveStatus::kNonFinite));
  EXPECT_NE(driver.last_fault().find("RVE 7 step 5: non-finite values"), std::string::npos);
  // A rate update without a valid dt is the client's fault, thrown after the loop.
  dem::SubstepRule rate;
  rate.kind = dem::SubstepRule::Kind::kRate;
  dem::RveDriver by_rate(rate, 10.0);
  req[0] = request(a, 0, std::nan(""));
  EXPECT_THROW(by_rate.step(h, req, reply, 1, 0, s, 1), std::runtime_error);
}

}  // namespace
