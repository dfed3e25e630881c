// batch_bench: the GPU backend's batch (coupling.backend: cuda) on many RVEs, for the device
// check (tests/device/check.sh) and CPU measurements. RVEs come from a native checkpoint file
// (--load), from native packings (--packings DIR/NAME,DIR/NAME2: <name>.native.txt, as read by
// the native backend, unconsolidated) or are built in place (Table 1 clouds of --spheres spheres
// consolidated to 10 kPa by the native backend, --distinct of them, one per thread) and may be
// saved (--save) for the next run; the batch repeats them to --rves RVEs. Every RVE gets its own
// small random dF per step (seeded by RVE and step: the same on every path) and --ns substeps (or,
// with --mixed, ns between 2 and --ns drawn per RVE and step: mixed counts in one launch).
//   --device gpu|host   where the batch runs (host: the same code on the CPU, --threads)
//   --validate R        R RVEs on the device and on the host batch path, --steps steps, every
//                       reply compared (stress relative difference; exit 1 above 1e-10)
//   --native M          M of the RVEs through the native backend on one core, the same dF
//                       and ns: its sphere-steps/s beside the batch's
// Prints sphere-steps/s (spheres x substeps x RVEs / wall time of the steps) and, on a GPU,
// the kernel time and the host-device copies per step.
#include <omp.h>
#include <unistd.h>

#include <Eigen/Core>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "backends/batch/batch_device.hpp"
#include "backends/batch/batch_host.hpp"
#include "backends/batch/batch_state.hpp"
#include "backends/native/binary_state.hpp"
#include "backends/native/native_backend.hpp"
#include "backends/native/packing.hpp"

