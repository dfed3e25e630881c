// Rules of a scene between its sections, one function per rule, checked on the loaded Scene
// when the file is loaded (load_scene calls check_scene_rules() last, so mpm_app
// --check-config and scripts/run refuse the scene before anything runs). Each throws
// config::ConfigError naming the key, its value, the file and the line, and what to change.
// Rules of one section stay with its loader (config/scene_loader.cpp); the DEM backends'
// sections of `coupling:` and their rules are dem_app's (`dem_app --check-config`).
#pragma once

#include "mpmdem/config/schema.hpp"
#include "scene.hpp"

namespace mpmdem::mpm {

// All of the rules below.
void check_scene_rules(const config::Config& cfg, const Scene& scene);

// velocity_constraints[].name are unique (column_collapse.release_constraint names one).
void check_constraint_names(const config::Config& cfg, const Scene& scene);
// A constraint's release can happen within the run: release_min_time < release_time when
// both rules are given, and the earliest release before solver.end_time.
void check_release_schedule(const config::Config& cfg, const Scene& scene);
// solver.dt_fixed < solver.end_time.
void check_time_step_schedule(const config::Config& cfg, const Scene& scene);
// column_collapse: the rules of column_geometry() (analysis/column_collapse.hpp): gravity,
// the region and release constraint it names, the walls that hold the column, a release.
void check_column_collapse(const config::Config& cfg, const Scene& scene);
// verification.kind: what the analytic solution needs of the scene
// (verification/elastic_column.hpp).
void check_verification(const config::Config& cfg, const Scene& scene);

}  // namespace mpmdem::mpm
