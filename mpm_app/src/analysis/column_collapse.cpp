#include "analysis/column_collapse.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <tuple>
#include <vector>

#include "boundary_conditions.hpp"
#include "energies.hpp"
#include "errors.hpp"
#include "mpmdem/config/schema.hpp"

namespace mpmdem::mpm {

namespace {

std::string text(const Vec3& v) {
  return "[" + config::format_number(v[0]) + ", " + config::format_number(v[1]) + ", " +
         config::format_number(v[2]) + "]";
}

// "'a', 'b'": the names of a list, for "names no entry" messages.
template <class Items>
std::string names_of(const Items& items) {
  std::string s;
  for (const auto& item : items) s += (s.empty() ? "'" : ", '") + item.name + "'";
  return s.empty() ? "none" : s;
}

// The velocity constraint whose release starts stage 2 (-1: none, stage 2 from t = 0).
int release_constraint(const Scene& scene) {
  const std::string& name = scene.column_collapse.release_constraint;
  const auto& cs = scene.constraints;
  if (name == "none") {
    for (std::size_t c = 0; c < cs.size(); ++c) {
      if (cs[c].name == "none") {
        throw SceneError("column_collapse.release_constraint",
                         "'none' is ambiguous: velocity_constraints[" + std::to_string(c) +
                             "] is named none too; rename that constraint");
      }
    }
    return -1;
  }
  for (std::size_t c = 0; c < cs.size(); ++c) {
    if (name.empty() || cs[c].name == name) return static_cast<int>(c);
  }
  if (!name.empty()) {
    throw SceneError("column_collapse.release_constraint",
                     "'" + name +
                         "' names no entry of velocity_constraints[] (names: " + names_of(cs) +
                         "); name one, write '' for the first or none for stage 2 from t = 0");
  }
  return -1;  // no constraint at all: stage 2 from t = 0
}

}  // namespace

ColumnGeometry column_geometry(const Scene& scene) {
  const ColumnCollapseParams& cp = scene.column_collapse;
  ColumnGeometry g;
  const Vec3& grav = scene.solver.gravity;
  if (!(grav[2] < 0.0) || std::abs(grav[0]) > 1e-12 * std::abs(grav[2]) ||
      std::abs(grav[1]) > 1e-12 * std::abs(grav[2])) {
    throw SceneError("solver.gravity", text(grav) +
                                           " does not point along -z, which column_collapse "
                                           "needs (the column stands on the z_min face)");
  }
  g.g = -grav[2];
  g.region = -1;
  for (std::size_t r = 0; r < scene.regions.size(); ++r) {
    if (cp.region.empty() || scene.regions[r].name == cp.region) {
      g.region = static_cast<int>(r);
      break;
    }
  }
  if (g.region < 0) {
    throw SceneError("column_collapse.region",
                     "'" + cp.region + "' names no entry of regions[] (names: " +
                         names_of(scene.regions) + "); name one, or write '' for the first");
  }
  const RegionParams& reg = scene.regions[static_cast<std::size_t>(g.region)];
  g.x_back = reg.min[0];
  g.z_base = reg.min[2];
  g.L_i = reg.max[0] - reg.min[0];
  g.H_i = reg.max[2] - reg.min[2];
  g.W = reg.max[1] - reg.min[1];
  g.t_star = std::sqrt(g.H_i / g.g);
  g.spacing_x = scene.grid.cell_size / reg.points_along(0);
  g.spacing_z = scene.grid.cell_size / reg.points_along(2);
  g.cell_size = scene.grid.cell_size;
  const double tol = 1e-9 * scene.grid.cell_size;
  const std::string reg_key = "regions[" + std::to_string(g.region) + "].min";
  if (std::abs(reg.min[0] - scene.grid.origin[0]) > tol) {
    throw SceneError(reg_key, text(reg.min) + ": the column region '" + reg.name +
                                  "' must touch the back wall, but its min x differs from "
                                  "grid.origin x " +
                                  config::format_number(scene.grid.origin[0]));
  }
  if (std::abs(reg.min[2] - scene.grid.origin[2]) > tol) {
    throw SceneError(reg_key, text(reg.min) + ": the column region '" + reg.name +
                                  "' must stand on the base, but its min z differs from "
                                  "grid.origin z " +
                                  config::format_number(scene.grid.origin[2]));
  }
  // The back wall and the base hold the column: a free face would let it leave the grid.
  for (const auto& [face, index, what] :
       {std::tuple{"x_min", 0, "back wall"}, std::tuple{"z_min", 4, "base"}}) {
    if (scene.walls[static_cast<std::size_t>(index)].type == WallType::kFree) {
      throw SceneError(std::string("walls.") + face,
                       std::string("is free, but it is the column's ") + what +
                           " (column_collapse): make it slip, fixed or friction");
    }
  }
  g.constraint = release_constraint(scene);
  if (g.constraint >= 0) {
    const VelocityConstraintParams& c = scene.constraints[static_cast<std::size_t>(g.constraint)];
    if (!c.release_time && !c.release_kinetic_ratio) {
      throw SceneError("velocity_constraints[" + std::to_string(g.constraint) + "]",
                       "'" + c.name +
                           "' holds the column in stage 1 (column_collapse.release_constraint) "
                           "but has neither release_time nor release_kinetic_ratio: it is never "
                           "released, so the column would never collapse; give it one, or set "
                           "column_collapse.release_constraint: none for stage 2 from t = 0");
    }
  }
  return g;
}

DepositShape measure_deposit(const ColumnGeometry& g, const Particles& p) {
  DepositShape d;
  if (p.size() == 0) return d;
  std::vector<std::size_t> order(p.size());
  for (std::size_t q = 0; q < order.size(); ++q) order[q] = q;
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return p.x[a][0] < p.x[b][0]; });
  double z_max = -std::numeric_limits<double>::infinity();
  for (std::size_t q = 0; q < p.size(); ++q) z_max = std::max(z_max, p.x[q][2]);
  // The connected front: the last point before the first gap wider than a cell.
  std::size_t front = order.size() - 1;
  for (std::size_t k = 1; k < order.size(); ++k) {
    if (p.x[order[k]][0] - p.x[order[k - 1]][0] > g.cell_size) {
      front = k - 1;
      break;
    }
  }
  double mass = 0.0, detached = 0.0;
  for (std::size_t k = 0; k < order.size(); ++k) {
    mass += p.m[order[k]];
    if (k > front) detached += p.m[order[k]];
  }
  double cumulative = 0.0;
  for (std::size_t k = 0; k < order.size(); ++k) {
    cumulative += p.m[order[k]];
    if (cumulative >= 0.99 * mass || k + 1 == order.size()) {
      d.runout_mass99_m = p.x[order[k]][0] - g.x_back;
      break;
    }
  }
  d.runout_m = p.x[order.back()][0] + 0.5 * g.spacing_x - g.x_back;
  d.runout_front_m = p.x[order[front]][0] + 0.5 * g.spacing_x - g.x_back;
  d.detached_mass_fraction = mass > 0.0 ? detached / mass : 0.0;
  d.final_height_m = z_max + 0.5 * g.spacing_z - g.z_base;
  return d;
}