namespace {

using namespace mpmdem;
using namespace mpmdem::dem;
using Clock = std::chrono::steady_clock;

struct Options {
  std::string load, save, packings, device = "gpu";
  int spheres = 100, distinct = 4, ns = 100, steps = 5, validate = 0, native = 0, threads = 1;
  int tpb = 128;
  long rves = 1560;
  bool mixed = false;
};

std::vector<native::RveRecord> build(const Options& o) {
  std::vector<native::RveRecord> out(static_cast<std::size_t>(o.distinct));
#pragma omp parallel for schedule(dynamic, 1)
  for (int d = 0; d < o.distinct; ++d) {
    NativeParams p;
    p.inline_spheres = o.spheres;
    p.seed = 1 + d;
    p.consolidation_tol = 0.02;
    p.consolidation_unbalanced = 0.05;
    NativeBackend nb(p);
    BackendContext ctx;
    ctx.n_rve = 1;
    nb.setup(ctx);
    protocol::RveInit init;
    std::memset(&init, 0, sizeof init);
    init.stress[0] = init.stress[4] = init.stress[8] = -1e4;
    protocol::RveReply reply;
    nb.initialise(&init, &reply);
    out[static_cast<std::size_t>(d)] = nb.rve(0);
  }
  return out;
}

std::vector<native::RveRecord> from_packings(const std::string& list) {
  std::vector<native::RveRecord> out;
  std::size_t a = 0;
  while (a <= list.size()) {
    const std::size_t b = std::min(list.find(',', a), list.size());
    native::RveRecord r;
    r.state = native::read_packing(list.substr(a, b - a) + native::kPackingExtension);
    r.state.contacts.sort_by_first();  // as NativeBackend::make_rve
    r.p0 = 1e4;
    out.push_back(std::move(r));
    a = b + 1;
  }
  return out;
}

std::vector<native::RveRecord> load(const std::string& file) {
  std::vector<native::RveRecord> out;
  native::read_checkpoint(
      file, [&](std::uint64_t, const std::string& blob) { out.push_back(native::decode(blob)); });
  if (out.empty()) throw std::runtime_error(file + " holds no RVE");
  return out;
}

void save(const std::string& file, const std::vector<native::RveRecord>& rves) {
  std::ofstream f(file, std::ios::binary | std::ios::trunc);
  native::write_checkpoint_header(f, rves.size());
  for (std::size_t k = 0; k < rves.size(); ++k)
    native::write_checkpoint_record(f, k, native::encode(rves[k]));
  if (!f) throw std::runtime_error("cannot write " + file);
}

// The step inputs of step s for RVEs [0, n).
void inputs(std::vector<batch::StepIn>& in, std::size_t n, int s, const Options& o) {
  for (std::size_t k = 0; k < n; ++k) {
    std::mt19937_64 rng(k * 1000003u + static_cast<std::uint64_t>(s));
    std::uniform_real_distribution<double> u(-1e-4, 1e-4);
    batch::StepIn& x = in[k];
    std::memset(&x, 0, sizeof x);
    for (int i = 0; i < 9; ++i) x.dF[i] = (i % 4 == 0 ? 1.0 : 0.0) + u(rng);
    x.ns = o.mixed ? 2 + static_cast<int>(rng() % static_cast<std::uint64_t>(o.ns - 1)) : o.ns;
    x.flags = batch::kStepActive | (s % 10 == 0 ? batch::kStepTileCheck : 0);
  }
}

batch::BatchParams params() {
  return {0.2, 10, 0.5, 1, protocol::kOutputRotation};
}

struct Run {
  double seconds = 0, sphere_steps = 0;
};

// steps of the whole batch on the device (dev) or the host; out_each: the replies per step.
Run run(batch::BatchState& b, batch::DeviceBatch* dev, const Options& o,
        std::vector<std::vector<batch::StepOut>>* out_each) {
  Run r;
  const std::size_t n = static_cast<std::size_t>(b.n_rve());
  for (int s = 1; s <= o.steps; ++s) {
    inputs(b.in(), n, s, o);
    const auto t0 = Clock::now();
    if (dev) {
      dev->step(b, params());
    } else {
      batch::step_batch_host(b.view(), params(), o.threads);
    }
    r.seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    for (std::size_t k = 0; k < n; ++k) {
      r.sphere_steps +=
          static_cast<double>(b.in()[k].ns) * static_cast<double>(b.sph0_[k + 1] - b.sph0_[k]);
      if (b.out()[k].error)
        throw std::runtime_error("RVE " + std::to_string(k) + " outgrew its capacity");
    }
    if (out_each) out_each->push_back(b.out());
  }
  return r;
}

int validate(const std::vector<native::RveRecord>& src, const Options& o) {
  const std::size_t n = static_cast<std::size_t>(o.validate);
  const auto get = [&](std::size_t k) -> const native::RveRecord& { return src[k % src.size()]; };
  batch::BatchState host, gpu;
  host.pack(n, get, {});
  gpu.pack(n, get, {});
  auto dev = batch::DeviceBatch::create(-1, 0, o.tpb);
  dev->upload(gpu);
  std::vector<std::vector<batch::StepOut>> oh, og;
  run(host, nullptr, o, &oh);
  run(gpu, dev.get(), o, &og);
  double worst = 0;
  long same = 0, total = 0;
  for (std::size_t s = 0; s < oh.size(); ++s) {
    for (std::size_t k = 0; k < n; ++k) {
      double num = 0, den = 0;
      for (int i = 0; i < 9; ++i) {
        num = std::max(num, std::abs(oh[s][k].stress[i] - og[s][k].stress[i]));
        den = std::max(den, std::abs(oh[s][k].stress[i]));
      }
      worst = std::max(worst, den > 0 ? num / den : num);
      same += std::memcmp(oh[s][k].stress, og[s][k].stress, sizeof oh[s][k].stress) == 0 &&
              oh[s][k].status == og[s][k].status;
      ++total;
    }
  }
  std::cout << "validate: " << n << " RVEs x " << o.steps << " steps on " << dev->name()
            << " against the host batch path: largest relative stress difference " << worst
            << ", replies bit for bit equal " << same << " / " << total << std::endl;
  return worst <= 1e-10 ? 0 : 1;
}

double native_rate(const std::vector<native::RveRecord>& src, const Options& o) {
  const std::size_t m = static_cast<std::size_t>(o.native);
  const auto dir =
      std::filesystem::temp_directory_path() / ("batch_bench_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::vector<native::RveRecord> rec(m);
  for (std::size_t k = 0; k < m; ++k) rec[k] = src[k % src.size()];
  save((dir / "native_rank0.bin").string(), rec);
  NativeParams p;
  p.substeps.kind = SubstepRule::Kind::kFixed;
  NativeBackend nb(p);
  nb.set_threads(1);
  BackendContext ctx;
  ctx.n_rve = m;
  ctx.outputs = protocol::kOutputRotation;
  nb.setup(ctx);
  nb.restore(dir);
  std::filesystem::remove_all(dir);
  std::vector<batch::StepIn> in(m);
  double seconds = 0, sphere_steps = 0;
  for (int s = 1; s <= o.steps; ++s) {
    inputs(in, m, s, o);
    const auto t0 = Clock::now();
    for (std::size_t k = 0; k < m; ++k) {  // the backend's burst, RVE by RVE (one core)
      nb.burst(k, in[k].dF, in[k].ns);
      sphere_steps +=
          static_cast<double>(in[k].ns) * static_cast<double>(rec[k].state.spheres.size());
    }
    seconds += std::chrono::duration<double>(Clock::now() - t0).count();
  }
  return sphere_steps / seconds;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      const auto next = [&]() -> std::string {
        if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
        return argv[++i];
      };
      if (a == "--load")
        o.load = next();
      else if (a == "--save")
        o.save = next();
      else if (a == "--packings")
        o.packings = next();
      else if (a == "--device")
        o.device = next();
      else if (a == "--spheres")
        o.spheres = std::stoi(next());
      else if (a == "--distinct")
        o.distinct = std::stoi(next());
      else if (a == "--rves")
        o.rves = std::stol(next());
      else if (a == "--ns")
        o.ns = std::stoi(next());
      else if (a == "--steps")
        o.steps = std::stoi(next());
      else if (a == "--validate")
        o.validate = std::stoi(next());
      else if (a == "--native")
        o.native = std::stoi(next());
      else if (a == "--threads")
        o.threads = std::stoi(next());
      else if (a == "--threads-per-block")
        o.tpb = std::stoi(next());
      else if (a == "--mixed")
        o.mixed = true;
      else
        throw std::invalid_argument("unknown argument " + a + " (see the head of batch_bench.cpp)");
    }
    if (o.ns < 2) throw std::invalid_argument("--ns must be >= 2");
    const auto t0 = Clock::now();
    const std::vector<native::RveRecord> src = !o.load.empty()       ? load(o.load)
                                               : !o.packings.empty() ? from_packings(o.packings)
                                                                     : build(o);
    std::cout << "RVEs: " << src.size() << " distinct of " << src[0].state.spheres.size()
              << " spheres (" << std::chrono::duration<double>(Clock::now() - t0).count()
              << " s to " << (o.load.empty() ? "build" : "load") << ")" << std::endl;
    if (!o.save.empty()) save(o.save, src);
    if (o.validate > 0) return validate(src, o);
    if (o.native > 0) {
      std::cout << "native backend, one core, " << o.native << " RVEs x " << o.steps
                << " steps: " << native_rate(src, o) << " sphere-steps/s" << std::endl;
    }
    if (o.rves <= 0) return 0;
    batch::BatchState b;
    b.pack(static_cast<std::size_t>(o.rves),
           [&](std::size_t k) -> const native::RveRecord& { return src[k % src.size()]; }, {});
    std::unique_ptr<batch::DeviceBatch> dev;
    if (o.device == "gpu") {
      dev = batch::DeviceBatch::create(-1, 0, o.tpb);
      dev->upload(b);
    }
    const Run r = run(b, dev.get(), o, nullptr);
    std::cout << "batch on "
              << (dev ? dev->name() : "the host (" + std::to_string(o.threads) + " threads)")
              << ": " << o.rves << " RVEs x " << b.n_spheres() / o.rves << " spheres x "
              << (o.mixed ? "mixed 2.." : "") << o.ns << " substeps x " << o.steps
              << " steps: " << r.sphere_steps / r.seconds << " sphere-steps/s ("
              << r.seconds / o.steps << " s per coupling step; batch "
              << static_cast<double>(b.bytes()) / 1e9 << " GB)";
    if (dev) {
      const auto& t = dev->tally();
      std::cout << "; kernel " << t.kernel_s / o.steps << " s per step, "
                << static_cast<double>(t.copies) / static_cast<double>(t.steps)
                << " host-device copies per step (" << t.bytes / t.steps << " bytes)";
    }
    std::cout << std::endl;
  } catch (const std::exception& e) {
    std::cerr << "batch_bench: " << e.what() << std::endl;
    return 2;
  }
  return 0;
}
