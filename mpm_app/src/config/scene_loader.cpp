// From a scene file to a Scene: schema validation (config/scene_schema.cpp), conversion to
// the structs of scene.hpp, and the checks that involve several keys, each naming the key,
// its value, the file and the line.
#include "config/scene_loader.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "config/scene_rules.hpp"
#include "constitutive/model_registry.hpp"
#include "mpmdem/config_hash.hpp"
#include "mpmdem/coupling_keys.hpp"

namespace mpmdem::mpm {

namespace {

using config::Config;

Vec3 vec(const std::array<double, 3>& a) {
  return Vec3(a[0], a[1], a[2]);
}

std::string text(const Vec3& v) {
  return "[" + config::format_number(v.x()) + ", " + config::format_number(v.y()) + ", " +
         config::format_number(v.z()) + "]";
}

int axis_index(const std::string& a) {
  return a == "x" ? 0 : a == "y" ? 1 : 2;
}

const char* const kAxis[] = {"x", "y", "z"};

// The domain box [lo, hi] as the grid will have it, and a length tolerance for comparisons.
struct Domain {
  Vec3 lo, hi;
  double h, tol;
  std::string describe() const {
    return "the domain grid.origin .. grid.origin + grid.extent = " + text(lo) + " .. " + text(hi);
  }
};

GridParams load_grid(const Config& cfg) {
  GridParams g;
  g.origin = vec(cfg.vec3("grid.origin"));
  g.extent = vec(cfg.vec3("grid.extent"));
  g.cell_size = cfg.number("grid.cell_size");
  double cells = 1.0;
  for (int a = 0; a < 3; ++a) cells *= std::ceil(g.extent[a] / g.cell_size - 1e-9);
  if (cells > 2.0e8) {
    cfg.fail("grid.cell_size", config::format_number(g.cell_size) + " m gives " +
                                   config::format_number(cells) + " cells for grid.extent " +
                                   text(g.extent) + "; use a larger cell size (at most 2e8 cells)");
  }
  return g;
}

// min < max (or <= for planes) and the box inside the domain.
void check_box(const Config& item, const Domain& d, bool allow_flat) {
  const Vec3 lo = vec(item.vec3("min")), hi = vec(item.vec3("max"));
  for (int a = 0; a < 3; ++a) {
    if (allow_flat ? hi[a] < lo[a] : hi[a] <= lo[a]) {
      item.fail("max", text(hi) + " must be " + (allow_flat ? ">=" : ">") + " min " + text(lo) +
                           " in every component (" + kAxis[a] + " is not)");
    }
  }
  for (int a = 0; a < 3; ++a) {
    if (lo[a] < d.lo[a] - d.tol || lo[a] > d.hi[a] + d.tol) {
      item.fail("min", text(lo) + " lies outside " + d.describe());
    }
    if (hi[a] > d.hi[a] + d.tol || hi[a] < d.lo[a] - d.tol) {
      item.fail("max", text(hi) + " lies outside " + d.describe());
    }
  }
}

std::vector<RegionParams> load_regions(const Config& cfg, const Domain& d) {
  const std::vector<Config> items = cfg.list("regions");
  if (items.empty()) cfg.fail("regions", "is empty: list at least one region of material");
  std::vector<RegionParams> regions;
  for (std::size_t i = 0; i < items.size(); ++i) {
    const Config& r = items[i];
    check_box(r, d, false);
    RegionParams p;
    p.name = r.string("name").empty() ? "region" + std::to_string(i) : r.string("name");
    for (std::size_t j = 0; j < regions.size(); ++j) {
      if (regions[j].name == p.name) {
        r.fail("name", "'" + p.name + "' is used by regions[" + std::to_string(j) +
                           "] too; names must be unique");
      }
    }
    p.min = vec(r.vec3("min"));
    p.max = vec(r.vec3("max"));
    p.points_per_cell = static_cast<int>(r.integer("points_per_cell"));
    if (r.has("points_per_cell_xyz")) {
      const auto n = r.vec3("points_per_cell_xyz");
      for (int a = 0; a < 3; ++a) {
        if (!(n[a] >= 1 && n[a] <= 8 && n[a] == std::floor(n[a]))) {
          r.fail("points_per_cell_xyz", std::string("must hold integers from 1 to 8; the ") +
                                            kAxis[a] + " entry is " + config::format_number(n[a]));
        }
        p.points_xyz[static_cast<std::size_t>(a)] = static_cast<int>(n[a]);
      }
    }
    for (int a = 0; a < 3; ++a) {
      const double spacing = d.h / p.points_along(a);
      if (p.max[a] - p.min[a] < spacing - d.tol) {
        r.fail("", "is " + config::format_number(p.max[a] - p.min[a]) + " m thick along " +
                       kAxis[a] + ", less than one point spacing (grid.cell_size / " +
                       "points per cell = " + config::format_number(spacing) +
                       " m): it would hold no material points");
      }
    }
    p.density = r.number("density");
    p.velocity = vec(r.vec3("velocity"));
    if (r.has("sine_velocity")) {
      p.sine_velocity = true;
      p.sine_axis = axis_index(r.string("sine_velocity.axis"));
      p.sine_amplitude = r.number("sine_velocity.amplitude");
    }
    p.geostatic = r.string("initial_stress") == "geostatic";
    p.gauss_placement = r.string("placement") == "gauss";
    p.k0 = r.number("k0");
    regions.push_back(p);
  }
  return regions;
}

Walls load_walls(const Config& cfg) {
  static const char* const kFaces[] = {"x_min", "x_max", "y_min", "y_max", "z_min", "z_max"};
  Walls walls;
  const double mu = cfg.number("walls.friction");
  bool any_friction = false;
  for (std::size_t f = 0; f < 6; ++f) {
    const std::string t = cfg.string(std::string("walls.") + kFaces[f]);
    walls[f].type = t == "fixed"      ? WallType::kFixed
                    : t == "slip"     ? WallType::kSlip
                    : t == "friction" ? WallType::kFriction
                                      : WallType::kFree;
    walls[f].friction = walls[f].type == WallType::kFriction ? mu : 0.0;
    any_friction = any_friction || walls[f].type == WallType::kFriction;
  }
  if (any_friction && mu <= 0.0) {
    cfg.fail("walls.friction",
             "must be > 0 when a wall is of type friction (use slip for a frictionless "
             "wall), got " +
                 config::format_number(mu));
  }
  return walls;
}

std::vector<VelocityConstraintParams> load_constraints(const Config& cfg, const Domain& d) {
  std::vector<VelocityConstraintParams> out;
  const std::vector<Config> items = cfg.list("velocity_constraints");
  for (std::size_t i = 0; i < items.size(); ++i) {
    const Config& c = items[i];
    check_box(c, d, true);
    VelocityConstraintParams p;
    p.name = c.string("name").empty() ? "constraint" + std::to_string(i) : c.string("name");
    p.min = vec(c.vec3("min"));
    p.max = vec(c.vec3("max"));
    const std::vector<std::string> comps = c.strings("components");
    if (comps.empty()) c.fail("components", "is empty: list at least one of x, y, z");
    for (const std::string& a : comps) p.components[axis_index(a)] = true;
    // Nodes sit at origin + k h: the box must contain at least one along every axis.
    for (int a = 0; a < 3; ++a) {
      const double k_hi = std::floor((p.max[a] - d.lo[a] + d.tol) / d.h);
      if (d.lo[a] + k_hi * d.h < p.min[a] - d.tol) {
        c.fail("", "box " + text(p.min) + " .. " + text(p.max) + " contains no grid node along " +
                       kAxis[a] + " (nodes are grid.origin + k grid.cell_size)");
      }
    }
    p.value = vec(c.vec3("value"));
    if (c.has("release_min_time") && !c.has("release_kinetic_ratio")) {
      c.fail("release_min_time", "only applies with release_kinetic_ratio, which is missing");
    }
    if (c.has("release_time")) p.release_time = c.number("release_time");
    if (c.has("release_kinetic_ratio")) p.release_kinetic_ratio = c.number("release_kinetic_ratio");
    p.release_min_time = c.number("release_min_time");
    out.push_back(p);
  }
  return out;
}

SolverParams load_solver(const Config& cfg, double cell_size) {
  SolverParams s;
  s.scheme = cfg.string("solver.scheme") == "usl" ? Scheme::kUSL : Scheme::kMUSL;
  s.shape =
      cfg.string("solver.shape") == "bspline2" ? ShapeKind::kQuadraticBSpline : ShapeKind::kLinear;
  const std::string transfer = cfg.string("solver.transfer");
  s.transfer = transfer == "pic_flip" ? Transfer::kPicFlip
               : transfer == "xpic"   ? Transfer::kXPIC
                                      : Transfer::kAPIC;
  if (s.transfer != Transfer::kPicFlip && cfg.has("solver.flip")) {
    cfg.fail("solver.flip", "applies only to solver.transfer: pic_flip (the transfer is " +
                                transfer + "); remove it or set transfer: pic_flip");
  }
  if (s.transfer != Transfer::kXPIC && cfg.has("solver.xpic_order")) {
    cfg.fail("solver.xpic_order", "applies only to solver.transfer: xpic (the transfer is " +
                                      transfer + "); remove it or set transfer: xpic");
  }
  if (s.transfer == Transfer::kAPIC && s.shape == ShapeKind::kLinear) {
    cfg.fail("solver.transfer",
             "apic needs solver.shape: bspline2; with trilinear shapes APIC's D_p is singular on "
             "node planes and the affine velocities grow without bound as points cross cells (a "
             "stress-free translating block blows up within 100 steps). Set shape: bspline2, or "
             "transfer: pic_flip");
  }
  s.flip = cfg.number("solver.flip");
  s.xpic_order = static_cast<int>(cfg.integer("solver.xpic_order"));
  s.flip_time_scale = cfg.number("solver.flip_time_scale");
  const double u = cfg.number("solver.flip_velocity_scale");
  for (const char* k : {"solver.flip_time_scale", "solver.flip_velocity_scale"}) {
    if (!(cfg.number(k) > 0.0)) continue;
    if (cfg.has("solver.flip")) {
      cfg.fail(k, "replaces solver.flip, which is set too; remove one of them");
    }
  }
  if (u > 0.0 && s.flip_time_scale > 0.0) {
    cfg.fail("solver.flip_velocity_scale",
             "sets solver.flip_time_scale (grid.cell_size / flip_velocity_scale), which is set "
             "too; remove one of them");
  }
  if (u > 0.0) s.flip_time_scale = cell_size / u;
  s.cfl = cfg.number("solver.cfl");
  s.dt_max = cfg.number("solver.dt_max");
  s.dt_fixed = cfg.number("solver.dt_fixed");
  s.end_time = cfg.number("solver.end_time");
  s.gravity = vec(cfg.vec3("solver.gravity"));
  s.local_damping = cfg.number("solver.local_damping");
  s.on_exit = cfg.string("solver.on_exit") == "remove" ? OnExit::kRemove : OnExit::kError;
  s.threads = static_cast<int>(cfg.integer("solver.threads"));
  return s;
}

// constitutive.model and, for a local model, its section (read by the model's load hook).
ConstitutiveParams load_constitutive(const Config& cfg) {
  ConstitutiveParams c;
  c.model = cfg.string("constitutive.model");
  if (c.is_remote()) {
    if (!cfg.has("coupling")) {
      cfg.fail("constitutive.model",
               "is remote but the file has no coupling: section (backend, outputs, ...); "
               "add one, see docs/configuration.md");
    }
    return c;
  }
  const LocalModel& model = local_model(c.model);  // the schema admits registered names only
  const std::string section = "constitutive." + model.name;
  if (!cfg.has(section)) {
    // "(youngs_modulus, poisson_ratio, friction_angle_deg, ...)": the required keys, and
    // "..." when there are others.
    std::string keys;
    bool more = false;
    for (const config::KeySpec* k : scene_schema().children(section)) {
      if (!k->required) {
        more = true;
        continue;
      }
      keys += (keys.empty() ? "" : ", ") + k->path.substr(section.size() + 1);
    }
    if (more) keys += keys.empty() ? "..." : ", ...";
    cfg.fail("constitutive.model",
             "is " + model.name + " but the section " + section + " (" + keys + ") is missing");
  }
  model.load(cfg, section, c);
  return c;
}

CouplingParams load_coupling(const Config& cfg) {
  CouplingParams c;
  c.backend = cfg.string("coupling.backend");
  c.outputs = coupling_output_bits(cfg);
  c.service_name = cfg.string("coupling.service_name");
  c.connect_timeout_s = cfg.number("coupling.connect_timeout_s");
  c.peer_timeout_s = cfg.number("coupling.peer_timeout_s");
  c.port_file = cfg.string("coupling.port_file");
  c.lazy_tolerance = cfg.number("coupling.lazy_tolerance");
  c.rve_order = cfg.string("coupling.rve_order") == "interleaved" ? RveOrder::kInterleaved
                                                                  : RveOrder::kContiguous;
  c.load_balance_threshold = cfg.number("coupling.load_balance.threshold");
  c.load_balance_min_interval = cfg.integer("coupling.load_balance.min_interval_steps");
  c.load_balance_smoothing = cfg.number("coupling.load_balance.smoothing");
  c.canonical_text = coupling_canonical_text(cfg);
  c.hash = fnv1a64(c.canonical_text);
  return c;
}

OutputParams load_output(const Config& cfg) {
  OutputParams o;
  o.interval = cfg.number("output.interval");
  o.energy_interval = cfg.number("output.energy_interval");
  o.vtk = cfg.boolean("output.vtk");
  o.hdf5 = cfg.boolean("output.hdf5");
  o.rve_costs = cfg.boolean("output.rve_costs");
  if (o.rve_costs && cfg.string("constitutive.model") != kRemoteModel) {
    cfg.fail("output.rve_costs", "is true but constitutive.model is '" +
                                     cfg.string("constitutive.model") +
                                     "': RVE costs exist only with the remote model");
  }
  o.progress_interval_s = cfg.number("output.progress_interval_s");
  o.checkpoint_interval_steps = cfg.integer("output.checkpoint_interval_steps");
  o.checkpoint_interval_s = cfg.number("output.checkpoint_interval_s");
  o.checkpoints_kept = static_cast<int>(cfg.integer("output.checkpoints_kept"));
  return o;
}

VerificationParams load_verification(const Config& cfg) {
  const std::string k = cfg.string("verification.kind");
  VerificationParams v;
  v.kind = k == "elastic_column"  ? VerificationKind::kElasticColumn
           : k == "bar_vibration" ? VerificationKind::kBarVibration
                                  : VerificationKind::kNone;
  return v;
}

}  // namespace

ColumnCollapseParams load_column_collapse(const Config& cfg) {
  ColumnCollapseParams c;
  if (!cfg.has("column_collapse")) return c;
  c.enabled = true;
  c.region = cfg.string("column_collapse.region");
  c.release_constraint = cfg.string("column_collapse.release_constraint");
  c.duration_t_star = cfg.number("column_collapse.duration_t_star");
  c.snapshots_t_star = cfg.numbers("column_collapse.snapshots_t_star");
  for (std::size_t i = 1; i < c.snapshots_t_star.size(); ++i) {
    if (c.snapshots_t_star[i] <= c.snapshots_t_star[i - 1]) {
      cfg.fail("column_collapse.snapshots_t_star",
               "must increase (each time names its snapshot file): " +
                   config::format_number(c.snapshots_t_star[i]) + " follows " +
                   config::format_number(c.snapshots_t_star[i - 1]));
    }
  }
  for (double t : c.snapshots_t_star) {
    if (t > c.duration_t_star) {
      cfg.fail("column_collapse.snapshots_t_star",
               "asks for " + config::format_number(t) +
                   " t*, after stage 2 ends at column_collapse.duration_t_star " +
                   config::format_number(c.duration_t_star) +
                   ": that snapshot would never be written; drop it or lengthen the duration");
    }
  }
  if (cfg.has("column_collapse.at_rest")) {
    c.at_rest = true;
    c.at_rest_kinetic_ratio = cfg.number("column_collapse.at_rest.kinetic_ratio");
    c.at_rest_hold_t_star = cfg.number("column_collapse.at_rest.hold_t_star");
    c.at_rest_min_t_star = cfg.number("column_collapse.at_rest.min_t_star");
    for (const auto& [key, value] : {std::pair{"min_t_star", c.at_rest_min_t_star},
                                     std::pair{"hold_t_star", c.at_rest_hold_t_star}}) {
      if (value >= c.duration_t_star) {
        cfg.fail(std::string("column_collapse.at_rest.") + key,
                 config::format_number(value) + " is not below column_collapse.duration_t_star " +
                     config::format_number(c.duration_t_star) +
                     ": the at-rest stop could never end the run before the duration does");
      }
    }
  }
  return c;
}

Scene load_scene(const std::string& file) {
  const Config cfg = Config::load(file, scene_schema());
  Scene scene;
  scene.source_file = file;
  scene.name = cfg.string("scene.name");
  if (scene.name.empty()) scene.name = std::filesystem::path(file).stem().string();
  scene.grid = load_grid(cfg);
  Domain d;
  d.lo = scene.grid.origin;
  d.hi = scene.grid.origin + scene.grid.extent;
  d.h = scene.grid.cell_size;
  d.tol = 1e-9 * scene.grid.cell_size;
  scene.regions = load_regions(cfg, d);
  scene.walls = load_walls(cfg);
  scene.constraints = load_constraints(cfg, d);
  scene.solver = load_solver(cfg, scene.grid.cell_size);
  scene.constitutive = load_constitutive(cfg);
  scene.coupling = load_coupling(cfg);
  scene.output = load_output(cfg);
  scene.verification = load_verification(cfg);
  scene.column_collapse = load_column_collapse(cfg);
  check_scene_rules(cfg, scene);
  return scene;
}

}  // namespace mpmdem::mpm
