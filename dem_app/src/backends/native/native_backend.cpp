// The native RVE backend: see native_backend.hpp.
#include "backends/native/native_backend.hpp"

#include <omp.h>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iostream>

#include <cstdlib>
#include <ctime>
#include <random>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "backends/contact_laws/table1.hpp"
#include "backends/native/cell_regularisation.hpp"
#include "backends/native/integrator.hpp"
#include "backends/native/measures.hpp"
#include "backends/native/packing.hpp"
#include "backends/native/rve_preparation.hpp"
#include "backends/native/rve_reply.hpp"
#include "coupling_rules.hpp"

namespace mpmdem::dem {

namespace {

using native::RveRecord;

std::int32_t as_int(protocol::RveStatus s) {
  return static_cast<std::int32_t>(s);
}

}  // namespace

NativeBackend::NativeBackend(const NativeParams& p) : p_(p), driver_(p.substeps, p.ke_threshold) {
  if (std::getenv("OMP_NUM_THREADS")) set_threads(omp_get_max_threads());
}

void NativeBackend::setup(const BackendContext& ctx) {
  ctx_ = ctx;
  packing_cache_.clear();
  rves_.clear();
  lists_.clear();
  driver_.forget();
  consolidation_cache_.reset();
  if (!p_.consolidation_cache.empty()) {
    consolidation_cache_ =
        std::make_unique<native::ConsolidationCache>(p_.consolidation_cache, std::cerr);
  }
}

std::string NativeBackend::packing_name(std::uint64_t point) const {
  if (p_.packings.empty()) return {};
  std::size_t pick = 0;
  if (p_.packings.size() > 1) {
    std::mt19937_64 rng(static_cast<std::uint64_t>(p_.seed) * 1000003u + point);
    pick = static_cast<std::size_t>(rng() % p_.packings.size());
  }
  return p_.packings[pick];
}

const NativeBackend::Packing& NativeBackend::packing(const std::string& name) {
  auto cached = packing_cache_.find(name);
  if (cached == packing_cache_.end()) {
    Packing pk;
    pk.state = native::read_packing(std::filesystem::path(p_.packing_dir) /
                                    (name + native::kPackingExtension));
    pk.state.contacts.sort_by_first();  // YADE's order: the force scatter wants them by sphere
    native::set_contact_law(pk.state, p_.law);  // frict_visco: part of the hash (NAT6 state)
    pk.hash = native::state_hash(pk.state);
    cached = packing_cache_.emplace(name, std::move(pk)).first;
  }
  return cached->second;
}

native::RveState NativeBackend::cloud(std::uint64_t point) const {
  native::CloudParams c;
  c.n_spheres = p_.inline_spheres;
  c.r_min = dem::laws::table1::kRadiusMin;  // Table 1's grains (backends/contact_laws/table1.hpp)
  c.r_max = dem::laws::table1::kRadiusMax;
  c.material.friction_angle = std::atan(dem::laws::table1::kFriction);
  c.seed = static_cast<std::uint64_t>(p_.seed) + point;
  native::RveState s = native::build_cloud(c);
  native::set_contact_law(s, p_.law);
  return s;
}

void NativeBackend::initialise(const protocol::RveInit* init, protocol::RveReply* reply) {
  rves_.clear();
  lists_.clear();
  native::ConsolidationParams cp;
  cp.stress_tol = p_.consolidation_tol;
  cp.unbalanced_tol = p_.consolidation_unbalanced;
  cp.max_steps = p_.consolidation_max_steps;
  cp.damping = p_.damping;
  cp.keep_on_failure = p_.consolidation_warn;
  const auto t0 = std::chrono::steady_clock::now();
  const std::clock_t cpu0 = std::clock();
  const std::size_t n = ctx_.n_rve;
  // Each RVE's starting state (its packing, or its own cloud) and target stress; the RVEs
  // with equal ones are prepared once (rve_preparation.hpp).
  std::vector<native::RveState> clouds(p_.packings.empty() ? n : 0);
  std::vector<native::PreparationInput> in(n);
  rves_.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    RveRecord& r = rves_[k];
    r.point = init[k].point;
    r.packing = packing_name(r.point);
    if (r.packing.empty()) {
      clouds[k] = cloud(r.point);
      in[k].start = &clouds[k];
      in[k].start_hash = native::state_hash(clouds[k]);
    } else {
      const Packing& pk = packing(r.packing);
      in[k].start = &pk.state;
      in[k].start_hash = pk.hash;
    }
    std::copy(init[k].stress, init[k].stress + 9, in[k].stress);
  }
  native::PreparedSet set = native::prepare_rves(in, cp, p_.verlet_skin, consolidation_cache_.get(),
                                                 ctx_.rank, ctx_.n_ranks);
  clouds.clear();
  // Each RVE gets its group's state: a copy, the last one of the group the state itself.
  std::vector<std::size_t> last(set.groups.size(), 0);
  for (std::size_t k = 0; k < n; ++k) last[set.of[k]] = k;
  for (std::size_t k = 0; k < n; ++k) {
    native::PreparedRve& g = set.groups[set.of[k]];
    RveRecord& r = rves_[k];
    r.state = last[set.of[k]] == k ? std::move(g.state) : g.state;
    // Consolidated with the packing's step; the updates take time_step_scale of it.
    r.state.dt *= p_.time_step_scale;
    r.unbalanced = g.unbalanced;
    const double mean = (init[k].stress[0] + init[k].stress[4] + init[k].stress[8]) / 3.0;
    r.p0 = std::max(std::abs(mean), 1.0);
    lists_.emplace_back(p_.verlet_skin);
    fill_reply(k, as_int(protocol::RveStatus::kOk),
               static_cast<std::int32_t>(r.state.spheres.size()), reply[k]);
  }
  driver_.initialised(reply, n, ctx_.first_rve);
  log_preparation(set.tally,
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
                  static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC);
  last_tally_ = set.tally;
}

