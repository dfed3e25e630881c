// Stability guards (issue 6, item 3): the per-step non-finite state guard (state_guard.hpp),
// the energy budget (energy_budget.hpp) that closes the energy balance, and solver.dt_fixed
// above the CFL limit detected as an instability naming the point and the step. In every
// failed run, no file of the run directory holds a NaN or an Inf.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "constitutive/linear_elastic.hpp"
#include "hooked_provider.hpp"
#include "mpmdem/protocol.hpp"
#include "run_driver.hpp"
#include "scene_builder.hpp"
#include "state_guard.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace mpmdem::mpm;
using test_fixture::HookedProvider;
using test_fixture::quiet_options;
using test_fixture::SceneBuilder;
using test_fixture::Update;
using test_support::read_file;
using test_support::TempDir;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The elastic column (configs/elastic_column.yaml) without its verification, an energy row
// every step.
SceneBuilder column(double end_time, double damping) {
  return SceneBuilder::config("configs/elastic_column.yaml")
      .end_time(end_time)
      .damping(damping)
      .verification(VerificationKind::kNone)
      .with([](Scene& s) { s.output.energy_interval = 0.0; });
}

// Non-finite values in a .vtu with raw appended Float64 arrays (vtk_writer.cpp's layout).
std::size_t vtu_non_finite(const fs::path& file) {
  const std::string text = read_file(file);
  const std::size_t appended = text.find("<AppendedData encoding=\"raw\">");
  EXPECT_NE(appended, std::string::npos) << file;
  if (appended == std::string::npos) return 1;
  const std::string head = text.substr(0, appended);
  const std::size_t data = text.find('_', appended) + 1;
  const std::regex decl("<DataArray type=\"Float64\"[^>]* offset=\"(\\d+)\"/>");
  std::size_t bad = 0, arrays = 0;
  for (auto it = std::sregex_iterator(head.begin(), head.end(), decl); it != std::sregex_iterator();
       ++it, ++arrays) {
    const std::size_t offset = std::stoul((*it)[1]);
    std::uint64_t nbytes = 0;
    std::memcpy(&nbytes, text.data() + data + offset, sizeof nbytes);
    for (std::size_t k = 0; k < nbytes / sizeof(double); ++k) {
      double v;
      std::memcpy(&v, text.data() + data + offset + sizeof nbytes + k * sizeof v, sizeof v);
      if (!std::isfinite(v)) ++bad;
    }
  }
  EXPECT_GT(arrays, 3u) << file;
  return bad;
}

// Every file of a run directory: text files hold no nan/inf token, VTK frames no
// non-finite Float64. Returns the number of files checked.
std::size_t expect_no_non_finite(const std::string& dir) {
  const std::regex token("(^|[,:\\s\\[])[-+]?(nan|inf)", std::regex::icase);
  std::size_t files = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (!e.is_regular_file()) continue;
    const std::string ext = e.path().extension().string();
    if (ext == ".vtu") {
      EXPECT_EQ(vtu_non_finite(e.path()), 0u) << e.path();
    } else if (ext == ".csv" || ext == ".json" || ext == ".pvd" || ext == ".txt") {
      const std::string text = read_file(e.path());
      EXPECT_FALSE(std::regex_search(text, token)) << e.path() << ":\n" << text.substr(0, 400);
    } else {
      continue;
    }
    ++files;
  }
  return files;
}

double column_value(const std::string& csv_line, std::size_t col) {
  std::stringstream ss(csv_line);
  std::string cell;
  for (std::size_t c = 0; std::getline(ss, cell, ','); ++c)
    if (c == col) return std::stod(cell);
  return kNaN;
}

}  // namespace

TEST(StateGuard, NamesTheFirstPointAndTheField) {
  Particles p = column(0.1, 0.0).particles();
  p.porosity.assign(p.size(), 0.4);
  NonFinite where;
  EXPECT_FALSE(find_first_non_finite(p, where));
  const std::vector<std::pair<std::function<void(std::size_t)>, std::string>> faults = {
      {[&](std::size_t q) { p.x[q].y() = kNaN; }, "position"},
      {[&](std::size_t q) { p.v[q].z() = std::numeric_limits<double>::infinity(); }, "velocity"},
      {[&](std::size_t q) { p.sigma[q](0, 2) = kNaN; }, "stress"},
      {[&](std::size_t q) { p.F[q](1, 1) = kNaN; }, "deformation gradient"},
      {[&](std::size_t q) { p.V[q] = kNaN; }, "volume"},
      {[&](std::size_t q) { p.porosity[q] = kNaN; }, "porosity"}};
  for (const auto& [inject, field] : faults) {
    Particles clean = p;
    std::swap(p, clean);
    inject(17);
    inject(250);  // a later point too: the first one is reported
    ASSERT_TRUE(find_first_non_finite(p, where)) << field;
    EXPECT_EQ(where.point, 17u);
    EXPECT_EQ(std::string(where.field), field);
    std::swap(p, clean);
  }
}

