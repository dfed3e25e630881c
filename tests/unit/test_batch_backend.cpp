// The GPU backend's host batch path (coupling.backend: cuda, device: host) against the native
// backend: the same RVEs, the same increments, step by step (stresses to 1e-10 relative over
// 100 coupling steps; the batch keeps the native order of every sum, so they agree bit for
// bit), RVEs with different substep counts in one batch, checkpoints written by one backend
// and resumed by the other. The batch's 3x3 algebra against Eigen, bit for bit.
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <random>
#include <set>

#include "backends/batch/cell_physics.hpp"
#include "backends/batch/cuda_backend.hpp"
#include "backends/batch/sphere_physics.hpp"
#include "backends/native/native_backend.hpp"

namespace {

using namespace mpmdem;
using protocol::RveReply;
using protocol::RveRequest;
using RowMajor3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
namespace b = dem::batch;

b::M3 to_m3(const Eigen::Matrix3d& m) {
  b::M3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r(i, j) = m(i, j);
  return r;
}
int differing(const Eigen::Matrix3d& m, const b::M3& r) {
  int n = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) n += std::memcmp(&m.coeffRef(i, j), &r.a[3 * i + j], 8) != 0;
  return n;
}

TEST(BatchMat3, EqualsEigenBitForBit) {
  std::mt19937_64 g(7);
  std::uniform_real_distribution<double> u(-1, 1);
  int bad = 0;
  for (int t = 0; t < 20000; ++t) {
    Eigen::Matrix3d a, c;
    for (int i = 0; i < 9; ++i) {
      a.data()[i] = u(g) * std::exp(5 * u(g));
      c.data()[i] = u(g) * std::exp(5 * u(g));
    }
    double dF[9];
    for (double& x : dF) x = u(g);
    const double dt = 1e-3 * u(g);
    const Eigen::Matrix3d id = Eigen::Matrix3d::Identity();
    bad += differing(a * c, b::mul(to_m3(a), to_m3(c)));
    const Eigen::Matrix3d target = Eigen::Map<const RowMajor3>(dF) * c;
    bad += differing(target, b::mul_row_major_lhs(b::m3_load(dF), to_m3(c)));
    const Eigen::Matrix3d after = (id + a * dt) * c;
    bad += differing(after, b::mul(b::add(b::m3_identity(), b::scale_r(to_m3(a), dt)), to_m3(c)));
    bad += differing(
        (target * after.inverse() - id) / (3 * dt),
        b::divide(b::sub(b::mul(to_m3(target), b::inverse(to_m3(after))), b::m3_identity()),
                  3 * dt));
    bad += differing(a.inverse(), b::inverse(to_m3(a)));
    const double d = a.determinant(), e = b::det(to_m3(a));
    bad += std::memcmp(&d, &e, 8) != 0;
    // The cell's move and an image shift H c of 16-bit offsets (PeriodicCell, the scan).
    dem::native::PeriodicCell cell;
    cell.hsize = c, cell.vel_grad = a;
    double cb[b::kCellDoubles] = {};
    b::cell_set(cb, b::kHsize, to_m3(c)), b::cell_set(cb, b::kVelGrad, to_m3(a));
    cell.integrate_and_update(dt);
    b::integrate_and_update(cb, dt);
    bad += differing(cell.hsize, b::cell_get(cb, b::kHsize));
    bad += differing(cell.vgrad_times_prev_h, b::cell_get(cb, b::kLh));
    const dem::native::CellDist cd(static_cast<std::int16_t>(t % 7 - 3), -2, 1);
    const Eigen::Vector3d sh = cell.shift(cd);
    const double cv[3] = {static_cast<double>(cd[0]), -2.0, 1.0};
    double out[3];
    b::mul_vec(b::cell_get(cb, b::kHsize), cv, out);
    for (int q = 0; q < 3; ++q) bad += std::memcmp(&sh[q], &out[q], 8) != 0;
    // A flip of a sheared cell (the lattice, bit for bit).
    dem::native::PeriodicCell sheared;
    sheared.hsize = Eigen::Matrix3d::Identity() * 0.01;
    sheared.hsize(0, 1) = 0.01 * (1.5 + u(g)), sheared.hsize(1, 2) = 0.01 * u(g);
    double fb[b::kCellDoubles] = {};
    b::cell_set(fb, b::kHsize, to_m3(sheared.hsize));
    int m[9];
    const bool changed = b::flip(fb, m);
    const Eigen::Matrix3i mm = sheared.flip();
    EXPECT_EQ(changed, mm != Eigen::Matrix3i::Identity());
    bad += differing(sheared.hsize, b::cell_get(fb, b::kHsize));
    // Quaternions: Eigen's product and normalisation.
    Eigen::Quaterniond p(u(g), u(g), u(g), u(g)), q(u(g), u(g), u(g), u(g));
    const Eigen::Quaterniond pq = (p * q).normalized();
    double r[4];
    b::quat_mul(p.coeffs().data(), q.coeffs().data(), r);
    b::quat_normalise(r);
    for (int k = 0; k < 4; ++k) bad += std::memcmp(&pq.coeffs()[k], &r[k], 8) != 0;
  }
  EXPECT_EQ(bad, 0);
}