// The cost of preparing the RVEs (the consolidation is most of it when the points carry an
// initial stress), one line per rank in dem_app's log. The figures per RVE count the steps
// of the state it got, wherever it was consolidated; "distinct" counts the consolidations
// this rank needed, and where each came from.
void NativeBackend::log_preparation(const native::PreparationTally& t, double seconds,
                                    double cpu_seconds) const {
  // Composed first and written in one call: the ranks share the log, and std::cerr writes
  // every << on its own, so the lines of ranks that finish together would interleave.
  std::ostringstream line;
  line << "dem_app rank " << ctx_.rank << ": prepared " << ctx_.n_rve << " RVEs in " << seconds
       << " s (CPU " << cpu_seconds << " s); " << t.consolidated << " consolidated, DEM steps mean "
       << (t.consolidated ? t.steps_sum / static_cast<long>(t.consolidated) : 0) << ", max "
       << t.steps_max << "; " << t.distinct << " distinct (packing, stress): " << t.computed
       << " consolidated here in " << t.steps_run << " DEM steps, " << t.from_cache
       << " from the consolidation cache";
  if (consolidation_cache_) {
    line << " " << consolidation_cache_->dir().string();
    if (t.rejected > 0) line << " (" << t.rejected << " unusable entries recomputed)";
  }
  if (t.not_converged > 0) {
    line << "; WARNING: " << t.not_converged << " did not reach their stress within "
         << p_.consolidation_max_steps
         << " steps and are kept as reached (coupling.native.consolidation_on_failure: warn)";
  }
  line << "\n";
  std::cerr << line.str() << std::flush;
}

void NativeBackend::substep(std::size_t k) {
  native::dem_step(rves_[k].state, lists_[k], p_.damping);
}

void NativeBackend::end_burst(std::size_t k) {
  if (ctx_.outputs & protocol::kOutputUnbalancedForce) {  // only when replied
    rves_[k].unbalanced = native::unbalanced_force(rves_[k].state);
  }
  rves_[k].state.spheres.release_forces();
}

RveEnergy NativeBackend::energy(std::size_t k) const {
  const native::RveState& s = rves_[k].state;
  return {native::kinetic_energy(s), s.cell.volume(), rves_[k].p0};
}

void NativeBackend::measure(std::size_t k, std::uint64_t step, std::int32_t status, std::int32_t ns,
                            protocol::RveReply& reply) {
  regularise(k, step);
  fill_reply(k, status, ns, reply);
}

void NativeBackend::regularise(std::size_t k, std::uint64_t step) {
  native::flip_cell(rves_[k].state, lists_[k]);
  if (step % 10) return;
  if (native::tile_if_thin(rves_[k].state, lists_[k]) >= 0) ++rves_[k].tilings;
}

void NativeBackend::fill_reply(std::size_t k, std::int32_t status, std::int32_t n_sub,
                               protocol::RveReply& reply) const {
  native::reply_from_state(rves_[k], status, n_sub, ctx_.outputs, p_.stiffness, reply);
}

void NativeBackend::step(const protocol::ControlHeader& header, const protocol::RveRequest* req,
                         protocol::RveReply* reply) {
  driver_.step(header, req, reply, rves_.size(), ctx_.first_rve, *this, threads_);
}

void NativeBackend::checkpoint(const std::filesystem::path& dir) {
  const auto file = dir / ("native_rank" + std::to_string(ctx_.rank) + ".bin");
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error("cannot write native checkpoint " + file.string());
  native::write_checkpoint_header(out, rves_.size());
  for (std::size_t k = 0; k < rves_.size(); ++k) {
    native::write_checkpoint_record(out, ctx_.first_rve + k, native::encode(rves_[k]));
    lists_[k].invalidate();  // continue as a restart from this file would (same rebuilds)
  }
  // Replies after a checkpoint come from the RVE states, here as in a resumed run.
  driver_.forget();
  if (!out) throw std::runtime_error("error while writing native checkpoint " + file.string());
}

