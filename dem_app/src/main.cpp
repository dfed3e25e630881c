// dem_app: the RVE server. Reads only `config_version` and the `coupling:` section of the
// scene, opens an MPI port, serves one mpm_app until it shuts down.
//
//   mpirun --ompi-server file:URI -np N dem_app --backend elastic|native|cuda|yade --scene FILE
//          --run-dir DIR [--restore CHECKPOINT_DIR] [--timeout S] [--idle-timeout S]
//          [--jobs K --job-index J]
//   dem_app --check-config FILE      validate the scene's coupling: section as the server would
//                                    (no MPI; for scripts/run, before anything runs)
//   dem_app --print-backend FILE     coupling.backend of a scene (no MPI; for scripts/run)
//   dem_app --print-port-file FILE   coupling.port_file of a scene (no MPI; for scripts/run)
//   dem_app --print-config-hash FILE the Hello's config_hash (16 hex digits) and the canonical
//                                    coupling text it hashes (no MPI; docs/protocol.md)
//   dem_app --list-backends [--long] the backends built into this dem_app, one per line
//                                    (--long: with what each one is)
//   dem_app --print-config-reference every key of the coupling: section (markdown tables)
//
// Exit codes: 0 after an orderly shutdown, 2 config/command-line error, 3 handshake
// refused, 4 no client / MPI failure / client aborted.
#include <mpi.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>

#include "backend_catalog.hpp"
#include "backend_factory.hpp"
#include "backends/contact_laws/registry.hpp"
#include "coupling_rules.hpp"
#include "coupling_schema.hpp"
#include "mpmdem/config_hash.hpp"
#include "mpmdem/connection.hpp"
#include "mpmdem/errors.hpp"
#include "server_loop.hpp"

namespace {

constexpr const char* kUsage =
    "usage: dem_app --backend elastic|native|cuda|yade --scene FILE --run-dir DIR\n"
    "               [--restore CHECKPOINT_DIR] [--timeout S] [--idle-timeout S]\n"
    "               [--jobs K --job-index J]\n"
    "  --backend   RVE backend; must equal coupling.backend of the scene\n"
    "  --scene     scene YAML; only config_version and coupling: are read\n"
    "  --run-dir   run directory shared with mpm_app (--out): the port file goes there\n"
    "  --restore   start the RVEs from a checkpoint directory instead of kInitialise\n"
    "  --timeout   seconds to wait for mpm_app (default coupling.connect_timeout_s)\n"
    "  --idle-timeout  exit if mpm_app sends nothing for this long (default 600 s;\n"
    "              0: wait forever). Open MPI does not report a killed peer.\n"
    "  --jobs, --job-index  this mpirun job is job J (0-based) of K DEM jobs that mpm_app\n"
    "              (--dem-jobs K) joins into one partition: one job per node (Open MPI\n"
    "              4.1; docs/cluster.md). Default 1 job.\n"
    "       dem_app --check-config FILE    validate the scene's coupling: section and exit\n"
    "       dem_app --print-backend FILE   print coupling.backend of a scene and exit\n"
    "       dem_app --print-port-file FILE print coupling.port_file of a scene and exit\n"
    "       dem_app --print-config-hash FILE  print the config hash this server would send\n"
    "              in its Hello (16 hex digits) and, on line 2, the canonical coupling text\n"
    "              it hashes (docs/protocol.md), and exit\n"
    "       dem_app --list-backends [--long]  print the backends built into this dem_app\n"
    "       dem_app --print-config-reference  every key of coupling: (markdown tables)\n"
    "Run under mpirun with the same --ompi-server file:URI as mpm_app (see docs/protocol.md).\n";

struct Args {
  std::string backend, scene, run_dir, restore;
  std::optional<double> timeout;
  double idle_timeout = 600.0;
  int jobs = 1, job_index = 0;
};

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The scene's `coupling:` section, validated as the server uses it: the schema, the rules
// between its keys (coupling_rules.hpp) and a backend built into this dem_app. Throws
// config::ConfigError.
mpmdem::config::Config load_coupling(const std::string& file) {
  auto cfg = mpmdem::config::Config::load(file, mpmdem::coupling_schema(), "coupling");
  mpmdem::check_coupling(cfg);
  mpmdem::dem::check_backend_available(cfg);
  mpmdem::check_consolidation_cache(cfg);
  return cfg;
}

Args parse(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string key = argv[i];
    if (key == "--help" || key == "-h") {
      std::cout << kUsage;
      std::exit(0);
    }
    if (i + 1 >= argc) throw UsageError("missing value after " + key);
    const std::string value = argv[++i];
    if (key == "--backend") {
      a.backend = value;
    } else if (key == "--scene") {
      a.scene = value;
    } else if (key == "--run-dir") {
      a.run_dir = value;
    } else if (key == "--restore") {
      a.restore = value;
    } else if (key == "--timeout" || key == "--idle-timeout") {
      char* end = nullptr;
      const double t = std::strtod(value.c_str(), &end);
      const bool idle = key == "--idle-timeout";
      if (end == value.c_str() || *end != '\0' || !(idle ? t >= 0.0 : t > 0.0)) {
        throw UsageError(key + " must be a number of seconds " + (idle ? ">= 0" : "> 0") +
                         ", got '" + value + "'");
      }
      if (idle) {
        a.idle_timeout = t;
      } else {
        a.timeout = t;
      }
    } else if (key == "--jobs" || key == "--job-index") {
      char* end = nullptr;
      const long n = std::strtol(value.c_str(), &end, 10);
      const long lowest = key == "--jobs" ? 1 : 0;
      if (end == value.c_str() || *end != '\0' || n < lowest || n > 4096) {
        throw UsageError(key + " must be a whole number >= " + std::to_string(lowest) + ", got '" +
                         value + "'");
      }
      (key == "--jobs" ? a.jobs : a.job_index) = static_cast<int>(n);
    } else {
      throw UsageError("unknown option '" + key + "'");
    }
  }
  if (a.job_index >= a.jobs) {
    throw UsageError("--job-index " + std::to_string(a.job_index) + " is not below --jobs " +
                     std::to_string(a.jobs) + " (job indices are 0-based)");
  }
  if (a.backend.empty()) throw UsageError("--backend is required");
  if (a.scene.empty()) throw UsageError("--scene is required");
  if (a.run_dir.empty()) throw UsageError("--run-dir is required");
  return a;
}

