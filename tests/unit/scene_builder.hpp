// The one way a unit test builds a scene, its material points and its solver: a fluent
// SceneBuilder over mpm::Scene, with defaults that make a valid small scene.
//
//   Scene s = SceneBuilder().domain(Vec3(0.1, 0.05, 0.4)).cell(0.025)
//                 .block(Vec3::Zero(), Vec3(0.1, 0.05, 0.3)).geostatic(0.3 / 0.7)
//                 .side_walls(WallType::kSlip).base(WallType::kFixed).damping(0.1).build();
//   Solver solver = SceneBuilder().no_gravity().block(...).velocity(v0).solver();
//   Scene column = SceneBuilder::config("configs/elastic_column.yaml").end_time(0.1).build();
//
// Defaults: a 0.2 m cube of 0.05 m cells at the origin, gravity (0, 0, -9.81), free walls,
// linear_elastic with E = 1e7 Pa and nu = 0.3, the solver's own defaults (SolverParams), and,
// if no block is added, one block "block" filling [0, 0.1]^3 with 2 points per cell per
// direction at 2000 kg/m^3. A block's modifiers (points, density, velocity, geostatic, ...)
// apply to the block added last. What the builder has no setter for is set through with().
//
// solver() makes the points with generate_particles and the provider of the scene's local
// model from the registry (constitutive/model_registry.hpp); pass points or a provider to
// replace either. quiet_options() is the RunOptions of a unit test that runs a whole scene
// through run_scene (one thread, no signal handlers, the log in a stream).
#pragma once

#include <array>
#include <functional>
#include <memory>
#include <ostream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "config/scene_loader.hpp"
#include "constitutive/model_registry.hpp"
#include "particle_init.hpp"
#include "run_driver.hpp"
#include "scene.hpp"
#include "solver.hpp"

namespace mpmdem::mpm::test_fixture {

// The faces of the domain box, in the order of Scene::walls.
enum Face : std::size_t { kXMin = 0, kXMax, kYMin, kYMax, kZMin, kZMax };

class SceneBuilder {
 public:
  SceneBuilder() {
    s_.name = "test";
    s_.grid.origin = Vec3::Zero();
    s_.grid.extent = Vec3(0.2, 0.2, 0.2);
    s_.grid.cell_size = 0.05;
    s_.solver.gravity = Vec3(0.0, 0.0, -9.81);
    s_.constitutive.model = "linear_elastic";
    s_.constitutive.youngs_modulus = 1e7;
    s_.constitutive.poisson_ratio = 0.3;
  }
  // A shipped scene (path relative to the source tree, e.g. "configs/elastic_column.yaml"),
  // loaded and validated as mpm_app loads it; the setters then change it.
  static SceneBuilder config(const std::string& path) {
    SceneBuilder b;
    b.s_ = load_scene(std::string(MPMDEM_SOURCE_DIR) + "/" + path);
    return b;
  }

  // The domain and its grid.
  SceneBuilder& name(const std::string& n) {
    return set([&](Scene& s) { s.name = n; });
  }
  SceneBuilder& domain(const Vec3& extent, const Vec3& origin = Vec3::Zero()) {
    return set([&](Scene& s) { s.grid.extent = extent, s.grid.origin = origin; });
  }
  SceneBuilder& cell(double h) {
    return set([&](Scene& s) { s.grid.cell_size = h; });
  }

