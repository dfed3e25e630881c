// The column collapse with the local Drucker-Prager model (configs/column_collapse_mc.yaml,
// 240 points, < 1 s per run): conservation, dissipation, a deposit at rest inside the domain,
// runout in the published band and a height between the wedge bound and the measured one, the
// friction angle's effect, the at-rest stop
// (column_collapse.at_rest) against the full 6 t*, and checkpoints from which a resumed run
// ends in exactly the uninterrupted state, also inside the at-rest hold.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "analysis/column_collapse.hpp"
#include "config/scene_loader.hpp"
#include "constitutive/drucker_prager.hpp"
#include "output/checkpoint.hpp"
#include "run_driver.hpp"
#include "scene_builder.hpp"
#include "test_support.hpp"

using namespace mpmdem::mpm;
using test_fixture::quiet_options;
using test_fixture::SceneBuilder;
using test_support::TempDir;
namespace fs = std::filesystem;

namespace {

SceneBuilder mc_scene() {
  return SceneBuilder::config("configs/column_collapse_mc.yaml");
}

struct ColumnRun {
  RunResult result;
  Particles final_state;
  std::vector<std::vector<double>> energies;  // time, step, dt, E_p, E_k, E_d, E_strain, E_p0
};

ColumnRun run(const Scene& scene, const std::string& dir, const std::string& resume = "") {
  ColumnRun r;
  std::ostringstream sink;
  RunOptions o = quiet_options(dir, sink, &r.final_state);
  o.force = true;
  o.resume = resume;
  r.result = run_scene(scene, o);
  std::ifstream in(dir + "/energies.csv");
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) row.push_back(std::stod(cell));
    r.energies.push_back(row);
  }
  return r;
}

double figure(const RunSummary& s, const std::string& key) {
  for (const auto& [k, v] : s.analysis)
    if (k == key) return v;
  ADD_FAILURE() << "summary has no " << key;
  return NAN;
}

}  // namespace