double potential_energy_above_base(const ColumnGeometry& g, const Particles& p) {
  double mass = 0.0;
  for (double m : p.m) mass += m;
  return compute_energies(p, Vec3(0.0, 0.0, -g.g)).E_p - mass * g.g * g.z_base;
}

ColumnCollapseMonitor::ColumnCollapseMonitor(const Scene& scene)
    : g_(column_geometry(scene)),
      duration_t_star_(scene.column_collapse.duration_t_star),
      snapshots_t_star_(scene.column_collapse.snapshots_t_star),
      snapshot_done_(snapshots_t_star_.size(), false) {
  const ColumnCollapseParams& cp = scene.column_collapse;
  if (cp.at_rest) {
    rest_.emplace(cp.at_rest_kinetic_ratio, cp.at_rest_hold_t_star * g_.t_star,
                  cp.at_rest_min_t_star * g_.t_star);
  }
}

bool ColumnCollapseMonitor::observe_rest(double time, const Particles& p) {
  if (!rest_ || !release_time_ || rest_->at_rest()) return false;
  const double E_k = kinetic_energy(p);
  const double ratio =
      E_p0_release_ > 0.0 ? E_k / E_p0_release_ : std::numeric_limits<double>::quiet_NaN();
  return rest_->update(time - *release_time_, ratio);
}

std::string ColumnCollapseMonitor::end_reason(double time) const {
  if (rest_ && rest_->at_rest()) return "at_rest";
  if (release_time_ && time >= *release_time_ + duration_t_star_ * g_.t_star * (1.0 - 1e-12))
    return "duration";
  return "";
}

