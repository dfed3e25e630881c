// The native backend consolidates once per distinct (packing, stress) and hands out exact
// copies (issue 36, item 5; dem_app/src/backends/native/rve_preparation.hpp), and its cache
// on disk (consolidation_cache.hpp) gives the states a fresh consolidation gives: cold, warm,
// off and in another rank's order alike; unusable entries are consolidated again; an entry
// kept unconverged is refused under consolidation_on_failure: error; the key changes with
// every input of the consolidation. Two packings of 40 spheres, 12 RVEs on 3 depths.
#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "backends/native/binary_state.hpp"
#include "backends/native/consolidation.hpp"
#include "backends/native/consolidation_key.hpp"
#include "backends/native/integrator.hpp"
#include "backends/native/measures.hpp"
#include "backends/native/native_backend.hpp"
#include "backends/native/packing.hpp"

namespace {

using namespace mpmdem;
namespace fs = std::filesystem;
namespace nat = mpmdem::dem::native;

constexpr std::size_t kRves = 12;
const double kDepthStress[3] = {-4.0e3, -7.0e3, -1.1e4};  // vertical stress of the 3 depths

// A folder of two 40-sphere packings (built clouds), removed at the end.
struct Library {
  fs::path dir;
  Library() {
    dir = fs::temp_directory_path() / ("mpmdem_consol_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir / "packings");
    for (int i = 0; i < 2; ++i) {
      nat::CloudParams c;
      c.n_spheres = 40;
      c.material.friction_angle = std::atan(0.5);
      c.seed = 11 + static_cast<std::uint64_t>(i);
      nat::write_packing(nat::build_cloud(c), dir / "packings" / (name(i) + ".native.txt"));
    }
  }
  ~Library() { fs::remove_all(dir); }
  static std::string name(int i) { return "cloud" + std::to_string(i); }
  fs::path cache() const { return dir / "cache"; }
};

dem::NativeParams params(const Library& lib, const std::string& cache = "") {
  dem::NativeParams p;
  p.packing_dir = (lib.dir / "packings").string();
  p.packings = {Library::name(0), Library::name(1)};
  p.seed = 5;
  p.consolidation_tol = 0.02;
  p.consolidation_unbalanced = 0.05;
  p.consolidation_cache = cache;
  return p;
}

// RVE k sits at depth k % 3 (k0 = 0.7), as the points of a lattice share their depths.
std::vector<protocol::RveInit> inits() {
  std::vector<protocol::RveInit> init(kRves);
  for (std::size_t k = 0; k < kRves; ++k) {
    std::memset(&init[k], 0, sizeof init[k]);
    const double v = kDepthStress[k % 3];
    init[k].stress[0] = init[k].stress[4] = 0.7 * v;
    init[k].stress[8] = v;
    init[k].point = 100 + k;
  }
  return init;
}

std::unique_ptr<dem::NativeBackend> run(const dem::NativeParams& p, int rank = 0, int n_ranks = 1) {
  auto b = std::make_unique<dem::NativeBackend>(p);
  dem::BackendContext ctx;
  ctx.n_rve = kRves;
  ctx.outputs = protocol::kKnownOutputs;
  ctx.rank = rank;
  ctx.n_ranks = n_ranks;
  b->setup(ctx);
  std::vector<protocol::RveInit> init = inits();
  std::vector<protocol::RveReply> reply(kRves);
  b->initialise(init.data(), reply.data());
  return b;
}

std::string bits(const nat::RveState& s) {
  nat::RveRecord r;
  r.state = s;
  return nat::encode(r);
}

// Every RVE's state, bit for bit.
std::vector<std::string> states(dem::NativeBackend& b) {
  std::vector<std::string> out;
  for (std::size_t k = 0; k < kRves; ++k) out.push_back(bits(b.rve(k).state));
  return out;
}

std::vector<fs::path> entries(const fs::path& dir) {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

TEST(NativeConsolidationCache, DistinctKeysAreConsolidatedOnceAndCopiesEqualFreshOnes) {
  const Library lib;
  const dem::NativeParams p = params(lib);
  auto b = run(p);
  // The groups the packing draw and the depths give, counted here from each RVE's packing.
  std::set<std::pair<std::string, std::size_t>> groups;
  for (std::size_t k = 0; k < kRves; ++k) groups.insert({b->rve(k).packing, k % 3});
  ASSERT_EQ(groups.size(), 6u) << "the draw should give both packings at every depth";
  const nat::PreparationTally& t = b->preparation_tally();
  EXPECT_EQ(t.consolidated, kRves);
  EXPECT_EQ(t.distinct, groups.size());
  EXPECT_EQ(t.computed, groups.size());
  EXPECT_EQ(t.from_cache, 0u);

  const std::vector<protocol::RveInit> init = inits();
  nat::ConsolidationParams cp;
  cp.stress_tol = p.consolidation_tol;
  cp.unbalanced_tol = p.consolidation_unbalanced;
  cp.max_steps = p.consolidation_max_steps;
  cp.damping = p.damping;
  long steps_sum = 0;
  for (std::size_t k = 0; k < kRves; ++k) {
    SCOPED_TRACE("RVE " + std::to_string(k));
    // A fresh consolidation of this RVE alone, as the backend did before the grouping.
    nat::RveState fresh =
        nat::read_packing(fs::path(p.packing_dir) / (b->rve(k).packing + ".native.txt"));
    fresh.contacts.sort_by_first();
    nat::NeighbourList nl(p.verlet_skin);
    const Eigen::Vector3d goal(init[k].stress[0], init[k].stress[4], init[k].stress[8]);
    steps_sum += nat::consolidate(fresh, nl, goal, cp).steps;
    nat::finish_preparation(fresh, nl, p.damping);
    EXPECT_EQ(nat::unbalanced_force(fresh), b->rve(k).unbalanced);
    fresh.spheres.release_forces();
    ASSERT_EQ(bits(fresh), bits(b->rve(k).state));
    // And they go on alike: the fresh one with its Verlet list, the copy with a new one.
    nat::RveState copy = b->rve(k).state;
    nat::NeighbourList copy_nl(p.verlet_skin);
    Eigen::Matrix3d l = Eigen::Matrix3d::Zero();
    l(0, 2) = 20.0, l(2, 2) = -5.0;
    fresh.cell.set_vel_grad(l);
    copy.cell.set_vel_grad(l);
    for (int n = 0; n < 300; ++n) {
      nat::dem_step(fresh, nl, p.damping);
      nat::dem_step(copy, copy_nl, p.damping);
    }
    fresh.spheres.release_forces();
    copy.spheres.release_forces();
    EXPECT_EQ(bits(fresh), bits(copy));
  }
  EXPECT_EQ(t.steps_sum, steps_sum);
}

TEST(NativeConsolidationCache, ColdWarmOffAndAnotherRanksOrderGiveTheSameBits) {
  const Library lib;
  const auto off = states(*run(params(lib), 1, 3));  // rank 1 of 3: another order
  auto cold = run(params(lib, lib.cache().string()));
  const std::size_t distinct = cold->preparation_tally().distinct;
  EXPECT_EQ(cold->preparation_tally().computed, distinct);
  EXPECT_EQ(entries(lib.cache()).size(), distinct);  // one file per key, no temporary left
  EXPECT_EQ(states(*cold), off);

  auto warm = run(params(lib, lib.cache().string()), 2, 3);
  EXPECT_EQ(warm->preparation_tally().from_cache, distinct);
  EXPECT_EQ(warm->preparation_tally().computed, 0u);
  EXPECT_EQ(warm->preparation_tally().steps_run, 0);
  EXPECT_EQ(warm->preparation_tally().steps_sum, cold->preparation_tally().steps_sum);
  EXPECT_EQ(states(*warm), off);
  for (std::size_t k = 0; k < kRves; ++k) {
    EXPECT_EQ(warm->rve(k).unbalanced, cold->rve(k).unbalanced);
  }

  // A truncated entry and one with a flipped byte are consolidated again and rewritten.
  const std::vector<fs::path> files = entries(lib.cache());
  fs::resize_file(files[0], fs::file_size(files[0]) - 9);
  {
    std::fstream f(files[1], std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(fs::file_size(files[1]) / 2));
    f.put('\x5a');
  }
  auto mended = run(params(lib, lib.cache().string()));
  EXPECT_EQ(mended->preparation_tally().rejected, 2u);
  EXPECT_EQ(mended->preparation_tally().computed, 2u);
  EXPECT_EQ(mended->preparation_tally().from_cache, distinct - 2);
  EXPECT_EQ(states(*mended), off);
  EXPECT_EQ(run(params(lib, lib.cache().string()))->preparation_tally().from_cache, distinct);
}

TEST(NativeConsolidationCache, AStateKeptUnconvergedIsRefusedUnderError) {
  const Library lib;
  dem::NativeParams p = params(lib, lib.cache().string());
  p.consolidation_max_steps = 100;  // too few for any of them
  p.consolidation_warn = true;
  auto kept = run(p);
  EXPECT_EQ(kept->preparation_tally().not_converged, kRves);
  p.consolidation_warn = false;
  EXPECT_THROW(
      {
        try {
          run(p);
        } catch (const std::runtime_error& e) {
          EXPECT_NE(std::string(e.what()).find("did not converge in 100 steps"), std::string::npos)
              << e.what();
          EXPECT_NE(std::string(e.what()).find(lib.cache().string()), std::string::npos);
          throw;
        }
      },
      std::runtime_error);
  p.consolidation_cache.clear();  // as a fresh consolidation does
  EXPECT_THROW(run(p), std::runtime_error);
}

// Each input of the consolidation changes the key (and so the cache file).
TEST(NativeConsolidationCache, TheKeyChangesWithEveryInput) {
  const nat::StateHash packing{0x1234, 5000};
  const double stress[9] = {-7e3, 0, 0, 0, -7e3, 0, 0, 0, -1e4};
  const nat::ConsolidationParams base;
  const nat::ConsolidationKey k0 = nat::consolidation_key(packing, stress, base, 0.5);
  EXPECT_EQ(k0, nat::consolidation_key(packing, stress, base, 0.5));
  std::set<std::string> names{k0.name()};
  auto differs = [&](const nat::ConsolidationKey& k, const char* what) {
    EXPECT_FALSE(k == k0) << what;
    EXPECT_TRUE(names.insert(k.name()).second) << what;
  };
  differs(nat::consolidation_key({0x1235, 5000}, stress, base, 0.5), "packing hash");
  differs(nat::consolidation_key({0x1234, 5008}, stress, base, 0.5), "packing size");
  for (int i = 0; i < 9; ++i) {
    double s[9];
    std::copy(stress, stress + 9, s);
    s[i] = std::nextafter(s[i], 1.0);  // one bit
    differs(nat::consolidation_key(packing, s, base, 0.5), "stress component");
  }
  nat::ConsolidationParams q = base;
  q.stress_tol *= 2;
  differs(nat::consolidation_key(packing, stress, q, 0.5), "stress_tol");
  q = base, q.unbalanced_tol *= 2;
  differs(nat::consolidation_key(packing, stress, q, 0.5), "unbalanced_tol");
  q = base, q.max_steps += 100;
  differs(nat::consolidation_key(packing, stress, q, 0.5), "max_steps");
  q = base, q.max_strain_rate *= 2;
  differs(nat::consolidation_key(packing, stress, q, 0.5), "max_strain_rate");
  q = base, q.damping = 0.3;
  differs(nat::consolidation_key(packing, stress, q, 0.5), "damping");
  differs(nat::consolidation_key(packing, stress, base, 0.6), "verlet_skin");
  q = base, q.keep_on_failure = true;  // not an input of the state
  EXPECT_EQ(nat::consolidation_key(packing, stress, q, 0.5), k0);
}

}  // namespace