TEST(ColumnCollapse, LocalModelConservesMassDissipatesAndRunsOutInTheLawsBand) {
  TempDir dir("mc");
  const Scene scene = mc_scene().build();
  const ColumnRun r = run(scene, dir.str());
  ASSERT_EQ(r.result.exit_code, 0);
  const RunSummary& s = r.result.summary;
  // Mass: no point may leave, and the grid carried all of it at the last step.
  EXPECT_EQ(s.removed_points, 0u);
  EXPECT_NEAR(s.mass_grid_kg, s.mass_initial_kg, 1e-12 * s.mass_initial_kg);
  const Grid grid(scene.grid);
  ASSERT_GT(r.final_state.size(), 0u) << "the run returned no final state";
  for (const auto& x : r.final_state.x) ASSERT_TRUE(grid.contains(x)) << x.transpose();
  // Stage 1 ended by its own rule, stage 2 by the at-rest stop, between min_t_star and 6 t*.
  const ColumnGeometry g = column_geometry(scene);
  EXPECT_NEAR(figure(s, "t_star_s"), std::sqrt(1.32 / 9.81), 1e-12);
  const double t_r = figure(s, "stage1_time_s");
  EXPECT_GE(t_r, 0.05);
  EXPECT_LE(t_r, 0.5);
  ASSERT_TRUE(scene.column_collapse.at_rest);
  EXPECT_EQ(s.stop_reason, "at_rest");
  EXPECT_GE(figure(s, "time_over_t_star_final"), scene.column_collapse.at_rest_min_t_star);
  EXPECT_LT(figure(s, "time_over_t_star_final"), 6.0);
  // Dissipation: E_d (from the base, E_p0 at the release) never negative and never
  // decreasing by more than 1% of E_p0 (E_d also holds the elastic energy, which oscillates).
  const double Ep0 = figure(s, "Ep0_release_J");
  double Ed_prev = 0.0, Ed_max = 0.0;
  for (const auto& row : r.energies) {
    if (row[0] < t_r) continue;
    const double Ed = Ep0 - row[3] - row[4];  // E_p of the CSV is from z = 0 = the base here
    EXPECT_GE(Ed, -0.01 * Ep0) << "t = " << row[0];
    EXPECT_GE(Ed, Ed_prev - 0.01 * Ep0) << "t = " << row[0];
    Ed_prev = Ed;
    Ed_max = std::max(Ed_max, Ed);
  }
  EXPECT_GT(Ed_max, 0.3 * Ep0);
  // At rest at the end: below the stop's threshold.
  EXPECT_LT(figure(s, "Ek_over_Ep0_final"), scene.column_collapse.at_rest_kinetic_ratio);
  // Runout in the band of the published laws (shared/notes/validation.md): dL/L_i 2.88-4.32.
  // The height is not held to the laws' band H_f/L_i = a^(1/3)..a^(2/5) (0.74-0.78 m): this
  // Drucker-Prager column (phi = 20 deg) settles below it once the discretisation converges
  // (0.58 -> 0.55 m from 0.11 to 0.0275 m cells on quadratic B-splines; trilinear shapes gave
  // 0.78 m on 0.11 m cells and fell with every refinement; docs/transfers.md, "The shape").
  // Instead: the deposit holds the column (no plastic dilation): a granular deposit lies
  // below the straight wedge from H_f at the back wall to its front, so L_f H_f / 2 >= L_i H_i
  // (2 % for the elastic compression: 0.527 m here), and it stands at most 10 % above what
  // this scene measured (0.579 m, 2026-11-28; 0.55 m on the finest cells): a column that
  // does not collapse, or collapses less, fails.
  const double dL = figure(s, "runout_normalized");
  EXPECT_GE(dL, 2.88);
  EXPECT_LE(dL, 4.32);
  const double H_f = figure(s, "final_height_m");
  EXPECT_GE(H_f, 0.98 * 2.0 * g.L_i * g.H_i / figure(s, "runout_m"));
  EXPECT_LE(H_f, 1.1 * 0.579);
  // Per-phase timing: one row per step, phases inside the step's wall time, no DEM side.
  std::ifstream timings(dir.str() + "/timings.csv");
  std::string row;
  std::int64_t rows = -1;  // the header
  while (std::getline(timings, row)) ++rows;
  EXPECT_EQ(rows, s.steps);
  const double phases = figure(s, "time_p2g_s") + figure(s, "time_grid_s") +
                        figure(s, "time_g2p_dF_s") + figure(s, "time_stress_s");
  EXPECT_GT(phases, 0.0);
  EXPECT_LE(phases, s.step_wall_time_s * 1.001 + 1e-6);
  EXPECT_EQ(figure(s, "time_dem_max_s"), 0.0);
  const double ed = figure(s, "Ed_over_Ep0_final");
  EXPECT_GE(ed, 1.0 - H_f / g.H_i - 0.02);
  EXPECT_LE(ed, 1.0 - g.L_i / figure(s, "runout_m") + 0.02);
  // The shipped transfer sheds no points: the connected front is the runout.
  EXPECT_EQ(figure(s, "runout_front_m"), figure(s, "runout_m"));
  // summary.json's energy budget is energies.csv's last row (W_int, W_damp, W_bc at columns
  // 9-11, E_err at 12, W_transfer at 13); the stress work is most of the energy released.
  const std::vector<double>& last = r.energies.back();
  const double released = s.E_p0_J + s.E_k0_J - s.E_p_J - s.E_k_J;
  EXPECT_NEAR(s.W_int_J, last[9], 1e-9 * released);
  EXPECT_NEAR(s.W_damp_J, last[10], 1e-9 * released);
  EXPECT_NEAR(s.W_bc_J, last[11], 1e-9 * released);
  EXPECT_NEAR(released - s.W_int_J - s.W_damp_J - s.W_bc_J, last[12], 1e-9 * released);
  EXPECT_NEAR(s.W_transfer_J, last[13], 1e-9 * released);
  EXPECT_GT(s.W_int_J, 0.5 * released);
  // The budget closes once the transfers' share is counted: what the PIC part of the blend
  // filters out is the residual E_err (22 % of the energy released on this scene), and the
  // rest, the time integration's error, is +0.26 % with USL (MUSL: -0.98 %; docs/transfers.md,
  // "USL, and where the residual goes").
  const double E_err = released - s.W_int_J - s.W_damp_J - s.W_bc_J;
  EXPECT_GT(s.W_transfer_J, 0.1 * released);
  EXPECT_LT(std::abs(E_err - s.W_transfer_J), 0.005 * released);
}