void NativeBackend::restore(const std::filesystem::path& dir) {
  std::vector<bool> found(ctx_.n_rve, false);
  rves_.assign(ctx_.n_rve, RveRecord{});
  lists_.assign(ctx_.n_rve, native::NeighbourList(p_.verlet_skin));
  driver_.forget();
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("native_rank", 0) != 0 || entry.path().extension() != ".bin") continue;
    native::read_checkpoint(entry.path(), [&](std::uint64_t gid, const std::string& blob) {
      if (gid >= ctx_.first_rve && gid < ctx_.first_rve + ctx_.n_rve) {
        rves_[gid - ctx_.first_rve] = native::decode(blob);
        found[gid - ctx_.first_rve] = true;
      }
    });
  }
  for (std::size_t i = 0; i < found.size(); ++i) {
    if (!found[i]) {
      throw std::runtime_error("no native checkpoint in " + dir.string() + " holds RVE " +
                               std::to_string(ctx_.first_rve + i) +
                               ": restore with the same RVE count");
    }
  }
}

std::string NativeBackend::export_rve(std::uint64_t gid) {
  if (gid < ctx_.first_rve || gid >= ctx_.first_rve + rves_.size()) {
    throw std::logic_error("native backend: export of RVE " + std::to_string(gid) +
                           " that this rank does not own");
  }
  lists_[gid - ctx_.first_rve].invalidate();  // as on the adopting rank
  return native::encode(rves_[gid - ctx_.first_rve]);
}

void NativeBackend::adopt(std::uint64_t first_rve, std::uint64_t n_rve,
                          std::map<std::uint64_t, std::string> incoming) {
  std::vector<RveRecord> next(n_rve);
  std::vector<native::NeighbourList> next_lists(n_rve, native::NeighbourList(p_.verlet_skin));
  for (std::uint64_t k = 0; k < n_rve; ++k) {
    const std::uint64_t gid = first_rve + k;
    if (gid >= ctx_.first_rve && gid < ctx_.first_rve + rves_.size()) {
      next[k] = std::move(rves_[gid - ctx_.first_rve]);
      next_lists[k] = std::move(lists_[gid - ctx_.first_rve]);
      continue;
    }
    const auto it = incoming.find(gid);
    if (it == incoming.end()) {
      throw std::runtime_error("native backend: no state received for RVE " + std::to_string(gid));
    }
    next[k] = native::decode(it->second);
  }
  rves_ = std::move(next);
  lists_ = std::move(next_lists);
  ctx_.first_rve = first_rve;
  ctx_.n_rve = n_rve;
}

NativeParams native_params(const config::Config& cfg) {
  check_rve_backend(cfg, "native");
  check_consolidation_cache(cfg);
  NativeParams p;
  std::string dir = cfg.string("coupling.native.packing_dir");
  if (!dir.empty() && !std::filesystem::path(dir).is_absolute()) {
    dir = (std::filesystem::path(cfg.file()).parent_path() / dir).lexically_normal().string();
  }
  p.packing_dir = dir;
  p.packings = cfg.strings("coupling.native.packings");
  p.seed = cfg.integer("coupling.native.seed");
  p.inline_spheres = static_cast<int>(cfg.integer("coupling.native.inline_spheres"));
  p.substeps = substep_rule(cfg, "native");
  p.damping = cfg.number("coupling.native.damping");
  p.time_step_scale = cfg.number("coupling.native.time_step_scale");
  p.ke_threshold = cfg.number("coupling.native.ke_threshold");
  p.stiffness = cfg.string("coupling.native.stiffness") == "tangent";
  p.consolidation_tol = cfg.number("coupling.native.consolidation_tol");
  p.consolidation_unbalanced = cfg.number("coupling.native.consolidation_unbalanced");
  p.consolidation_max_steps =
      static_cast<long>(cfg.integer("coupling.native.consolidation_max_steps"));
  p.consolidation_warn = cfg.string("coupling.native.consolidation_on_failure") == "warn";
  std::string cache = cfg.string("coupling.native.consolidation_cache");
  if (!cache.empty() && !std::filesystem::path(cache).is_absolute()) {
    cache = (std::filesystem::path(cfg.file()).parent_path() / cache).lexically_normal().string();
  }
  p.consolidation_cache = cache;
  p.verlet_skin = cfg.number("coupling.native.verlet_skin");
  p.law = contact_law(cfg, "native");
  return p;
}

std::unique_ptr<RveBackend> make_native_backend(const config::Config& cfg) {
  return std::make_unique<NativeBackend>(native_params(cfg));
}

}  // namespace mpmdem::dem