int run(int argc, char** argv, int rank) {
  const bool root = rank == 0;
  Args args;
  std::optional<mpmdem::config::Config> cfg;
  try {
    args = parse(argc, argv);
    cfg = load_coupling(args.scene);
    const std::string scene_backend = cfg->string("coupling.backend");
    if (scene_backend != args.backend) {
      throw UsageError("--backend " + args.backend + " differs from coupling.backend '" +
                       scene_backend + "' in " + args.scene + " (line " +
                       std::to_string(cfg->line("coupling.backend")) +
                       "); start dem_app with --backend " + scene_backend);
    }
    std::error_code ec;
    std::filesystem::create_directories(args.run_dir, ec);
    if (!std::filesystem::is_directory(args.run_dir)) {
      throw UsageError("--run-dir " + args.run_dir + " is not a directory and cannot be created");
    }
  } catch (const UsageError& e) {
    if (root) std::cerr << "dem_app: error: " << e.what() << "\n" << kUsage;
    return mpmdem::kExitConfigError;
  } catch (const mpmdem::config::ConfigError& e) {
    if (root) std::cerr << "dem_app: config error: " << e.what() << "\n";
    return mpmdem::kExitConfigError;
  }

  mpmdem::dem::ServerOptions opts;
  opts.backend = args.backend;
  opts.outputs = mpmdem::dem::backend_outputs(args.backend);
  opts.config_hash = mpmdem::fnv1a64(mpmdem::coupling_canonical_text(*cfg));
  opts.run_dir = std::filesystem::absolute(args.run_dir);
  opts.restore_dir = args.restore;
  opts.idle_timeout_s = args.idle_timeout;
  opts.connect.service_name = cfg->string("coupling.service_name");
  opts.connect.port_file = opts.run_dir / cfg->string("coupling.port_file");
  opts.connect.timeout_s = args.timeout.value_or(cfg->number("coupling.connect_timeout_s"));
  opts.connect.config_file = args.scene;
  opts.connect.jobs = args.jobs;
  opts.connect.job_index = args.job_index;

  const auto& config = *cfg;
  return mpmdem::dem::serve(opts, [&](const mpmdem::dem::BackendContext& ctx) {
    return mpmdem::dem::make_backend(args.backend, config, ctx);
  });
}

}  // namespace