// On a Coulomb base (mu_b = 0.52, the grains' friction) the shipped scheme (USL) keeps the
// energy budget closed too: the time integration's part of E_err is +0.6 % of the energy
// released. MUSL, whose velocity gradient comes from re-mapped velocities, created 11 % at
// this cfl, and points left the deposit.
TEST(ColumnCollapse, CoulombBaseKeepsTheEnergyBudgetClosed) {
  TempDir dir("mc_coulomb");
  const Scene scene = mc_scene().base(WallType::kFriction, 0.52).build();
  ASSERT_EQ(scene.solver.scheme, Scheme::kUSL);
  const ColumnRun r = run(scene, dir.str());
  ASSERT_EQ(r.result.exit_code, 0);
  const RunSummary& s = r.result.summary;
  const double released = s.E_p0_J + s.E_k0_J - s.E_p_J - s.E_k_J;
  const double E_err = released - s.W_int_J - s.W_damp_J - s.W_bc_J;
  EXPECT_GT(s.W_bc_J, 0.01 * released);  // the base's friction works
  EXPECT_LT(std::abs(E_err - s.W_transfer_J), 0.01 * released);
  EXPECT_EQ(figure(s, "runout_front_m"), figure(s, "runout_m"));  // no point left the deposit
  EXPECT_EQ(s.stop_reason, "at_rest");
}

// The disconnected state (constitutive.drucker_prager.disconnection_volume_ratio) on APIC with
// a FLIP share: configs/column_collapse_mc_apic.yaml (docs/transfers.md, "The disconnected
// state"), whose domain is long enough for the runout of that little-damped blend. Without it,
// points that dilate at the front keep their stiffness at a falling density, which shrinks the
// stable step, and the deposit does not reach rest by 6 t*. With J_c = 1.5 the run stops at rest,
// the smallest step stays within a factor 2 of the largest, and the transfers dissipate less than
// half of what the shipped PIC/FLIP blend dissipates on the same column.
TEST(ColumnCollapse, DisconnectedStateBringsApicWithAFlipShareToRest) {
  TempDir d_shipped("shipped"), d_apic("apic"), d_disc("disc");
  const SceneBuilder apic_file = SceneBuilder::config("configs/column_collapse_mc_apic.yaml");
  const Scene disc = apic_file.build();
  ASSERT_EQ(disc.solver.transfer, Transfer::kAPIC);
  ASSERT_EQ(drucker_prager_params(disc.constitutive).disconnection_volume_ratio, 1.5);
  const Scene apic = SceneBuilder(apic_file)  // the same without the disconnected state
                         .with([](Scene& s) {
                           edit_drucker_prager_params(s.constitutive).disconnection_volume_ratio =
                               0.0;
                         })
                         .on_exit(OnExit::kRemove)
                         .build();
  const Scene shipped = mc_scene()  // PIC/FLIP, on the same domain
                            .with([&](Scene& s) { s.grid.extent.x() = disc.grid.extent.x(); })
                            .build();
  const ColumnRun a = run(shipped, d_shipped.str());
  const ColumnRun b = run(apic, d_apic.str());
  const ColumnRun c = run(disc, d_disc.str());
  ASSERT_EQ(a.result.exit_code, 0);
  ASSERT_EQ(b.result.exit_code, 0);
  ASSERT_EQ(c.result.exit_code, 0);
  const RunSummary &sa = a.result.summary, &sb = b.result.summary, &sc = c.result.summary;
  auto transfer_share = [](const RunSummary& s) {
    return s.W_transfer_J / (s.E_p0_J + s.E_k0_J - s.E_p_J - s.E_k_J);
  };
  std::printf(
      "APIC + FLIP share: stop %s / %s (without / with J_c), dt_min/dt_max %.3f / %.3f, "
      "transfers' share %.3f / %.3f (shipped PIC/FLIP %.3f), disconnected point updates %.0f, "
      "points at the end %.0f\n",
      sb.stop_reason.c_str(), sc.stop_reason.c_str(), sb.dt_min_s / sb.dt_max_s,
      sc.dt_min_s / sc.dt_max_s, transfer_share(sb), transfer_share(sc), transfer_share(sa),
      figure(sc, "disconnected_point_updates"), figure(sc, "disconnected_points_final"));
  EXPECT_NE(sb.stop_reason, "at_rest");
  EXPECT_EQ(sc.stop_reason, "at_rest");
  EXPECT_EQ(sc.removed_points, 0u);
  EXPECT_GT(figure(sc, "disconnected_point_updates"), 0.0)
      << "no point disconnected: the test lost its subject";
  EXPECT_GT(sc.dt_min_s, 0.5 * sc.dt_max_s);
  EXPECT_LT(sb.dt_min_s, 0.5 * sb.dt_max_s);
  EXPECT_LT(transfer_share(sc), 0.5 * transfer_share(sa));
}