std::vector<std::pair<std::string, double>> ColumnCollapseMonitor::stop_figures(
    double time, std::int64_t steps) const {
  if (!rest_) return {};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const bool at_rest = rest_->at_rest();
  const double t_star = g_.t_star;
  return {{"at_rest", at_rest ? 1.0 : 0.0},
          {"time_s", at_rest ? time : nan},
          {"step", at_rest ? static_cast<double>(steps) : nan},
          {"time_over_t_star", at_rest ? *rest_->at_rest_time() / t_star : nan},
          {"quiet_since_t_star", rest_->quiet_since() ? *rest_->quiet_since() / t_star : nan},
          {"kinetic_ratio", rest_->kinetic_ratio()},
          {"hold_t_star", rest_->hold_time() / t_star},
          {"min_t_star", rest_->earliest_time() / t_star}};
}

bool ColumnCollapseMonitor::observe(double time, const BoundaryConditions& bc, const Particles& p) {
  if (release_time_) return false;
  if (g_.constraint >= 0 && bc.constraint_active(static_cast<std::size_t>(g_.constraint))) {
    return false;
  }
  release_time_ = time;
  E_p0_release_ = potential_energy_above_base(g_, p);
  return true;
}

ColumnState ColumnCollapseMonitor::state() const {
  ColumnState s;
  s.release_time = release_time_;
  s.E_p0_release = E_p0_release_;
  s.snapshots_done.assign(snapshot_done_.begin(), snapshot_done_.end());
  if (rest_) {
    s.rest_quiet_since = rest_->quiet_since();
    s.rest_time = rest_->at_rest_time();
  }
  return s;
}

void ColumnCollapseMonitor::restore(const ColumnState& s) {
  release_time_ = s.release_time;
  E_p0_release_ = s.E_p0_release;
  for (std::size_t k = 0; k < snapshot_done_.size() && k < s.snapshots_done.size(); ++k)
    snapshot_done_[k] = s.snapshots_done[k] != 0;
  // A checkpoint of a run without column_collapse.at_rest has no window: the wait starts anew.
  if (rest_) rest_->restore(s.rest_quiet_since, s.rest_time);
}

double ColumnCollapseMonitor::end_time() const {
  return release_time_ ? *release_time_ + duration_t_star_ * g_.t_star
                       : std::numeric_limits<double>::infinity();
}

bool ColumnCollapseMonitor::done(double time) const {
  return !end_reason(time).empty();
}

std::vector<std::string> ColumnCollapseMonitor::due_snapshots(double time, double tol) {
  std::vector<std::string> due;
  if (!release_time_) return due;
  for (std::size_t k = 0; k < snapshots_t_star_.size(); ++k) {
    if (snapshot_done_[k]) continue;
    if (time + tol >= *release_time_ + snapshots_t_star_[k] * g_.t_star) {
      snapshot_done_[k] = true;
      char label[32];
      std::snprintf(label, sizeof label, "t_star_%g", snapshots_t_star_[k]);
      due.emplace_back(label);
    }
  }
  return due;
}

double ColumnCollapseMonitor::time_over_t_star(double time) const {
  return (time - release_time_.value_or(time)) / g_.t_star;
}

std::vector<std::pair<std::string, double>> ColumnCollapseMonitor::figures(
    double time, const Particles& p) const {
  const DepositShape d = measure_deposit(g_, p);
  const double E_k = kinetic_energy(p);
  const double E_p = potential_energy_above_base(g_, p);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double E_d = E_p0_release_ - E_p - E_k;
  return {{"t_star_s", g_.t_star},
          {"initial_height_m", g_.H_i},
          {"initial_length_m", g_.L_i},
          {"aspect_ratio", g_.H_i / g_.L_i},
          {"stage1_time_s", release_time_.value_or(nan)},
          {"time_over_t_star_final", release_time_ ? time_over_t_star(time) : nan},
          {"runout_m", d.runout_m},
          {"runout_normalized", (d.runout_m - g_.L_i) / g_.L_i},
          {"runout_front_m", d.runout_front_m},
          {"runout_front_detached_mass_fraction", d.detached_mass_fraction},
          {"runout_mass99_m", d.runout_mass99_m},
          {"final_height_m", d.final_height_m},
          {"final_height_over_initial", d.final_height_m / g_.H_i},
          {"Ep0_release_J", release_time_ ? E_p0_release_ : nan},
          {"Ed_over_Ep0_final", release_time_ && E_p0_release_ > 0 ? E_d / E_p0_release_ : nan},
          {"Ek_over_Ep0_final", release_time_ && E_p0_release_ > 0 ? E_k / E_p0_release_ : nan}};
}

}  // namespace mpmdem::mpm
