// Rules of a scene between its sections: see scene_rules.hpp.
#include "config/scene_rules.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "analysis/column_collapse.hpp"
#include "errors.hpp"
#include "verification/elastic_column.hpp"

namespace mpmdem::mpm {

namespace {

using config::format_number;

// Runs a rule that lives with the code it protects and throws a SceneError naming a key;
// reports it as a ConfigError with the key's file and line.
template <class Rule>
void at_key(const config::Config& cfg, Rule rule) {
  try {
    rule();
  } catch (const SceneError& e) {
    if (e.key().empty()) throw;
    cfg.fail(e.key(), e.detail());
  }
}

std::string item(std::size_t i) {
  return "velocity_constraints[" + std::to_string(i) + "]";
}

}  // namespace

void check_constraint_names(const config::Config& cfg, const Scene& scene) {
  const auto& cs = scene.constraints;
  for (std::size_t i = 0; i < cs.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (cs[j].name == cs[i].name) {
        cfg.fail(item(i) + ".name", "'" + cs[i].name + "' is used by " + item(j) +
                                        " too; names must be unique "
                                        "(column_collapse.release_constraint names one)");
      }
    }
  }
}

void check_release_schedule(const config::Config& cfg, const Scene& scene) {
  const double end = scene.solver.end_time;
  const auto& cs = scene.constraints;
  for (std::size_t i = 0; i < cs.size(); ++i) {
    const VelocityConstraintParams& c = cs[i];
    if (c.release_time && c.release_kinetic_ratio && !(c.release_min_time < *c.release_time)) {
      cfg.fail(item(i) + ".release_min_time",
               format_number(c.release_min_time) + " is not below release_time " +
                   format_number(*c.release_time) +
                   ": release_time always comes first, so release_kinetic_ratio could never "
                   "release the constraint; lower release_min_time, or drop the ratio");
    }
    double earliest = std::numeric_limits<double>::infinity();
    std::string key;
    if (c.release_time) {
      earliest = *c.release_time;
      key = "release_time";
    }
    if (c.release_kinetic_ratio && c.release_min_time < earliest) {
      earliest = c.release_min_time;
      key = "release_min_time";
    }
    if (!key.empty() && earliest >= end) {
      cfg.fail(item(i) + "." + key,
               format_number(earliest) + " is not before solver.end_time " + format_number(end) +
                   ": the constraint '" + c.name +
                   "' could never be released within the run; release it earlier, lengthen "
                   "the run, or drop its release keys to hold it for the whole run");
    }
  }
}

void check_time_step_schedule(const config::Config& cfg, const Scene& scene) {
  const double dt = scene.solver.dt_fixed, end = scene.solver.end_time;
  if (dt > 0.0 && dt >= end) {
    cfg.fail("solver.dt_fixed", format_number(dt) + " is not below solver.end_time " +
                                    format_number(end) +
                                    ": the run would be one step past its end; lower dt_fixed "
                                    "or lengthen the run");
  }
}

void check_column_collapse(const config::Config& cfg, const Scene& scene) {
  if (!scene.column_collapse.enabled) return;
  at_key(cfg, [&] { (void)column_geometry(scene); });
}

void check_verification(const config::Config& cfg, const Scene& scene) {
  switch (scene.verification.kind) {
    case VerificationKind::kElasticColumn:
      at_key(cfg, [&] { check_elastic_column_scene(scene); });
      return;
    case VerificationKind::kBarVibration:
      at_key(cfg, [&] { (void)scene_elastic_moduli(scene); });
      return;
    case VerificationKind::kNone:
      return;
  }
}

void check_scene_rules(const config::Config& cfg, const Scene& scene) {
  check_constraint_names(cfg, scene);
  check_release_schedule(cfg, scene);
  check_time_step_schedule(cfg, scene);
  check_column_collapse(cfg, scene);
  check_verification(cfg, scene);
}

}  // namespace mpmdem::mpm
