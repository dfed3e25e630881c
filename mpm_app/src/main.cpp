// mpm_app: the MPM side of mpmdem.
//   mpm_app SCENE.yaml [--out DIR] [--threads T] [--force]   run a scene
//   mpm_app SCENE.yaml ... --max-steps N                     stop after N steps (benchmarks)
//   mpm_app SCENE.yaml --out RUN --resume CHECKPOINT|latest   continue a checkpointed run
//   mpm_app SCENE.yaml ... --dem-jobs K        join K dem_app jobs (one per DEM node)
//   mpm_app --check-config FILE                            validate a scene, count points
//   mpm_app --print-config-reference                       every key: type, default, unit
//   mpm_app --print-model FILE                 the scene's constitutive model
//   mpm_app --list-models                      the constitutive models (local ones + remote)
//   mpm_app --version
// Exit codes: 0 ok, 2 config/usage/output-directory error, 3 handshake refused, 4 failed,
// 130 interrupted (see run_driver.hpp).
#include <mpi.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <iomanip>
#include <iostream>
#include <optional>
#include <string>

#include "config/scene_loader.hpp"
#include "constitutive/model_registry.hpp"
#include "errors.hpp"
#include "mpmdem/connection.hpp"
#include "particle_init.hpp"
#include "run_driver.hpp"
#include "run_status.hpp"

namespace {

using namespace mpmdem::mpm;

const int kExitConfig = exit_code(RunStatus::kConfigError);

int check_config(const std::string& file) {
  try {
    const Scene scene = load_scene(file);
    const Particles particles = generate_particles(scene);
    std::cout << "OK: " << file << " (" << scene.regions.size() << " regions, " << particles.size()
              << " points)" << std::endl;
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << std::endl;
    return kExitConfig;
  }
}

int print_model(const std::string& file) {
  try {
    const Scene scene = load_scene(file);
    std::cout << scene.constitutive.model << std::endl;
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << std::endl;
    return kExitConfig;
  }
}

// One line per model: the local ones (the registry), then remote.
int list_models() {
  std::size_t width = std::string(kRemoteModel).size();
  for (const LocalModel* m : local_models()) width = std::max(width, m->name.size());
  for (const LocalModel* m : local_models()) {
    std::cout << std::left << std::setw(static_cast<int>(width)) << m->name
              << "  local: " << m->summary << "\n";
  }
  std::cout << std::left << std::setw(static_cast<int>(width)) << kRemoteModel << "  "
            << remote_model_summary() << std::endl;
  return 0;
}

int run(const std::string& file, const RunOptions& options, int dem_jobs) {
  if (!options.resume.empty() && options.out_dir.empty()) {
    std::cerr << "error: --resume needs --out RUN (the run directory to continue)" << std::endl;
    return kExitConfig;
  }
  Scene scene;
  try {
    scene = load_scene(file);
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << std::endl;
    return kExitConfig;
  }
  if (dem_jobs > 1 && !scene.constitutive.is_remote()) {
    std::cerr << "error: --dem-jobs " << dem_jobs << " needs a scene with constitutive.model "
              << "remote (" << file << " has a local model)" << std::endl;
    return kExitConfig;
  }
  scene.coupling.dem_jobs = dem_jobs;
  // MPI only for the remote model: the local one must run without any MPI environment.
  // MpiSession bounds MPI_Finalize when the peer has died.
  std::optional<mpmdem::MpiSession> mpi;
  if (scene.constitutive.is_remote()) {
    try {
      mpi.emplace(nullptr, nullptr, MPI_THREAD_FUNNELED);
    } catch (const std::exception& e) {
      std::cerr << "error: " << e.what() << std::endl;
      return 4;
    }
  }
  return run_scene(scene, options).exit_code;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"mpm_app: explicit 3D material point method solver of mpmdem", "mpm_app"};
  std::string scene_file, check_file, model_file;
  RunOptions options;
  bool print_reference = false, version = false, list = false;
  int dem_jobs = 1;
  app.add_option("scene", scene_file, "scene file (YAML) to run");
  app.add_option("--out", options.out_dir,
                 "run directory (default: runs/<scene>-<UTC yyyymmdd-HHMMSS>)");
  app.add_option("--threads", options.threads, "OpenMP threads (default: solver.threads)")
      ->check(CLI::Range(1, 1024));
  app.add_flag("--force", options.force, "overwrite a run directory that holds an earlier run");
  app.add_option("--resume", options.resume,
                 "continue the run in --out from a checkpoint directory (RUN/checkpoints/"
                 "step_<n>) or 'latest' (the newest complete one)");
  app.add_option("--max-steps", options.max_steps,
                 "stop after this many steps (status 'truncated', exit 0): a fixed workload "
                 "for benchmarks")
      ->check(CLI::Range(std::int64_t{1}, std::int64_t{1} << 62));
  app.add_option("--dem-jobs", dem_jobs,
                 "join this many dem_app jobs (started with --jobs K --job-index 0..K-1) into "
                 "one DEM partition: one job per DEM node (docs/cluster.md)")
      ->check(CLI::Range(1, 4096));
  app.add_option("--check-config", check_file, "validate a scene file and exit");
  app.add_flag("--print-config-reference", print_reference,
               "print every config key (type, default, unit, range, doc) and exit");
  app.add_option("--print-model", model_file,
                 "print the constitutive model of a scene (a local model's name or remote) and "
                 "exit");
  app.add_flag("--list-models", list,
               "list the constitutive models a scene may name (constitutive.model) and exit");
  app.add_flag("--version", version, "print the version and exit");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : kExitConfig;
  }

  if (version) {
    std::cout << "mpm_app " << MPMDEM_VERSION << std::endl;
    return 0;
  }
  if (print_reference) {
    std::cout << scene_schema().reference();
    return 0;
  }
  if (list) return list_models();
  if (!check_file.empty()) return check_config(check_file);
  if (!model_file.empty()) return print_model(model_file);
  if (scene_file.empty()) {
    std::cerr << "error: no scene file given\n" << app.help() << std::endl;
    return kExitConfig;
  }
  return run(scene_file, options, dem_jobs);
}