// ---- the backends side by side ----

dem::NativeParams native_params(bool column_packings) {
  dem::NativeParams p;
  p.inline_spheres = 100;
  p.substeps.kind = dem::SubstepRule::Kind::kProportional;
  p.substeps.ns_factor = 1.5e4;  // the default column's
  p.substeps.ns_min = 2;
  p.substeps.ns_max = 100;
  p.consolidation_tol = 0.02;
  p.consolidation_unbalanced = 0.05;
  if (column_packings) {
    p.packing_dir = std::string(MPMDEM_SOURCE_DIR) + "/packings/column_collapse";
    p.packings = {"col100_s1", "col100_s2", "col100_s3", "col100_s4"};
  }
  return p;
}

template <class Backend>
void start(Backend& be, std::uint64_t n, double p0, RveReply* reply) {
  dem::BackendContext ctx;
  ctx.n_rve = n;
  ctx.outputs = protocol::kKnownOutputs;
  be.setup(ctx);
  std::vector<protocol::RveInit> init(n);
  for (std::uint64_t k = 0; k < n; ++k) {
    std::memset(&init[k], 0, sizeof init[k]);
    init[k].stress[0] = init[k].stress[4] = init[k].stress[8] = -p0 * (1 + 0.2 * k);
    init[k].point = k;
  }
  be.initialise(init.data(), reply);
}

// Increments of different sizes per RVE (so different ns), a shear that grows with the step.
std::vector<RveRequest> requests(std::mt19937_64& rng, std::size_t n, int step) {
  std::vector<RveRequest> req(n);
  for (std::size_t k = 0; k < n; ++k) {
    std::memset(&req[k], 0, sizeof req[k]);
    std::uniform_real_distribution<double> u(-1, 1);
    const double size = 2e-4 * (1 + static_cast<double>(k % 4)) / 4;
    RowMajor3 f = RowMajor3::Identity();
    for (int i = 0; i < 9; ++i) f(i / 3, i % 3) += size * u(rng);
    f(0, 1) += size * (step % 7 == 0 ? 3 : 1);
    Eigen::Map<RowMajor3>(req[k].dF) = f;
    if (step % 13 == 5 && k == 1) req[k].flags = protocol::kFlagQueryOnly;
  }
  return req;
}

double rel_diff(const RveReply& a, const RveReply& c) {
  double num = 0, den = 0;
  for (int i = 0; i < 9; ++i) {
    num = std::max(num, std::abs(a.stress[i] - c.stress[i]));
    den = std::max(den, std::abs(a.stress[i]));
  }
  return den > 0 ? num / den : num;
}

// Runs both backends `steps` coupling steps; returns the largest relative stress difference
// and checks everything else of the replies and the substep counts.
double compare(dem::NativeBackend& nat, dem::CudaBackend& cu, std::size_t n, int first, int steps,
               std::set<int>* ns_seen) {
  std::mt19937_64 rng(1234 + first);
  std::vector<RveReply> rn(n), rc(n);
  double worst = 0;
  for (int s = first; s < first + steps; ++s) {
    const std::vector<RveRequest> req = requests(rng, n, s);
    protocol::ControlHeader h{};
    h.step = s;
    nat.step(h, req.data(), rn.data());
    cu.step(h, req.data(), rc.data());
    for (std::size_t k = 0; k < n; ++k) {
      EXPECT_EQ(rn[k].status, rc[k].status) << "RVE " << k << " step " << s;
      EXPECT_EQ(rn[k].n_substeps, rc[k].n_substeps);
      if (ns_seen) ns_seen->insert(rc[k].n_substeps);
      worst = std::max(worst, rel_diff(rn[k], rc[k]));
      EXPECT_NEAR(rn[k].stiffness, rc[k].stiffness, 1e-10 * std::abs(rn[k].stiffness));
      EXPECT_EQ(rn[k].coordination, rc[k].coordination);
      EXPECT_EQ(rn[k].porosity, rc[k].porosity);
      EXPECT_NEAR(rn[k].unbalanced_force, rc[k].unbalanced_force, 1e-10);
      for (int i = 0; i < 3; ++i) EXPECT_NEAR(rn[k].rotation[i], rc[k].rotation[i], 1e-14);
    }
  }
  return worst;
}