// The deposit's connected front: a 10 x 3 block of points 0.05 m apart, a train of points
// 0.09 m apart (less than the 0.1 m cell: still connected) and two stray points beyond a
// 0.25 m gap. runout_m is set by the last stray point, the front by the end of the train.
TEST(ColumnCollapse, FrontIgnoresPointsThatLeftTheDeposit) {
  ColumnGeometry g;
  g.x_back = 0.0;
  g.z_base = 0.0;
  g.spacing_x = 0.05;
  g.spacing_z = 0.05;
  g.cell_size = 0.1;
  Particles p;
  auto add = [&](double x, double z) {
    p.x.emplace_back(x, 0.0, z);
    p.m.push_back(2.0);
  };
  for (int i = 0; i < 10; ++i)
    for (int k = 0; k < 3; ++k) add(0.025 + 0.05 * i, 0.025 + 0.05 * k);
  for (int i = 1; i <= 4; ++i) add(0.475 + 0.09 * i, 0.025);  // train up to x = 0.835
  add(0.835 + 0.25, 0.025);
  add(0.835 + 0.30, 0.025);
  const DepositShape d = measure_deposit(g, p);
  EXPECT_NEAR(d.runout_m, 1.135 + 0.025, 1e-12);
  EXPECT_NEAR(d.runout_front_m, 0.835 + 0.025, 1e-12);
  EXPECT_NEAR(d.detached_mass_fraction, 2.0 / 36.0, 1e-12);
  EXPECT_NEAR(d.final_height_m, 0.15, 1e-12);
  // Without stray points the two measures agree.
  p.x.resize(34);
  p.m.resize(34);
  const DepositShape e = measure_deposit(g, p);
  EXPECT_EQ(e.runout_front_m, e.runout_m);
  EXPECT_EQ(e.detached_mass_fraction, 0.0);
  // runout_mass99_m: with a light train and strays (0.1 kg each against 2 kg per block point)
  // 99 % of the 60.6 kg lies in the block, whose last column is at x = 0.475; with equal masses
  // (34 points) it takes the last point.
  EXPECT_NEAR(e.runout_mass99_m, 0.835, 1e-12);
  p.x.resize(36);
  p.m.assign(36, 2.0);
  for (std::size_t q = 30; q < 36; ++q) p.m[q] = 0.1;
  p.x[34] = Vec3(0.835 + 0.25, 0.0, 0.025);
  p.x[35] = Vec3(0.835 + 0.30, 0.0, 0.025);
  EXPECT_NEAR(measure_deposit(g, p).runout_mass99_m, 0.475, 1e-12);
}

TEST(ColumnCollapse, HigherFrictionRunsOutLessAndStandsTaller) {
  TempDir d20("phi20"), d35("phi35");
  const Scene low = mc_scene().build();
  const Scene high = mc_scene()
                         .with([](Scene& s) {
                           edit_drucker_prager_params(s.constitutive).friction_angle_deg = 35.0;
                         })
                         .build();
  const ColumnRun a = run(low, d20.str());
  const ColumnRun b = run(high, d35.str());
  ASSERT_EQ(a.result.exit_code, 0);
  ASSERT_EQ(b.result.exit_code, 0);
  EXPECT_LT(figure(b.result.summary, "runout_m"), figure(a.result.summary, "runout_m") - 0.1);
  EXPECT_GT(figure(b.result.summary, "final_height_m"), figure(a.result.summary, "final_height_m"));
  EXPECT_LT(figure(b.result.summary, "Ed_over_Ep0_final"),
            figure(a.result.summary, "Ed_over_Ep0_final"));
}

