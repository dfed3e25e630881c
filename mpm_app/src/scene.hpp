// The validated scene: what the config file says, in SI units, as plain structs.
// Filled by config/scene_loader.cpp from a config that already passed the schema
// (config/scene_schema.cpp), so everything here is in range and consistent.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mpmdem/partition.hpp"

namespace mpmdem::mpm {

using Vec3 = Eigen::Vector3d;

// Background grid: a regular hexahedral lattice of cubic cells.
struct GridParams {
  Vec3 origin = Vec3::Zero();  // lower corner of the domain [m]
  Vec3 extent = Vec3::Ones();  // domain size [m]; rounded up to whole cells
  double cell_size = 0.05;     // [m]
};

// Box region filled with material points, n per cell per direction.
struct RegionParams {
  std::string name;
  Vec3 min = Vec3::Zero();
  Vec3 max = Vec3::Ones();
  int points_per_cell = 2;                   // per direction, unless points_xyz overrides it
  std::array<int, 3> points_xyz{{0, 0, 0}};  // per cell along x, y, z; 0: points_per_cell
  int points_along(int axis) const {
    const int n = points_xyz[static_cast<std::size_t>(axis)];
    return n > 0 ? n : points_per_cell;
  }
  // Placement: false: the centres of the n^3 sub-cells of each cell (equal volumes); true: n
  // Gauss-Legendre points per direction in every knot span of the shape functions.
  bool gauss_placement = false;
  double density = 2000.0;       // [kg/m^3]
  Vec3 velocity = Vec3::Zero();  // initial velocity [m/s]
  // Optional first-mode velocity profile v(x) = amplitude * sin(pi/2 * (x_a - x0)/L)
  // along `axis`, used by the vibrating-bar scene (fixed at x0, free at x0 + L).
  bool sine_velocity = false;
  int sine_axis = 0;
  double sine_amplitude = 0.0;
  // Initial stress: none, or geostatic (sigma_v = -rho g depth, sigma_h = K0 sigma_v)
  // measured from the region's top surface along gravity.
  bool geostatic = false;
  double k0 = 1.0;
};

// What happens on one face of the domain box.
enum class WallType { kFree, kFixed, kSlip, kFriction };
struct WallParams {
  WallType type = WallType::kFree;
  double friction = 0.0;  // Coulomb coefficient for kFriction
};
// Faces in the order x_min, x_max, y_min, y_max, z_min, z_max.
using Walls = std::array<WallParams, 6>;

// Prescribed velocity component on grid nodes inside a box, held until released.
struct VelocityConstraintParams {
  std::string name;
  Vec3 min = Vec3::Zero();
  Vec3 max = Vec3::Zero();
  std::array<bool, 3> components{{false, false, false}};  // which components are held
  Vec3 value = Vec3::Zero();                              // held value [m/s]
  // Release: at a time, or when E_k / E_p0 falls below a ratio after min_time, or never.
  std::optional<double> release_time;
  std::optional<double> release_kinetic_ratio;
  double release_min_time = 0.0;
};

enum class Scheme { kUSL, kMUSL };
enum class ShapeKind { kLinear, kQuadraticBSpline };
// Particle <-> grid velocity transfer: APIC (affine particle-in-cell, Jiang et al. 2015), the
// PIC/FLIP blend, or XPIC(m) (extended PIC, Hammerquist & Nairn 2017: xpic.hpp).
enum class Transfer { kAPIC, kPicFlip, kXPIC };
enum class OnExit { kError, kRemove };

struct SolverParams {
  Scheme scheme = Scheme::kMUSL;
  ShapeKind shape = ShapeKind::kLinear;
  Transfer transfer = Transfer::kPicFlip;  // kAPIC needs shape kQuadraticBSpline
  double flip = 0.99;  // FLIP fraction of the PIC/FLIP blend (1 = pure FLIP; pic_flip only)
  // > 0: the PIC share of the blend is dt / flip_time_scale per step (a fixed filtering rate
  // per unit time, so the dissipation does not grow with the step count) in place of 1 - flip.
  // The scene key solver.flip_velocity_scale U sets it to cell_size / U.
  double flip_time_scale = 0.0;  // [s]
  int xpic_order = 4;            // m of XPIC(m) (xpic only; 1 = PIC)
  double cfl = 0.5;              // Courant number
  double dt_max = 1e-3;          // cap on the automatic step [s]
  double dt_fixed = 0.0;  // > 0: this step in place of the automatic one [s] (stability studies)
  double end_time = 1.0;  // [s]
  Vec3 gravity{0.0, 0.0, -9.81};