dem::CudaParams host_params(const dem::NativeParams& np) {
  dem::CudaParams p;
  p.native = np;
  p.on_gpu = false;
  return p;
}

void side_by_side(bool column_packings) {
  const std::size_t n = 4;
  const dem::NativeParams np = native_params(column_packings);
  dem::NativeBackend nat(np);
  dem::CudaBackend cu(host_params(np));
  std::vector<RveReply> rn(n), rc(n);
  start(nat, n, 1e4, rn.data());
  start(cu, n, 1e4, rc.data());
  for (std::size_t k = 0; k < n; ++k) EXPECT_EQ(0, std::memcmp(rn[k].stress, rc[k].stress, 72));
  std::set<int> ns_seen;
  const double worst = compare(nat, cu, n, 1, 100, &ns_seen);
  std::cout << "host batch vs native, 100 coupling steps of " << n << " RVEs: largest relative "
            << "stress difference " << worst << ", substep counts seen " << ns_seen.size()
            << std::endl;
  EXPECT_LE(worst, 1e-10);
  EXPECT_GE(ns_seen.size(), 3u);  // mixed counts in one batch (and the query-only 0)
}

TEST(BatchBackend, HostBatchEqualsNativeOnInlineRves) {
  side_by_side(false);
}

TEST(BatchBackend, HostBatchEqualsNativeOnTheDefaultColumnsPackings) {
  if (!std::filesystem::exists(std::string(MPMDEM_SOURCE_DIR) +
                               "/packings/column_collapse/col100_s1.native.txt")) {
    GTEST_SKIP()
        << "packings/column_collapse not built (scripts/run configs/column_collapse_3d.yaml "
           "builds them)";
  }
  side_by_side(true);
}

// A checkpoint written by one backend resumes on the other, and the two continue together.
TEST(BatchBackend, CheckpointsResumeAcrossBackends) {
  const std::size_t n = 3;
  const dem::NativeParams np = native_params(false);
  const auto dir =
      std::filesystem::temp_directory_path() / ("mpmdem_batch_ckpt_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir / "a");
  std::filesystem::create_directories(dir / "b");
  std::vector<RveReply> r(n);
  {  // native writes, cuda resumes
    dem::NativeBackend nat(np);
    start(nat, n, 1e4, r.data());
    dem::CudaBackend warm(host_params(np));
    start(warm, n, 1e4, r.data());
    compare(nat, warm, n, 1, 10, nullptr);
    nat.checkpoint(dir / "a");
    dem::CudaBackend cu(host_params(np));
    dem::BackendContext ctx;
    ctx.n_rve = n;
    ctx.outputs = protocol::kKnownOutputs;
    cu.setup(ctx);
    cu.restore(dir / "a");
    EXPECT_LE(compare(nat, cu, n, 11, 20, nullptr), 1e-10);
    cu.checkpoint(dir / "b");  // cuda writes, native resumes
    dem::NativeBackend nat2(np);
    nat2.setup(ctx);
    nat2.restore(dir / "b");
    EXPECT_LE(compare(nat2, cu, n, 31, 20, nullptr), 1e-10);
    // Migration: an exported RVE adopted by a native backend equals the cuda one's state.
    const std::string blob = cu.export_rve(1);
    const dem::native::RveRecord rec = dem::native::decode(blob);
    EXPECT_EQ(rec.state.spheres.size(), cu.rve(1).state.spheres.size());
    EXPECT_EQ(
        0, std::memcmp(rec.state.spheres.pos.c[0].data(), cu.rve(1).state.spheres.pos.c[0].data(),
                       8 * rec.state.spheres.size()));
  }
  std::filesystem::remove_all(dir);
}

TEST(BatchBackend, GpuWithoutDeviceIsRefusedNamingTheKey) {
  dem::CudaParams p = host_params(native_params(false));
  p.on_gpu = true;
  dem::CudaBackend cu(p);
  dem::BackendContext ctx;
  ctx.n_rve = 1;
  try {
    cu.setup(ctx);
    if (dem::batch::cuda_built()) GTEST_SKIP() << "a GPU is visible here";
    FAIL() << "setup accepted device: gpu without a device";
  } catch (const dem::batch::NoDeviceError& e) {
    EXPECT_NE(std::string(e.what()).find("coupling.cuda.device: host"), std::string::npos);
  }
}

}  // namespace