TEST(ColumnCollapse, AtRestStopEndsWithinHalfAPercentOfTheFullRun) {
  // The scene stops at rest (E_k/E_p0 below the ratio for the hold); the same scene without
  // column_collapse.at_rest runs the full 6 t*. The deposit must be the same to 0.5 %.
  TempDir d_rest("rest"), d_full("full");
  SceneBuilder scene = mc_scene().with([](Scene& s) { s.output.vtk = false; });
  const Scene rest = scene.build();
  const Scene full = scene.with([](Scene& s) { s.column_collapse.at_rest = false; }).build();
  const ColumnRun a = run(rest, d_rest.str());
  const ColumnRun b = run(full, d_full.str());
  ASSERT_EQ(a.result.exit_code, 0);
  ASSERT_EQ(b.result.exit_code, 0);
  const RunSummary& s = a.result.summary;
  EXPECT_EQ(s.stop_reason, "at_rest");
  EXPECT_EQ(b.result.summary.stop_reason, "duration");
  EXPECT_NEAR(figure(b.result.summary, "time_over_t_star_final"), 6.0, 0.01);
  EXPECT_LT(s.steps, b.result.summary.steps);
  for (const char* key : {"runout_m", "final_height_m", "Ed_over_Ep0_final"}) {
    const double ref = figure(b.result.summary, key);
    EXPECT_LT(std::abs(figure(s, key) - ref), 0.005 * ref) << key;
  }
  // summary.json says why and when: the stop's time and step are the run's last.
  std::ifstream in(d_rest.str() + "/summary.json");
  std::stringstream json;
  json << in.rdbuf();
  EXPECT_NE(json.str().find("\"reason\": \"at_rest\""), std::string::npos) << json.str();
  auto stop = [&](const std::string& key) -> double {
    for (const auto& [k, v] : s.stop)
      if (k == key) return v;
    ADD_FAILURE() << "stop has no " << key;
    return NAN;
  };
  EXPECT_EQ(stop("at_rest"), 1.0);
  EXPECT_EQ(stop("step"), static_cast<double>(s.steps));
  EXPECT_EQ(stop("time_s"), s.time_s);
  EXPECT_NEAR(stop("time_over_t_star"), figure(s, "time_over_t_star_final"), 1e-9);
  EXPECT_GE(stop("time_over_t_star") - stop("quiet_since_t_star"), 0.25 - 1e-9);
  // The hold really was quiet: every logged E_k/E_p0 since quiet_since is below the ratio.
  const double t_r = figure(s, "stage1_time_s"), t_star = figure(s, "t_star_s");
  const double Ep0 = figure(s, "Ep0_release_J");
  int rows = 0;
  for (const auto& row : a.energies) {
    if (row[0] < t_r + stop("quiet_since_t_star") * t_star) continue;
    EXPECT_LT(row[4] / Ep0, rest.column_collapse.at_rest_kinetic_ratio) << "t = " << row[0];
    ++rows;
  }
  EXPECT_GT(rows, 10);
}