// A NaN the provider returns in an RVE output (porosity: no other check looks at it) stops
// the run at that step, naming the point; nothing non-finite is written anywhere.
TEST(StateGuard, InjectedNaNStopsTheRunBeforeAnyOutputHoldsIt) {
  const Scene scene = column(0.05, 0.0)
                          .model(kRemoteModel)  // the points carry RVE outputs
                          .with([](Scene& s) {
                            s.coupling.outputs = mpmdem::protocol::kOutputPorosity;
                            s.output.interval = 1e-4;  // a frame about every step up to the fault
                            s.output.checkpoint_interval_steps = 2;
                          })
                          .build();
  TempDir dir("nan");
  std::ostringstream log;
  RunOptions o = quiet_options(dir.str(), log);
  o.provider_factory = [](const Scene& s, std::size_t) -> std::unique_ptr<ConstitutiveProvider> {
    return std::make_unique<HookedProvider>(make_linear_elastic(s.constitutive),
                                            [](const Update& u, auto& out) {
                                              for (auto& r : out) r.porosity = 0.4;
                                              if (u.call == 7) out[42].porosity = kNaN;
                                            });
  };
  const RunResult r = run_scene(scene, o);
  EXPECT_EQ(r.exit_code, 4) << log.str();
  EXPECT_EQ(r.summary.status, "failed");
  EXPECT_EQ(r.summary.steps, 7);
  const std::string& e = r.summary.error;
  EXPECT_NE(e.find("non-finite porosity at material point 42"), std::string::npos) << e;
  EXPECT_NE(e.find("at step 7"), std::string::npos) << e;
  EXPECT_NE(read_file(dir.str() + "/summary.json").find("material point 42"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir.str() + "/final_state.h5"));
  EXPECT_TRUE(fs::exists(dir.str() + "/frame_00006.vtu")) << log.str();
  EXPECT_GE(expect_no_non_finite(dir.str()), 8u);  // energies, timings, summary, pvd, frames
  // The last energy row is the last finite state (step 6).
  const std::string energies = read_file(dir.str() + "/energies.csv");
  const std::string last = energies.substr(energies.rfind('\n', energies.size() - 2) + 1);
  EXPECT_EQ(column_value(last, 1), 6.0) << last;
}

// A forced time step 3x the CFL limit: the run blows up and is stopped with the point and the
// step, status failed, exit code 4, and no NaN in the files.
TEST(StateGuard, ForcedTimeStepAboveTheCflLimitIsDetected) {
  SceneBuilder b = column(0.5, 0.0);
  const double c = 82.04, h = b.build().grid.cell_size;  // P-wave speed of the column (its comment)
  const Scene scene = b.dt_fixed(3.0 * h / c).build();
  TempDir dir("dt");
  std::ostringstream log;
  const RunResult r = run_scene(scene, quiet_options(dir.str(), log));
  EXPECT_EQ(r.exit_code, 4) << log.str();
  EXPECT_EQ(r.summary.status, "failed");
  EXPECT_NE(log.str().find("exceeds the CFL limit"), std::string::npos) << log.str();
  const std::regex named("material point \\d+ .* at step \\d+");
  EXPECT_TRUE(std::regex_search(r.summary.error, named)) << r.summary.error;
  EXPECT_NE(r.summary.error.find("solver.dt_fixed"), std::string::npos) << r.summary.error;
  EXPECT_LT(r.summary.steps, 400);  // it diverges fast
  EXPECT_GE(expect_no_non_finite(dir.str()), 3u);
}

// The energy budget closes: W_int equals the elastic strain energy, and
// E_err = E_p0 + E_k0 - E_p - E_k - W_int - W_damp - W_bc stays small against the energy
// released, undamped (W_damp = 0) and damped (W_damp carries what the damping removed).
TEST(EnergyBudget, ClosesTheBalanceOfTheElasticColumn) {
  for (double damping : {0.0, 0.8}) {
    const Scene scene = column(0.1, damping).build();
    TempDir dir("budget");
    std::ostringstream log;
    const RunResult r = run_scene(scene, quiet_options(dir.str(), log));
    ASSERT_EQ(r.exit_code, 0) << log.str();
    std::ifstream in(dir.str() + "/energies.csv");
    std::string line;
    std::getline(in, line);
    ASSERT_EQ(line,
              "time,step,dt,E_p,E_k,E_d,E_strain,E_p0,E_k0,W_int,W_damp,W_bc,E_err,W_transfer,"
              "W_transfer_walls");
    double released = 0.0, err = 0.0, int_vs_strain = 0.0, W_damp = 0.0;
    std::size_t rows = 0;
    while (std::getline(in, line)) {
      const auto v = [&](std::size_t c) { return column_value(line, c); };
      released = std::max(released, v(7) - v(3));
      err = std::max(err, std::abs(v(12)));
      EXPECT_NEAR(v(12), v(7) + v(8) - v(3) - v(4) - v(9) - v(10) - v(11), 1e-9 * v(7));
      int_vs_strain = std::max(int_vs_strain, std::abs(v(9) - v(6)));
      W_damp = v(10);
      ++rows;
    }
    EXPECT_GT(rows, 500u);
    ASSERT_GT(released, 1e-3);  // J; rho g H^2 A settlement scale
    std::cout << "damping " << damping << ": max |E_err| / released = " << err / released
              << ", max |W_int - E_strain| / released = " << int_vs_strain / released
              << ", W_damp = " << W_damp << " J\n";
    EXPECT_LT(err / released, 0.01);
    EXPECT_LT(int_vs_strain / released, 0.01);
    if (damping > 0.0) {
      EXPECT_GT(W_damp, 0.2 * released);
    } else {
      EXPECT_EQ(W_damp, 0.0);
    }
  }
}
