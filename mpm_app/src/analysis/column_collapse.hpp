// Granular column collapse (Liang & Zhao 2022, section 3; Lajeunesse et al. 2005): the two
// stages and the figures of the paper, measured on the material points.
//
// Geometry (checked when the scene is loaded): gravity along -z, the column is a region box
// whose min-x face lies on the back wall and whose base lies on the z_min wall; it collapses
// towards +x. H_i and L_i are the region's z and x extents, t* = sqrt(H_i / |g|).
//
// Stages: stage 1 holds the lateral free surface with the velocity constraint named by
// column_collapse.release_constraint until it is released (its own release rule: time, or
// E_k/E_p0 below a ratio); stage 2 starts at that release, time t_r, and the run ends at
// t_r + duration_t_star t* (solver.end_time stays a hard cap). Without a constraint
// (release_constraint: none, or no velocity constraint at all), t_r = 0: the column
// collapses from its initial state (e.g. regions[].initial_stress: geostatic), as after an
// instantaneous release.
// With column_collapse.at_rest it ends earlier once the deposit is at rest (analysis/at_rest.hpp:
// E_k/E_p0 below a ratio for a hold time, E_p0 the release value below).
//
// Figures (summary.json, top level), at the end of the run:
//   runout_m           L_f: front of the deposit from the back wall, max_p x_p + s_x/2 - x_back
//                      (s_x the initial point spacing along x: a point stands for a box of
//                      that length)
//   runout_normalized  (L_f - L_i) / L_i
//   runout_front_m     the front of the connected deposit: points sorted by x, the front is
//                      the last point before the first gap along x wider than one cell
//                      (material farther than a cell from the rest shares no grid node
//                      interaction with it), + s_x/2 - x_back. Points that left the deposit
//                      (FLIP-like transfers shed single points that slide on) do not set it.
//   runout_front_detached_mass_fraction  share of the mass beyond that gap
//   runout_mass99_m    x - x_back below which 99 % of the mass lies (points sorted by x, the
//                      first whose cumulative mass reaches 0.99): the bulk of the deposit,
//                      which neither a thin tongue one point deep nor a few shed points set
//   final_height_m     H_f: top of the deposit, max_p z_p + s_z/2 - z_base (s_z along z)
//   Ed_over_Ep0_final  E_d / E_p0 with E_p0 the potential energy at release measured from the
//                      base (E_p = sum m |g| (z - z_base)), E_d = E_p0 - E_p - E_k
//   stage1_time_s      t_r; t_star_s; time_over_t_star_final ((t_end - t_r) / t*)
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "analysis/at_rest.hpp"
#include "analysis/column_state.hpp"
#include "particles.hpp"
#include "scene.hpp"

namespace mpmdem::mpm {

class BoundaryConditions;

struct ColumnGeometry {
  double x_back = 0.0;     // back wall (region min x) [m]
  double z_base = 0.0;     // base (region min z) [m]
  double L_i = 0.0;        // initial length [m]
  double H_i = 0.0;        // initial height [m]
  double W = 0.0;          // width (y extent) [m]
  double g = 9.81;         // |gravity| [m/s^2]
  double t_star = 0.0;     // sqrt(H_i / g) [s]
  double spacing_x = 0.0;  // initial point spacing along x [m]
  double spacing_z = 0.0;  // initial point spacing along z [m]
  double cell_size = 0.0;  // grid cell size [m] (the gap that detaches the front)
  int region = 0;          // index of the column region
  int constraint = -1;     // index of the stage-1 constraint, -1 if none (t_r = 0)
};

// Throws SceneError naming the key (SceneError::key) if the scene does not describe a column
// collapse that can happen: gravity along -z; a region (column_collapse.region) on the base
// against the back wall, walls.z_min and walls.x_min not free; the release constraint
// (column_collapse.release_constraint: a name, '' for the first, none for no constraint)
// exists and has a release rule. The scene loader calls it (config/scene_rules.hpp).
ColumnGeometry column_geometry(const Scene& scene);

struct DepositShape {
  double runout_m = 0.0;
  double final_height_m = 0.0;
  double runout_front_m = 0.0;
  double detached_mass_fraction = 0.0;
  double runout_mass99_m = 0.0;
};
DepositShape measure_deposit(const ColumnGeometry& g, const Particles& p);

// Potential energy measured from the column's base.
double potential_energy_above_base(const ColumnGeometry& g, const Particles& p);

// Follows a run: release time, E_p0 at release, snapshot and end times.
class ColumnCollapseMonitor {
 public:
  explicit ColumnCollapseMonitor(const Scene& scene);

  // After every step (and once before the first): notes the release of the stage-1
  // constraint. Returns true when stage 2 started in this call.
  bool observe(double time, const BoundaryConditions& bc, const Particles& p);

  // After every stage-2 step (column_collapse.at_rest): feeds E_k/E_p0 to the at-rest
  // detector. Returns true when the deposit came to rest in this call.
  bool observe_rest(double time, const Particles& p);
  // The at-rest detector (null without column_collapse.at_rest).
  const AtRestDetector* at_rest() const { return rest_ ? &*rest_ : nullptr; }
  // Why stage 2 ended at `time`: "at_rest", "duration" (duration_t_star), or "" (it did not).
  std::string end_reason(double time) const;

  bool released() const { return release_time_.has_value(); }
  std::optional<double> release_time() const { return release_time_; }
  // t_r + duration_t_star t* (infinite before the release).
  double end_time() const;
  // Stage 2 has lasted duration_t_star t*, or the deposit is at rest.
  bool done(double time) const;
  // Snapshots whose time (t_r + k t*) has come since the last call: labels like "t_star_3".
  std::vector<std::string> due_snapshots(double time, double tol);
  // Stage-2 time in units of t* (negative during stage 1).
  double time_over_t_star(double time) const;

  const ColumnGeometry& geometry() const { return g_; }
  // Checkpoint state.
  ColumnState state() const;
  void restore(const ColumnState& s);
  // summary.json's "stop" figures of the at-rest detector (empty without it): the run ended
  // at `time` after `steps` steps.
  std::vector<std::pair<std::string, double>> stop_figures(double time, std::int64_t steps) const;
  // The headline figures for summary.json (see the file comment).
  std::vector<std::pair<std::string, double>> figures(double time, const Particles& p) const;

 private:
  ColumnGeometry g_;
  double duration_t_star_ = 6.0;
  std::vector<double> snapshots_t_star_;
  std::vector<bool> snapshot_done_;
  std::optional<double> release_time_;
  double E_p0_release_ = 0.0;
  std::optional<AtRestDetector> rest_;
};

}  // namespace mpmdem::mpm