namespace {

void resumed_run_ends_in_the_uninterrupted_state(Scene scene) {
  TempDir full("full"), part("part");
  scene.output.vtk = false;
  scene.output.checkpoint_interval_steps = 100;
  scene.output.checkpoints_kept = 100;
  const ColumnRun a = run(scene, full.str());
  ASSERT_EQ(a.result.exit_code, 0);
  ASSERT_EQ(a.result.summary.stop_reason, "at_rest");
  // Continue a copy from a checkpoint in stage 2 inside the at-rest hold (the constraint
  // released, snapshots 1 and 3 done, the quiet window open): the resumed run must keep the
  // window and stop at the same step.
  fs::copy(full.path(), part.path(), fs::copy_options::recursive);
  std::string ckpt;
  std::int64_t ckpt_step = -1;
  for (std::int64_t step = 100; step < a.result.summary.steps; step += 100) {
    SolverState state;
    DriverState driver;
    read_mpm_checkpoint(checkpoint_directory(part.str(), step), state, driver);
    if (driver.column.rest_quiet_since) {
      ckpt = checkpoint_directory(part.str(), step);
      ckpt_step = step;
      EXPECT_FALSE(driver.column.rest_time.has_value());
      break;
    }
  }
  ASSERT_FALSE(ckpt.empty()) << "no checkpoint inside the at-rest hold";
  const ColumnRun b = run(scene, part.str(), ckpt);
  ASSERT_EQ(b.result.exit_code, 0);
  // It resumed (a fresh re-run of this deterministic scene would end in the same state): from
  // the checkpoint's step, running only the steps after it.
  EXPECT_EQ(a.result.summary.resumed_from_step, -1);
  EXPECT_EQ(b.result.summary.resumed_from_step, ckpt_step);
  EXPECT_EQ(b.result.summary.steps_this_run, a.result.summary.steps - ckpt_step);
  EXPECT_EQ(a.result.summary.steps_this_run, a.result.summary.steps);
  ASSERT_GT(a.final_state.size(), 0u) << "the run returned no final state";
  ASSERT_EQ(a.final_state.size(), b.final_state.size());
  for (std::size_t q = 0; q < a.final_state.size(); ++q) {
    ASSERT_EQ(a.final_state.x[q], b.final_state.x[q]) << "point " << q;
    ASSERT_EQ(a.final_state.v[q], b.final_state.v[q]) << "point " << q;
    ASSERT_EQ(a.final_state.sigma[q], b.final_state.sigma[q]) << "point " << q;
    ASSERT_EQ(a.final_state.C[q], b.final_state.C[q]) << "point " << q;
    ASSERT_EQ(a.final_state.state[q], b.final_state.state[q]) << "point " << q;
  }
  EXPECT_EQ(a.result.summary.steps, b.result.summary.steps);
  EXPECT_EQ(b.result.summary.stop_reason, "at_rest");
  EXPECT_EQ(a.result.summary.stop, b.result.summary.stop);
  EXPECT_EQ(figure(a.result.summary, "runout_m"), figure(b.result.summary, "runout_m"));
  EXPECT_EQ(figure(a.result.summary, "stage1_time_s"), figure(b.result.summary, "stage1_time_s"));
  // The energy log of the resumed run is the uninterrupted one, row for row.
  EXPECT_EQ(a.energies, b.energies);
}

}  // namespace

// Also with APIC and the disconnected state (configs/column_collapse_mc_apic.yaml), whose
// affine matrices and volume ratios a checkpoint must carry.
TEST(ColumnCollapse, ResumedRunEndsInExactlyTheUninterruptedState) {
  for (const char* file : {"column_collapse_mc.yaml", "column_collapse_mc_apic.yaml"}) {
    SCOPED_TRACE(file);
    resumed_run_ends_in_the_uninterrupted_state(
        SceneBuilder::config(std::string("configs/") + file).build());
  }
}

TEST(ColumnCollapse, SceneErrorsNameTheKey) {
  const std::string base = std::string(MPMDEM_SOURCE_DIR) + "/configs/column_collapse_mc.yaml";
  std::ifstream in(base);
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  const auto bad = text.replace(text.find("release_constraint: lateral_face"),
                                std::string("release_constraint: lateral_face").size(),
                                "release_constraint: nope");
  TempDir dir("bad");
  fs::create_directories(dir.path());
  const std::string file = dir.str() + "/bad.yaml";
  std::ofstream(file) << bad;
  try {
    (void)load_scene(file);
    FAIL() << "a release_constraint naming no constraint was accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("column_collapse"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("'nope'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
  }
}

