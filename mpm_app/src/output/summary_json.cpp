#include "output/summary_json.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "output/run_directory.hpp"

namespace mpmdem::mpm {

namespace {

std::string quote(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\r':
        out += "\\r";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(c));
          out += buf;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

std::string number(double v) {
  if (!std::isfinite(v)) return "null";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

// Writes `"key": value` lines with commas between them.
class ObjectWriter {
 public:
  ObjectWriter(std::ostringstream& out, int indent) : out_(out), pad_(indent, ' ') {}
  void raw(const std::string& key, const std::string& value) {
    out_ << (first_ ? "" : ",\n") << pad_ << quote(key) << ": " << value;
    first_ = false;
  }
  void str(const std::string& key, const std::string& value) { raw(key, quote(value)); }
  void num(const std::string& key, double value) { raw(key, number(value)); }
  void integer(const std::string& key, long long value) { raw(key, std::to_string(value)); }

 private:
  std::ostringstream& out_;
  std::string pad_;
  bool first_ = true;
};

// A nested object {"<tag>": "<name>", figures...} at the second indentation level (without
// the tag when `tag` is null).
std::string tagged_object(const char* tag, const std::string& name,
                          const std::vector<std::pair<std::string, double>>& figures) {
  std::ostringstream inner;
  inner << "{\n";
  ObjectWriter v(inner, 4);
  if (tag != nullptr) v.str(tag, name);
  for (const auto& [key, value] : figures) v.num(key, value);
  inner << "\n  }";
  return inner.str();
}

std::string peer_fault_object(const PeerFault& f) {
  std::ostringstream inner;
  inner << "{\n";
  ObjectWriter v(inner, 4);
  v.str("kind", f.kind);
  v.integer("step", f.step);
  std::string ranks = "[", hosts = "[";
  for (std::size_t i = 0; i < f.ranks.size(); ++i) {
    ranks += (i ? ", " : "") + std::to_string(f.ranks[i]);
    hosts += (i ? ", " : "") + quote(i < f.hosts.size() ? f.hosts[i] : "");
  }
  v.raw("ranks", ranks + "]");
  v.raw("hosts", hosts + "]");
  v.raw("exact", f.exact ? "true" : "false");
  v.str("checkpoint", f.checkpoint);
  v.num("wall_time_at_checkpoint_s", f.wall_time_at_checkpoint_s);
  inner << "\n  }";
  return inner.str();
}

}  // namespace

std::string to_json(const RunSummary& s) {
  std::ostringstream out;
  out << "{\n";
  ObjectWriter w(out, 2);
  w.str("status", s.status);
  if (!s.error.empty()) w.str("error", s.error);
  w.str("scene", s.scene);
  w.str("config_file", s.config_file);
  w.str("run_directory", s.run_directory);
  w.str("model", s.model);
  w.str("program_version", s.program_version);
  w.num("wall_time_s", s.wall_time_s);
  w.num("step_wall_time_s", s.step_wall_time_s);
  w.num("step_cpu_time_s", s.step_cpu_time_s);
  w.integer("steps", s.steps);
  // A resumed run: the checkpoint's step, and the steps this process ran after it.
  if (s.resumed_from_step >= 0) {
    w.integer("resumed_from_step", s.resumed_from_step);
    w.integer("steps_after_resume", s.steps_this_run);
  }
  w.integer("n_material_points", static_cast<long long>(s.n_material_points));
  w.integer("removed_points", static_cast<long long>(s.removed_points));
  w.integer("threads", s.threads);
  const double point_steps =
      static_cast<double>(s.steps) * static_cast<double>(s.n_material_points);
  w.num("ns_per_point_step", point_steps > 0.0 ? 1e9 * s.step_wall_time_s / point_steps : 0.0);
  w.num("cpu_ns_per_point_step", point_steps > 0.0 ? 1e9 * s.step_cpu_time_s / point_steps : 0.0);
  w.num("time_s", s.time_s);
  w.num("end_time_s", s.end_time_s);
  w.num("dt_min_s", s.dt_min_s);
  w.num("dt_max_s", s.dt_max_s);
  w.num("mass_initial_kg", s.mass_initial_kg);
  w.num("mass_final_kg", s.mass_final_kg);
  w.num("mass_grid_kg", s.mass_grid_kg);
  w.num("E_p0_J", s.E_p0_J);
  w.num("E_p_J", s.E_p_J);
  w.num("E_k_J", s.E_k_J);
  const double E_d = s.E_p0_J - s.E_p_J - s.E_k_J;
  w.num("E_d_J", E_d);
  w.num("E_d_over_E_p0", s.E_p0_J != 0.0 ? E_d / s.E_p0_J : 0.0);
  for (const auto& [key, value] : s.analysis) w.num(key, value);
  const double released = s.E_p0_J + s.E_k0_J - s.E_p_J - s.E_k_J;
  const double E_err = released - s.W_int_J - s.W_damp_J - s.W_bc_J;
  const auto share = [&](double W) {
    return released != 0.0 ? W / released : std::numeric_limits<double>::quiet_NaN();
  };
  w.raw("energy_budget", tagged_object(nullptr, "",
                                       {{"released_J", released},
                                        {"W_int_J", s.W_int_J},
                                        {"W_bc_J", s.W_bc_J},
                                        {"W_damp_J", s.W_damp_J},
                                        {"E_err_J", E_err},
                                        {"E_err_transfer_J", s.W_transfer_J},
                                        {"E_err_transfer_walls_J", s.W_transfer_walls_J},
                                        {"E_err_other_J", E_err - s.W_transfer_J},
                                        {"W_int_share", share(s.W_int_J)},
                                        {"W_bc_share", share(s.W_bc_J)},
                                        {"W_damp_share", share(s.W_damp_J)},
                                        {"E_err_share", share(E_err)},
                                        {"E_err_transfer_share", share(s.W_transfer_J)},
                                        {"E_err_transfer_walls_share", share(s.W_transfer_walls_J)},
                                        {"E_err_other_share", share(E_err - s.W_transfer_J)}}));
  if (s.peer_fault) w.raw("peer_fault", peer_fault_object(*s.peer_fault));
  if (!s.stop_reason.empty()) w.raw("stop", tagged_object("reason", s.stop_reason, s.stop));
  if (!s.verification_kind.empty()) {
    w.raw("verification", tagged_object("kind", s.verification_kind, s.verification));
    // The error figures also at top level, where scripts look for headline numbers.
    for (const auto& [key, value] : s.verification) w.num(key, value);
  }
  out << "\n}\n";
  return out.str();
}

void write_summary(const std::string& path, const RunSummary& s) {
  write_file_atomic(path, to_json(s));
}

}  // namespace mpmdem::mpm
