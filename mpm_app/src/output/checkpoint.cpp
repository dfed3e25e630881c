#include "output/checkpoint.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "output/hdf5_io.hpp"
#include "output/run_directory.hpp"

namespace mpmdem::mpm {

namespace fs = std::filesystem;

namespace {

constexpr const char* kComplete = "COMPLETE";

std::vector<std::int32_t> to_int32(const std::vector<char>& v) {
  return std::vector<std::int32_t>(v.begin(), v.end());
}
std::vector<char> to_char(const std::vector<std::int32_t>& v) {
  std::vector<char> out;
  for (std::int32_t x : v) out.push_back(x != 0 ? 1 : 0);
  return out;
}

std::vector<std::string> checkpoints(const std::string& run_dir, bool complete_only) {
  std::vector<std::string> out;
  const fs::path root = fs::path(run_dir) / "checkpoints";
  std::error_code ec;
  if (!fs::is_directory(root, ec)) return out;
  for (const auto& e : fs::directory_iterator(root, ec)) {
    const std::string name = e.path().filename().string();
    if (!e.is_directory() || name.rfind("step_", 0) != 0) continue;
    if (complete_only && !fs::exists(e.path() / kComplete)) continue;
    out.push_back(e.path().string());
  }
  std::sort(out.begin(), out.end());  // step_<zero-padded>: lexical = numerical order
  return out;
}

}  // namespace

std::string checkpoint_directory(const std::string& run_dir, std::int64_t step) {
  char name[32];
  std::snprintf(name, sizeof name, "step_%09lld", static_cast<long long>(step));
  return (fs::path(run_dir) / "checkpoints" / name).string();
}

std::string fault_checkpoint_directory(const std::string& run_dir, std::int64_t step) {
  char name[40];
  std::snprintf(name, sizeof name, "fault_step_%09lld", static_cast<long long>(step));
  return (fs::path(run_dir) / "checkpoints" / name).string();
}

void write_mpm_checkpoint(const std::string& dir, const SolverState& s, const DriverState& d) {
  fs::create_directories(dir);
  const std::string path = dir + "/mpm.h5";
  const std::string tmp = path + ".tmp";
  const Particles& p = s.particles;
  const hsize_t n = p.size();
  {
    h5::File f = h5::File::create(tmp);
    f.write("id", p.id);
    f.write("region", std::vector<std::int32_t>(p.region.begin(), p.region.end()));
    f.write("m", p.m, {n});
    f.write("V", p.V, {n});
    f.write("V0", p.V0, {n});
    f.write("x", h5::flatten(p.x), {n, 3});
    f.write("x0", h5::flatten(p.x0), {n, 3});
    f.write("v", h5::flatten(p.v), {n, 3});
    f.write("C", h5::flatten(p.C), {n, 3, 3});
    f.write("F", h5::flatten(p.F), {n, 3, 3});
    f.write("dF", h5::flatten(p.dF), {n, 3, 3});
    f.write("sigma", h5::flatten(p.sigma), {n, 3, 3});
    f.write("stiffness", p.stiffness, {n});
    f.write("strain_energy", p.strain_energy, {n});
    if (p.rotation.size() == n) f.write("rotation", h5::flatten(p.rotation), {n, 3});
    if (p.porosity.size() == n) f.write("porosity", p.porosity, {n});
    if (p.coordination.size() == n) f.write("coordination", p.coordination, {n});
    if (p.unbalanced_force.size() == n) f.write("unbalanced_force", p.unbalanced_force, {n});
    f.write("status", state_codes(p.state));
    f.write("slot", std::vector<std::int64_t>(s.slot.begin(), s.slot.end()));
    f.write("constraint_active", to_int32(s.constraint_active));
    f.write("frame_times", d.frame_times, {d.frame_times.size()});
    f.write("provider_state", d.provider_state, {d.provider_state.size()});
    f.write("snapshots_done", to_int32(d.column.snapshots_done));
    f.attribute("n_slots", static_cast<std::int64_t>(s.n_slots));
    f.attribute("time", s.time);
    f.attribute("dt", s.dt);
    f.attribute("dt_next", s.dt_next);
    f.attribute("E_p0", s.E_p0);
    f.attribute("E_k0", s.budget.E_k0);
    f.attribute("W_int", s.budget.W_int);
    f.attribute("W_damp", s.budget.W_damp);
    f.attribute("W_bc", s.budget.W_bc);
    f.attribute("W_transfer", s.budget.W_transfer);
    f.attribute("W_transfer_walls", s.budget.W_transfer_walls);
    f.attribute("step", s.step);
    f.attribute("no_contact_updates", s.no_contact_updates);
    f.attribute("removed", static_cast<std::int64_t>(s.removed));
    f.attribute("next_frame", d.next_frame);
    f.attribute("next_energy", d.next_energy);
    f.attribute("last_frame_step", d.last_frame_step);
    f.attribute("last_energy_step", d.last_energy_step);
    f.attribute("released", static_cast<std::int64_t>(d.column.release_time.has_value()));
    f.attribute("release_time", d.column.release_time.value_or(0.0));
    f.attribute("E_p0_release", d.column.E_p0_release);
    f.attribute("rest_quiet", static_cast<std::int64_t>(d.column.rest_quiet_since.has_value()));
    f.attribute("rest_quiet_since", d.column.rest_quiet_since.value_or(0.0));
    f.attribute("rest_reached", static_cast<std::int64_t>(d.column.rest_time.has_value()));
    f.attribute("rest_time", d.column.rest_time.value_or(0.0));
    f.attribute("step_wall_time_s", d.step_wall_time_s);
    f.attribute("step_cpu_time_s", d.step_cpu_time_s);
    f.attribute("wall_time_s", d.wall_time_s);
    f.attribute("dt_min_s", d.dt_min_s);
    f.attribute("dt_max_s", d.dt_max_s);
    f.attribute("mass_initial_kg", d.mass_initial_kg);
    f.attribute("rve_particles", d.rve_particles);
    f.flush();
  }
  commit_file(tmp, path);
}

void commit_checkpoint(const std::string& run_dir, const std::string& dir, int keep) {
  write_file_atomic(dir + "/" + kComplete, "complete\n");
  const auto all = checkpoints(run_dir, false);
  const auto complete = checkpoints(run_dir, true);
  const std::size_t k = static_cast<std::size_t>(std::max(keep, 1));
  for (const std::string& c : all) {
    const auto it = std::find(complete.begin(), complete.end(), c);
    const bool old_complete = it != complete.end() && complete.end() - it > static_cast<long>(k);
    const bool stale_incomplete = it == complete.end() && c < dir;
    if (old_complete || stale_incomplete) {
      std::error_code ec;
      fs::remove_all(c, ec);
    }
  }
}

std::string latest_checkpoint(const std::string& run_dir) {
  const auto c = checkpoints(run_dir, true);
  return c.empty() ? std::string() : c.back();
}

void read_mpm_checkpoint(const std::string& dir, SolverState& s, DriverState& d) {
  if (!fs::exists(fs::path(dir) / kComplete)) {
    throw std::runtime_error("checkpoint " + dir + " is not complete (no " + kComplete +
                             " marker): the run stopped while writing it; resume from an "
                             "older one");
  }
  const h5::File f = h5::File::open(dir + "/mpm.h5");
  Particles& p = s.particles;
  p.id = f.read_int64("id");
  const std::size_t n = p.id.size();
  const auto region = f.read_int32("region");
  p.region.assign(region.begin(), region.end());
  p.m = f.read_doubles("m", n);
  p.V = f.read_doubles("V", n);
  p.V0 = f.read_doubles("V0", n);
  p.x = h5::unflatten<3, 1>(f.read_doubles("x", 3 * n), n);
  p.x0 = h5::unflatten<3, 1>(f.read_doubles("x0", 3 * n), n);
  p.v = h5::unflatten<3, 1>(f.read_doubles("v", 3 * n), n);
  if (!f.has("C")) {
    throw std::runtime_error("checkpoint " + dir +
                             " has no APIC affine matrices (C): it was written by an older "
                             "mpm_app; rerun from the start");
  }
  p.C = h5::unflatten<3, 3>(f.read_doubles("C", 9 * n), n);
  p.F = h5::unflatten<3, 3>(f.read_doubles("F", 9 * n), n);
  p.dF = h5::unflatten<3, 3>(f.read_doubles("dF", 9 * n), n);
  p.sigma = h5::unflatten<3, 3>(f.read_doubles("sigma", 9 * n), n);
  p.stiffness = f.read_doubles("stiffness", n);
  p.strain_energy = f.read_doubles("strain_energy", n);
  if (f.has("rotation")) p.rotation = h5::unflatten<3, 1>(f.read_doubles("rotation", 3 * n), n);
  if (f.has("porosity")) p.porosity = f.read_doubles("porosity", n);
  if (f.has("coordination")) p.coordination = f.read_doubles("coordination", n);
  if (f.has("unbalanced_force")) p.unbalanced_force = f.read_doubles("unbalanced_force", n);
  const auto state = f.read_int32("status");
  try {
    p.state = states_from_codes(state);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error("checkpoint " + dir + "/mpm.h5: " + e.what());
  }
  const auto slot = f.read_int64("slot");
  s.slot.assign(slot.begin(), slot.end());
  s.constraint_active = to_char(f.read_int32("constraint_active"));
  if (p.region.size() != n || p.state.size() != n || s.slot.size() != n) {
    throw std::runtime_error("checkpoint " + dir + "/mpm.h5 is inconsistent (field sizes)");
  }
  s.n_slots = static_cast<std::size_t>(f.attribute_int64("n_slots"));
  s.time = f.attribute_double("time");
  s.dt = f.attribute_double("dt");
  s.dt_next = f.attribute_double("dt_next");
  s.E_p0 = f.attribute_double("E_p0");
  s.budget.E_k0 = f.attribute_double("E_k0");
  s.budget.W_int = f.attribute_double("W_int");
  s.budget.W_damp = f.attribute_double("W_damp");
  s.budget.W_bc = f.attribute_double("W_bc");
  // Checkpoints written before W_transfer was measured: the resumed run counts from here.
  s.budget.W_transfer = f.has_attribute("W_transfer") ? f.attribute_double("W_transfer") : 0.0;
  s.budget.W_transfer_walls =
      f.has_attribute("W_transfer_walls") ? f.attribute_double("W_transfer_walls") : 0.0;
  s.step = f.attribute_int64("step");
  s.no_contact_updates = f.attribute_int64("no_contact_updates");
  s.removed = static_cast<std::size_t>(f.attribute_int64("removed"));
  d.frame_times = f.read_doubles("frame_times");
  if (f.has("provider_state")) d.provider_state = f.read_doubles("provider_state");
  d.next_frame = f.attribute_double("next_frame");
  d.next_energy = f.attribute_double("next_energy");
  d.last_frame_step = f.attribute_int64("last_frame_step");
  d.last_energy_step = f.attribute_int64("last_energy_step");
  if (f.attribute_int64("released") != 0)
    d.column.release_time = f.attribute_double("release_time");
  d.column.E_p0_release = f.attribute_double("E_p0_release");
  // Checkpoints from before column_collapse.at_rest have no at-rest state: none yet.
  if (f.has_attribute("rest_quiet") && f.attribute_int64("rest_quiet") != 0)
    d.column.rest_quiet_since = f.attribute_double("rest_quiet_since");
  if (f.has_attribute("rest_reached") && f.attribute_int64("rest_reached") != 0)
    d.column.rest_time = f.attribute_double("rest_time");
  d.column.snapshots_done = to_char(f.read_int32("snapshots_done"));
  d.step_wall_time_s = f.attribute_double("step_wall_time_s");
  d.step_cpu_time_s = f.attribute_double("step_cpu_time_s");
  d.wall_time_s = f.attribute_double("wall_time_s");
  d.dt_min_s = f.attribute_double("dt_min_s");
  d.dt_max_s = f.attribute_double("dt_max_s");
  d.mass_initial_kg = f.attribute_double("mass_initial_kg");
  d.rve_particles = f.attribute_int64("rve_particles");
}

}  // namespace mpmdem::mpm