TEST(ColumnCollapse, AtRestKeysAreReadCheckedAndNamed) {
  const Scene scene = mc_scene().build();
  ASSERT_TRUE(scene.column_collapse.at_rest);
  EXPECT_EQ(scene.column_collapse.at_rest_kinetic_ratio, 2e-5);
  EXPECT_EQ(scene.column_collapse.at_rest_hold_t_star, 0.25);
  EXPECT_EQ(scene.column_collapse.at_rest_min_t_star, 1.0);
  const std::string base = std::string(MPMDEM_SOURCE_DIR) + "/configs/column_collapse_mc.yaml";
  std::ifstream in(base);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  TempDir dir("bad_at_rest");
  fs::create_directories(dir.path());
  // Each bad variant: the error names the key, the value and the file.
  const std::vector<std::pair<std::pair<std::string, std::string>, std::vector<std::string>>>
      cases = {
          {{"    kinetic_ratio: 2.0e-5", "    kinetic_ratio: -1"},
           {"column_collapse.at_rest.kinetic_ratio", "-1"}},
          {{"    min_t_star: 1", "    min_t_star: 7"},
           {"column_collapse.at_rest.min_t_star", "7", "duration_t_star"}},
          {{"    hold_t_star: 0.25", "    hold_t_star: 0.25\n    hold_time: 3"},
           {"column_collapse.at_rest.hold_time"}},
      };
  for (const auto& [edit, parts] : cases) {
    std::string bad = text;
    const auto pos = bad.find(edit.first);
    ASSERT_NE(pos, std::string::npos) << edit.first;
    bad.replace(pos, edit.first.size(), edit.second);
    const std::string file = dir.str() + "/bad.yaml";
    std::ofstream(file) << bad;
    try {
      (void)load_scene(file);
      ADD_FAILURE() << "accepted: " << edit.second;
    } catch (const std::exception& e) {
      for (const std::string& part : parts)
        EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
    }
  }
}

// column_collapse.snapshots_t_star is a list of any length ([] for none), increasing; a run
// saves exactly the snapshots it lists. Bad lists are refused naming the key, the item and
// the file.
TEST(ColumnCollapse, SnapshotTimesAreAnIncreasingListOfAnyLength) {
  const std::string base = std::string(MPMDEM_SOURCE_DIR) + "/configs/column_collapse_mc.yaml";
  std::ifstream in(base);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  const std::string shipped = "  snapshots_t_star: [1, 3, 6]";
  ASSERT_NE(text.find(shipped), std::string::npos);
  TempDir dir("snapshot_list");
  fs::create_directories(dir.path());
  const std::string file = dir.str() + "/scene.yaml";
  auto load_with = [&](const std::string& value) {
    std::string t = text;
    t.replace(t.find(shipped), shipped.size(), "  snapshots_t_star: " + value);
    std::ofstream(file) << t;
    return load_scene(file);
  };
  EXPECT_EQ(load_with("[0.5]").column_collapse.snapshots_t_star, std::vector<double>{0.5});
  EXPECT_TRUE(load_with("[]").column_collapse.snapshots_t_star.empty());
  EXPECT_EQ(load_with("[0.5, 1, 2, 3, 6]").column_collapse.snapshots_t_star,
            (std::vector<double>{0.5, 1, 2, 3, 6}));
  const std::vector<std::pair<std::string, std::vector<std::string>>> bad = {
      {"[3, 1]", {"column_collapse.snapshots_t_star", "must increase", "1 follows 3"}},
      {"[1, 1]", {"column_collapse.snapshots_t_star", "must increase"}},
      {"[1, x]", {"column_collapse.snapshots_t_star[1] must be a number, got 'x'"}},
      {"[-1]", {"column_collapse.snapshots_t_star[0] must be >= 0, got -1"}},
      {"2", {"column_collapse.snapshots_t_star must be a list of numbers"}},
  };
  for (const auto& [value, parts] : bad) {
    try {
      (void)load_with(value);
      ADD_FAILURE() << "accepted: " << value;
    } catch (const std::exception& e) {
      for (const std::string& part : parts)
        EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
    }
  }

  // One snapshot, at 0.5 t*, on a run to 1 t*: that file and no other.
  const Scene scene = mc_scene()
                          .with([](Scene& s) {
                            s.column_collapse.snapshots_t_star = {0.5};
                            s.column_collapse.duration_t_star = 1.0;
                            s.column_collapse.at_rest = false;
                          })
                          .build();
  TempDir out("snapshot_one");
  const ColumnRun r = run(scene, out.str());
  ASSERT_EQ(r.result.exit_code, 0);
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(out.path() / "snapshots"))
    files.push_back(e.path().filename().string());
  EXPECT_EQ(files, std::vector<std::string>{"t_star_0.5.h5"});
}
