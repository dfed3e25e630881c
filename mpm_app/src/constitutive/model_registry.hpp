// The registry of local constitutive models: each one, registered by name from its own
// source file, brings its scene keys (constitutive.<name>), how to read them into
// ConstitutiveParams and how to make its provider. The rest of mpm_app asks only whether the
// model is remote (ConstitutiveParams::is_remote()) and, for a local one, asks the registry.
// Adding a model: docs/add_a_model.md.
//
// Registration is by a namespace-scope initialiser in the model's file:
//   const bool registered = register_local_model({"my_model", "one-line summary", ...});
// The model files must be linked whole, not picked from an archive (which would drop a file
// nothing references): mpm_core is an OBJECT library for this (mpm_app/CMakeLists.txt).
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "constitutive/provider.hpp"
#include "mpmdem/config/schema.hpp"
#include "scene.hpp"

namespace mpmdem::mpm {

class Solver;

using Figures = std::vector<std::pair<std::string, double>>;

struct LocalModel {
  // The value of constitutive.model, and the section constitutive.<name> of its parameters.
  std::string name;
  // One line: mpm_app --list-models, and the doc of the section constitutive.<name>.
  std::string summary;
  // Declares the keys of the section (section = "constitutive.<name>"; the section's map key
  // itself is declared by the registry).
  void (*add_keys)(config::Schema& schema, const std::string& section) = nullptr;
  // Reads the section (present in the file) into params: youngs_modulus and poisson_ratio
  // (the elastic moduli: energy budget, verification), the model's own parameters (a
  // struct derived from ModelParams, in params.own), and the checks that involve several
  // keys (cfg.fail names key, value, file and line).
  void (*load)(const config::Config& cfg, const std::string& section,
               ConstitutiveParams& params) = nullptr;
  // The provider for a run (throws std::invalid_argument for parameters it cannot use).
  std::unique_ptr<ConstitutiveProvider> (*make)(const ConstitutiveParams& params) = nullptr;
  // Optional: the model's figures for summary.json's analysis at the end of a run.
  Figures (*figures)(const ConstitutiveParams& params, const Solver& solver) = nullptr;
};

// Adds a model (at static initialisation: see the file comment). Returns true, for the
// initialiser. A name registered twice, "remote", an empty name or a missing hook is a
// programming error: std::logic_error.
bool register_local_model(LocalModel model);
// Every registered local model, by name.
std::vector<const LocalModel*> local_models();
// The model of that name, or nullptr.
const LocalModel* find_local_model(const std::string& name);
// The model of that name; std::invalid_argument naming the registered ones if there is none.
const LocalModel& local_model(const std::string& name);
// "drucker_prager, linear_elastic" (by name).
std::string local_model_names();
// The one-line summary of the remote model (mpm_app --list-models).
const char* remote_model_summary();

// Helpers for a model's hooks: <section>.youngs_modulus (> 0) and <section>.poisson_ratio
// (in [0, 0.5)), both required, and reading them into params.
void add_elastic_moduli_keys(config::Schema& schema, const std::string& section);
void load_elastic_moduli(const config::Config& cfg, const std::string& section,
                         ConstitutiveParams& params);

// constitutive.model (a registered name or remote) and every local model's section.
void add_constitutive_model_keys(config::Schema& schema);

}  // namespace mpmdem::mpm