  double local_damping = 0.0;  // Cundall non-viscous damping coefficient on grid forces
  OnExit on_exit = OnExit::kError;
  int threads = 0;  // 0: OpenMP default
};
// FLIP fraction of a step of dt: 1 - dt / flip_time_scale (at least 0) when that is set, else
// flip.
inline double flip_fraction(const SolverParams& sp, double dt) {
  if (sp.transfer != Transfer::kPicFlip && !(sp.flip_time_scale > 0.0)) return 0.0;
  return sp.flip_time_scale > 0.0 ? std::max(0.0, 1.0 - dt / sp.flip_time_scale) : sp.flip;
}

// The constitutive model's name for `remote` (RVEs on dem_app); every other name is a local
// model of the registry (constitutive/model_registry.hpp).
inline constexpr const char* kRemoteModel = "remote";
// A local model's own parameters beyond the elastic moduli (drucker_prager's
// DruckerPragerParams, a model registered in a test): its load hook sets them, its make hook
// reads them (dynamic_cast to its own type).
struct ModelParams {
  virtual ~ModelParams() = default;
};
struct ConstitutiveParams {
  // constitutive.model: a registered local model (mpm_app --list-models) or kRemoteModel.
  std::string model = "linear_elastic";
  bool is_remote() const { return model == kRemoteModel; }
  // Every local model: the moduli of its elastic response, which the energy budget
  // (1/2 sigma : C^-1 : sigma) and the elastic verifications use.
  double youngs_modulus = 1e7;  // [Pa]
  double poisson_ratio = 0.3;   // [-]
  // The model's own parameters (null for linear_elastic and remote).
  std::shared_ptr<const ModelParams> own;
};

// The shared section both programs read (hashed in the handshake).
struct CouplingParams {
  std::string backend = "elastic";
  std::uint32_t outputs = 0;  // OutputBits (mpmdem/protocol.hpp): the RVE outputs asked for
  std::string service_name = "mpmdem";
  double connect_timeout_s = 60.0;
  double peer_timeout_s = 300.0;                // longest wait for one exchange (unprobeable ranks)
  std::string port_file = "dem_port.txt";       // relative to the run directory
  double lazy_tolerance = 0.0;                  // coupling.lazy_tolerance: 0 = off
  RveOrder rve_order = RveOrder::kInterleaved;  // coupling.rve_order
  double load_balance_threshold = 0.0;          // coupling.load_balance.*: 0 = off
  std::int64_t load_balance_min_interval = 50;
  double load_balance_smoothing = 0.2;
  std::string canonical_text;  // canonical form of the whole section
  std::uint64_t hash = 0;      // fnv1a64(canonical_text)
  // Not from the scene (the launch, mpm_app --dem-jobs): how many separately launched DEM
  // jobs mpm_app joins into one partition (interface job_join.hpp). Not hashed.
  int dem_jobs = 1;
};

struct OutputParams {
  double interval = 0.0;         // simulated time between VTK frames [s]; 0: first and last only
  double energy_interval = 0.0;  // between energy CSV rows [s]; 0: every step
  bool vtk = true;
  bool hdf5 = true;
  bool rve_costs = false;                      // rve_costs.csv and rve_ranks.csv (remote model)
  double progress_interval_s = 2.0;            // wall time between progress lines
  std::int64_t checkpoint_interval_steps = 0;  // 0: no step-triggered checkpoints
  double checkpoint_interval_s = 60.0;         // wall time; 0: no time-triggered checkpoints
  int checkpoints_kept = 2;
};

enum class VerificationKind { kNone, kElasticColumn, kBarVibration };
struct VerificationParams {
  VerificationKind kind = VerificationKind::kNone;
};

// Column-collapse analysis (analysis/column_collapse.hpp): which region is the column,
// which constraint holds it in stage 1, how long stage 2 runs, when snapshots are taken.
struct ColumnCollapseParams {
  bool enabled = false;
  std::string region;              // empty: the first region
  std::string release_constraint;  // empty: the first velocity constraint (if any)
  double duration_t_star = 6.0;    // stage 2 length [t*]
  std::vector<double> snapshots_t_star{1.0, 3.0, 6.0};
  // column_collapse.at_rest: end stage 2 once E_k/E_p0 stayed below the ratio for the hold
  // (analysis/at_rest.hpp).
  bool at_rest = false;
  double at_rest_kinetic_ratio = 1e-5;
  double at_rest_hold_t_star = 0.25;  // [t*]
  double at_rest_min_t_star = 1.0;    // [t*]
};

struct Scene {
  std::string name;
  std::string source_file;
  GridParams grid;
  std::vector<RegionParams> regions;
  Walls walls;
  std::vector<VelocityConstraintParams> constraints;
  SolverParams solver;
  ConstitutiveParams constitutive;
  CouplingParams coupling;
  OutputParams output;
  VerificationParams verification;
  ColumnCollapseParams column_collapse;
};

}  // namespace mpmdem::mpm