// `dem_app --check-config FILE` (key empty: prints OK) / `--print-backend FILE` /
// `--print-port-file FILE`: a validated coupling key, without starting MPI (for scripts/run).
int print_key(const std::string& file, const std::string& key) {
  try {
    const auto cfg = load_coupling(file);
    std::cout << (key.empty() ? "OK: coupling section of " + file : cfg.string(key)) << "\n";
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "dem_app: config error: " << e.what() << "\n";
    return mpmdem::kExitConfigError;
  }
}

// `dem_app --print-config-hash FILE`: Hello::config_hash as 16 hex digits, then the canonical
// text of the coupling section it is the FNV-1a 64 of (no MPI; docs/protocol.md).
int print_config_hash(const std::string& file) {
  try {
    const auto cfg = load_coupling(file);
    const std::string text = mpmdem::coupling_canonical_text(cfg);
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx",
                  static_cast<unsigned long long>(mpmdem::fnv1a64(text)));
    std::cout << hex << "\n" << text << "\n";
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "dem_app: config error: " << e.what() << "\n";
    return mpmdem::kExitConfigError;
  }
}

int main(int argc, char** argv) {
  if ((argc == 2 || argc == 3) && std::string(argv[1]) == "--list-backends") {
    const bool long_form = argc == 3 && std::string(argv[2]) == "--long";
    if (argc == 3 && !long_form) {
      std::cerr << "dem_app: --list-backends takes only --long\n";
      return mpmdem::kExitConfigError;
    }
    for (const auto& name : mpmdem::dem::available_backends()) {
      std::cout << name;
      if (long_form) std::cout << "  " << mpmdem::dem::find_backend(name)->summary;
      std::cout << "\n";
    }
    // The contact laws of the RVE backends (coupling.<backend>.contact_law; the cuda backend's
    // batch kernel has frict only).
    if (long_form) {
      std::cout << "\ncontact laws (coupling.<backend>.contact_law):\n";
      for (const auto& law : mpmdem::dem::laws::kLaws) {
        std::cout << law.name << "  " << law.summary << "\n";
      }
    }
    return 0;
  }
  if (argc == 2 && std::string(argv[1]) == "--print-config-reference") {
    std::cout << mpmdem::coupling_schema().reference();
    return 0;
  }
  if (argc == 3 && std::string(argv[1]) == "--check-config") return print_key(argv[2], "");
  if (argc == 3 && std::string(argv[1]) == "--print-backend") {
    return print_key(argv[2], "coupling.backend");
  }
  if (argc == 3 && std::string(argv[1]) == "--print-port-file") {
    return print_key(argv[2], "coupling.port_file");
  }
  if (argc == 3 && std::string(argv[1]) == "--print-config-hash") return print_config_hash(argv[2]);
  int rank = 0;
  try {
    mpmdem::MpiSession mpi(&argc, &argv, MPI_THREAD_FUNNELED);
    rank = mpi.rank();
    try {
      return run(argc, argv, rank);
    } catch (const mpmdem::HandshakeError& e) {
      if (rank == 0) std::cerr << "dem_app: error: " << e.what() << "\n";
      return mpmdem::kExitHandshakeError;
    } catch (const mpmdem::PeerError& e) {
      // Not necessarily the same on every rank (an MPI failure may hit one rank only).
      std::cerr << "dem_app: rank " << rank << ": error: " << e.what() << std::endl;
      return mpmdem::kExitPeerError;
    }
  } catch (const std::exception& e) {
    std::cerr << "dem_app: rank " << rank << ": fatal error: " << e.what() << "\n";
    return 1;
  }
}
