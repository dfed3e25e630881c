// native_replay: one native RVE driven by a dF sequence from a file, outside MPI, for the
// side-by-side comparison with YADE (tests/integration/native_vs_yade.sh) and benchmarks.
//   native_replay --packing FILE.native.txt --df FILE [--ns N] [--damping D] [--repeat R]
//                 [--resident K] [--restitution E]
// FILE: one dF per line (9 numbers, row-major). Prints "init" and "step <n>" lines with the
// 9 stress components (symmetrised, 17 digits) and the contact count; with --repeat R the
// sequence is applied R times and the last lines report particle-steps per second and the
// binary state's size and encode/decode times; --resident K reports the RSS growth per RVE
// with K resident RVEs instead. --restitution E: the frict_visco law with e_n = E
// (coupling.native.contact_law frict_visco, restitution_normal E); default the frict law.
#include <Eigen/Core>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "backends/native/binary_state.hpp"
#include "backends/native/native_backend.hpp"

namespace {
// Resident set size of this process [KB] (/proc/self/statm).
long resident_kb() {
  std::ifstream statm("/proc/self/statm");
  long pages_total = 0, pages_resident = 0;
  statm >> pages_total >> pages_resident;
  return pages_resident * (sysconf(_SC_PAGESIZE) / 1024);
}
}  // namespace

int main(int argc, char** argv) {
  std::string packing, df_file;
  mpmdem::dem::NativeParams p;
  p.substeps.kind = mpmdem::dem::SubstepRule::Kind::kFixed;
  long repeat = 1;
  long resident = 0;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i], v = argv[i + 1];
    if (k == "--packing") {
      packing = v;
    } else if (k == "--df") {
      df_file = v;
    } else if (k == "--ns") {
      p.substeps.ns = std::stoi(v);
    } else if (k == "--damping") {
      p.damping = std::stod(v);
    } else if (k == "--repeat") {
      repeat = std::stol(v);
    } else if (k == "--resident") {
      resident = std::stol(v);
    } else if (k == "--restitution") {
      p.law = mpmdem::dem::native::frict_visco_law(std::stod(v));
    } else {
      std::cerr << "native_replay: unknown option " << k << "\n";
      return 2;
    }
  }
  if (packing.empty() || df_file.empty() || p.substeps.ns < 2) {
    std::cerr << "usage: native_replay --packing FILE.native.txt --df FILE [--ns N>=2] "
                 "[--damping D] [--repeat R]\n";
    return 2;
  }
  try {
    const std::filesystem::path path(packing);
    std::string name = path.filename().string();
    name = name.substr(0, name.size() - std::strlen(".native.txt"));
    p.packing_dir = path.parent_path().string();
    p.packings = {name};
    std::vector<std::vector<double>> dfs;
    std::ifstream in(df_file);
    if (!in) throw std::runtime_error("cannot read " + df_file);
    for (std::string line; std::getline(in, line);) {
      std::istringstream s(line);
      std::vector<double> v(9);
      for (double& x : v) s >> x;
      if (s) dfs.push_back(v);
    }
    if (resident > 0) {
      // Memory per resident RVE: RSS growth with `resident` RVEs of this packing in one
      // backend (initialised, one coupling step each so the Verlet lists exist).
      const long before = resident_kb();
      mpmdem::dem::NativeBackend many(p);
      mpmdem::dem::BackendContext mctx;
      mctx.n_rve = static_cast<std::uint64_t>(resident);
      many.setup(mctx);
      std::vector<mpmdem::protocol::RveInit> inits(mctx.n_rve);
      std::vector<mpmdem::protocol::RveReply> replies(mctx.n_rve);
      std::vector<mpmdem::protocol::RveRequest> reqs(mctx.n_rve);
      for (auto& q : reqs) std::memcpy(q.dF, dfs.at(0).data(), sizeof q.dF);
      many.initialise(inits.data(), replies.data());
      mpmdem::protocol::ControlHeader mh{};
      mh.step = 1;
      many.step(mh, reqs.data(), replies.data());
      const long after = resident_kb();
      std::printf("resident_rves %ld rss_kb_per_rve %.1f\n", resident,
                  static_cast<double>(after - before) / static_cast<double>(resident));
      // Where it goes (allocated capacity of RVE 0's arrays).
      const auto& s0 = many.rve(0).state;
      std::printf(
          "heap_kb spheres %.1f (%zu) contacts %.1f (%zu) neighbour_list %.1f (%zu pairs)\n",
          s0.spheres.heap_bytes() / 1024.0, s0.spheres.size(), s0.contacts.heap_bytes() / 1024.0,
          s0.contacts.size(), many.neighbour_list(0).heap_bytes() / 1024.0,
          many.neighbour_list(0).n_pairs());
      return 0;
    }
    mpmdem::dem::NativeBackend b(p);
    mpmdem::dem::BackendContext ctx;
    ctx.n_rve = 1;
    b.setup(ctx);
    mpmdem::protocol::RveInit init{};
    mpmdem::protocol::RveReply reply{};
    b.initialise(&init, &reply);
    auto print = [&](const std::string& tag) {
      std::printf("%s", tag.c_str());
      for (double x : reply.stress) std::printf(" %.17g", x);
      std::printf(" %zu\n", b.rve(0).state.contacts.size());
    };
    print("init");
    mpmdem::protocol::ControlHeader h{};
    mpmdem::protocol::RveRequest req{};
    const auto t0 = std::chrono::steady_clock::now();
    long steps = 0;
    for (long r = 0; r < repeat; ++r) {
      for (std::size_t n = 0; n < dfs.size(); ++n) {
        std::memcpy(req.dF, dfs[n].data(), sizeof req.dF);
        h.step = ++steps;
        b.step(h, &req, &reply);
        if (repeat == 1) print("step " + std::to_string(n + 1));
      }
    }
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (repeat > 1) {
      const double ps = static_cast<double>(steps) * p.substeps.ns *
                        static_cast<double>(b.rve(0).state.spheres.size());
      std::printf("particle_steps_per_s %.4g coupling_steps %ld wall_s %.4g\n", ps / wall, steps,
                  wall);
      // Checkpoint / migration cost: the binary state of the RVE, encoded and decoded.
      const int reps = 1000;
      std::string blob;
      const auto e0 = std::chrono::steady_clock::now();
      for (int i = 0; i < reps; ++i) blob = mpmdem::dem::native::encode(b.rve(0));
      const auto e1 = std::chrono::steady_clock::now();
      for (int i = 0; i < reps; ++i) mpmdem::dem::native::decode(blob);
      const auto e2 = std::chrono::steady_clock::now();
      std::printf("state_bytes %zu encode_us %.3g decode_us %.3g verlet_rebuilds %lld\n",
                  blob.size(), 1e6 * std::chrono::duration<double>(e1 - e0).count() / reps,
                  1e6 * std::chrono::duration<double>(e2 - e1).count() / reps,
                  static_cast<long long>(b.neighbour_list(0).rebuilds()));
    }
  } catch (const std::exception& e) {
    std::cerr << "native_replay: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