  // A box of material points [min, max), and modifiers of the block added last.
  SceneBuilder& block(const Vec3& min, const Vec3& max) { return block("block", min, max); }
  SceneBuilder& block(const std::string& name, const Vec3& min, const Vec3& max) {
    RegionParams r;
    r.name = name;
    r.min = min;
    r.max = max;
    r.points_per_cell = 2;
    r.density = 2000.0;
    s_.regions.push_back(r);
    return *this;
  }
  SceneBuilder& points(int per_cell) {
    return last([&](RegionParams& r) { r.points_per_cell = per_cell; });
  }
  SceneBuilder& points_xyz(const std::array<int, 3>& n) {
    return last([&](RegionParams& r) { r.points_xyz = n; });
  }
  SceneBuilder& gauss_placement(bool on = true) {
    return last([&](RegionParams& r) { r.gauss_placement = on; });
  }
  SceneBuilder& density(double rho) {
    return last([&](RegionParams& r) { r.density = rho; });
  }
  SceneBuilder& velocity(const Vec3& v) {
    return last([&](RegionParams& r) { r.velocity = v; });
  }
  SceneBuilder& sine_velocity(int axis, double amplitude) {
    return last([&](RegionParams& r) {
      r.sine_velocity = true, r.sine_axis = axis, r.sine_amplitude = amplitude;
    });
  }
  SceneBuilder& geostatic(double k0) {
    return last([&](RegionParams& r) { r.geostatic = true, r.k0 = k0; });
  }
  // Keeps only the generated points whose position satisfies keep (a block cut to a shape);
  // ids are renumbered 0, 1, ... in order.
  SceneBuilder& cut(std::function<bool(const Vec3&)> keep) {
    cut_ = std::move(keep);
    return *this;
  }

  // Body force and boundaries.
  SceneBuilder& gravity(const Vec3& g) {
    return set([&](Scene& s) { s.solver.gravity = g; });
  }
  SceneBuilder& no_gravity() { return gravity(Vec3::Zero()); }
  SceneBuilder& wall(Face face, WallType type, double friction = 0.0) {
    return set([&](Scene& s) { s.walls[face] = WallParams{type, friction}; });
  }
  SceneBuilder& walls(const Walls& w) {
    return set([&](Scene& s) { s.walls = w; });
  }
  // The four faces normal to x and y.
  SceneBuilder& side_walls(WallType type) {
    for (Face f : {kXMin, kXMax, kYMin, kYMax}) wall(f, type);
    return *this;
  }
  SceneBuilder& base(WallType type, double friction = 0.0) { return wall(kZMin, type, friction); }
  SceneBuilder& constraint(const VelocityConstraintParams& c) {
    return set([&](Scene& s) { s.constraints.push_back(c); });
  }

  // The constitutive model: a registered local model by name, and the elastic moduli.
  SceneBuilder& model(const std::string& name) {
    return set([&](Scene& s) { s.constitutive.model = name; });
  }
  SceneBuilder& moduli(double youngs_modulus, double poisson_ratio) {
    return set([&](Scene& s) {
      s.constitutive.youngs_modulus = youngs_modulus, s.constitutive.poisson_ratio = poisson_ratio;
    });
  }

  // The scheme.
  SceneBuilder& shape(ShapeKind k) {
    return set([&](Scene& s) { s.solver.shape = k; });
  }
  SceneBuilder& scheme(Scheme k) {
    return set([&](Scene& s) { s.solver.scheme = k; });
  }
  SceneBuilder& transfer(Transfer t) {
    return set([&](Scene& s) { s.solver.transfer = t; });
  }
  // The transfer and the FLIP fraction of the PIC/FLIP blend.
  SceneBuilder& transfer(Transfer t, double flip_fraction) {
    return transfer(t).flip(flip_fraction);
  }
  SceneBuilder& flip(double f) {
    return set([&](Scene& s) { s.solver.flip = f; });
  }
  SceneBuilder& flip_time_scale(double tau) {
    return set([&](Scene& s) { s.solver.flip_time_scale = tau; });
  }
  SceneBuilder& xpic_order(int m) {
    return set([&](Scene& s) { s.solver.xpic_order = m; });
  }
  SceneBuilder& cfl(double c) {
    return set([&](Scene& s) { s.solver.cfl = c; });
  }
  SceneBuilder& dt_max(double dt) {
    return set([&](Scene& s) { s.solver.dt_max = dt; });
  }
  SceneBuilder& dt_fixed(double dt) {
    return set([&](Scene& s) { s.solver.dt_fixed = dt; });
  }
  SceneBuilder& end_time(double t) {
    return set([&](Scene& s) { s.solver.end_time = t; });
  }
  SceneBuilder& damping(double alpha) {
    return set([&](Scene& s) { s.solver.local_damping = alpha; });
  }
  SceneBuilder& on_exit(OnExit e) {
    return set([&](Scene& s) { s.solver.on_exit = e; });
  }
  SceneBuilder& verification(VerificationKind k) {
    return set([&](Scene& s) { s.verification.kind = k; });
  }
  // Anything else (outputs, coupling, column_collapse, ...).
  SceneBuilder& with(const std::function<void(Scene&)>& edit) { return set(edit); }

  // The scene (with the default block if none was added).
  Scene build() const {
    Scene s = s_;
    if (s.regions.empty()) {
      SceneBuilder b;
      b.block(Vec3::Zero(), Vec3(0.1, 0.1, 0.1));
      s.regions = b.s_.regions;
    }
    return s;
  }
  Particles particles() const {
    Particles p = generate_particles(build());
    if (cut_) p = kept(p, cut_);
    return p;
  }
  // The provider of the scene's local model (std::invalid_argument for kRemoteModel).
  static std::unique_ptr<ConstitutiveProvider> provider(const Scene& s) {
    return local_model(s.constitutive.model).make(s.constitutive);
  }
  Solver solver() const { return solver(particles()); }
  Solver solver(Particles p) const {
    const Scene s = build();
    return Solver(s, std::move(p), provider(s));
  }
  Solver solver(std::unique_ptr<ConstitutiveProvider> provider) const {
    return Solver(build(), particles(), std::move(provider));
  }
  Solver solver(Particles p, std::unique_ptr<ConstitutiveProvider> provider) const {
    return Solver(build(), std::move(p), std::move(provider));
  }

 private:
  SceneBuilder& set(const std::function<void(Scene&)>& edit) {
    edit(s_);
    return *this;
  }
  SceneBuilder& last(const std::function<void(RegionParams&)>& edit) {
    if (s_.regions.empty())
      throw std::logic_error("SceneBuilder: add a block() before its modifiers");
    edit(s_.regions.back());
    return *this;
  }
  // The points of p where keep(x_p) holds: every per-point field filtered, ids renumbered.
  static Particles kept(const Particles& p, const std::function<bool(const Vec3&)>& keep) {
    const std::size_t n = p.size();
    std::vector<char> k(n);
    for (std::size_t q = 0; q < n; ++q) k[q] = keep(p.x[q]);
    Particles out = p;
    auto filter = [&](auto& v) {
      if (v.size() != n) return;  // a field the points do not carry
      std::size_t j = 0;
      for (std::size_t q = 0; q < n; ++q)
        if (k[q]) v[j++] = v[q];
      v.resize(j);
    };
    filter(out.id), filter(out.region), filter(out.m), filter(out.V), filter(out.V0);
    filter(out.x), filter(out.x0), filter(out.v), filter(out.C), filter(out.F), filter(out.dF);
    filter(out.sigma), filter(out.stiffness), filter(out.strain_energy), filter(out.rotation);
    filter(out.porosity), filter(out.coordination), filter(out.unbalanced_force);
    filter(out.state);
    for (std::size_t q = 0; q < out.id.size(); ++q) out.id[q] = static_cast<std::int64_t>(q);
    return out;
  }
  Scene s_;
  std::function<bool(const Vec3&)> cut_;
};

// A block of 0.2 x 0.15 x 0.15 m in the middle of a 1 m box of 0.05 m cells, no gravity, no
// walls: E = 1e6 Pa, nu = 0.25, 1500 kg/m^3, cfl 0.4. The tests give it its velocities
// (translating, spinning) and its scheme (test_conservation.cpp, test_energy_budget.cpp).
inline SceneBuilder flying_block() {
  return SceneBuilder()
      .name("flying_block")
      .domain(Vec3(1.0, 1.0, 1.0))
      .cell(0.05)
      .no_gravity()
      .block(Vec3(0.4, 0.42, 0.45), Vec3(0.6, 0.57, 0.6))
      .density(1500.0)
      .cfl(0.4)
      .end_time(1.0)
      .moduli(1e6, 0.25);
}

// RunOptions for a whole run in a unit test: into dir, one thread (the runs are small: threads
// would only add barrier waits on a busy machine), no signal handlers, progress and errors
// into log.
inline RunOptions quiet_options(const std::string& dir, std::ostream& log,
                                Particles* final_state = nullptr) {
  RunOptions o;
  o.out_dir = dir;
  o.threads = 1;
  o.handle_signals = false;
  o.out = &log;
  o.err = &log;
  o.final_particles = final_state;
  return o;
}

}  // namespace mpmdem::mpm::test_fixture
