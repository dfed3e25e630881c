// native_checkpoint_bench: the RVEs of a native checkpoint (the states a real run reached:
// sheared, tiled, jammed or not), each advanced by DEM steps at its own pending velocity
// gradient, one after the other on one core; for comparing builds side by side on them.
// Times are the process's CPU time (a shared machine slows the wall clock, not these).
//   native_checkpoint_bench [--stride K] [--steps N] [--damping D] FILE...
// FILE: checkpoint files (CHECKPOINT/dem/native_rank<r>.bin). Every K-th RVE (default 1) of
// each file is stepped N times (default 200; damping default 0.2, the backend's). Prints per
// sphere count: RVEs, tilings, contacts per sphere, CPU time per sphere-step, Verlet
// rebuilds per 100 steps and the cost of one rebuild; then the totals and a hash of the
// stepped states (positions, velocities, contact counts): two builds that give the same hash
// advanced the same RVEs bit for bit.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <iomanip>
#include <iostream>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include <time.h>

#include "backends/native/binary_state.hpp"
#include "backends/native/integrator.hpp"
#include "backends/native/neighbour_list.hpp"

namespace {

using namespace mpmdem::dem::native;

struct Tally {
  long rves = 0, tilings = 0, rebuilds = 0;
  double sphere_steps = 0, contacts = 0, seconds = 0, rebuild_seconds = 0;
};

// FNV-1a over the bits of the values.
struct Hash {
  std::uint64_t h = 1469598103934665603ull;
  void add(const void* p, std::size_t bytes) {
    const auto* c = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < bytes; ++i) h = (h ^ c[i]) * 1099511628211ull;
  }
};

// CPU time of this process [s].
double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

}  // namespace

int main(int argc, char** argv) {
  long stride = 1, steps = 200;
  double damping = 0.2;
  std::vector<std::string> files;
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      if (a == "--stride" || a == "--steps" || a == "--damping") {
        if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
        const std::string v = argv[++i];
        std::size_t used = 0;
        try {
          if (a == "--stride") stride = std::stol(v, &used);
          if (a == "--steps") steps = std::stol(v, &used);
          if (a == "--damping") damping = std::stod(v, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        if (used == 0 || used != v.size()) {
          throw std::invalid_argument(a + ": '" + v + "' is not a number");
        }
      } else if (a.rfind("--", 0) == 0) {
        throw std::invalid_argument("unknown option " + a);
      } else {
        files.push_back(a);
      }
    }
    if (files.empty() || stride < 1 || steps < 1) {
      throw std::invalid_argument("give a checkpoint file, --stride >= 1 and --steps >= 1");
    }
  } catch (const std::exception& e) {
    std::cerr << "native_checkpoint_bench: " << e.what()
              << "\nusage: native_checkpoint_bench [--stride K] [--steps N] [--damping D] "
                 "CHECKPOINT/dem/native_rank<r>.bin...\n";
    return 2;
  }
  std::map<std::size_t, Tally> by_size;
  Hash hash;
  try {
    for (const std::string& file : files) {
      long index = 0;
      read_checkpoint(file, [&](std::uint64_t, const std::string& blob) {
        if (index++ % stride) return;
        RveRecord r = decode(blob);
        RveState& s = r.state;
        Tally& t = by_size[s.spheres.size()];
        NeighbourList list;  // the backend's skin (0.5 of the smallest radius)
        double t0 = cpu_seconds();
        list.ensure(s);  // the first build, timed alone
        t.rebuild_seconds += cpu_seconds() - t0;
        const std::int64_t built = list.rebuilds();
        t0 = cpu_seconds();
        for (long k = 0; k < steps; ++k) dem_step(s, list, damping);
        t.seconds += cpu_seconds() - t0;
        t.rves += 1;
        t.tilings += r.tilings;
        t.rebuilds += list.rebuilds() - built;
        t.sphere_steps += static_cast<double>(s.spheres.size()) * steps;
        t.contacts +=
            static_cast<double>(s.contacts.size()) / std::max<std::size_t>(1, s.spheres.size());
        for (const auto* f : {&s.spheres.pos, &s.spheres.vel}) {
          for (const auto& c : f->c) hash.add(c.data(), c.size() * sizeof(double));
        }
        const std::uint64_t nc = s.contacts.size();
        hash.add(&nc, sizeof nc);
      });
    }
  } catch (const std::exception& e) {
    std::cerr << "native_checkpoint_bench: " << e.what() << "\n";
    return 1;
  }
  Tally all;
  std::cout << std::fixed;
  std::cout << "spheres  RVEs  tilings/RVE  contacts/sphere  us/sphere-step  rebuilds/100 steps  "
               "ms/rebuild\n";
  for (const auto& [n, t] : by_size) {
    std::cout << std::setw(7) << n << std::setw(6) << t.rves << std::setprecision(2)
              << std::setw(13) << double(t.tilings) / t.rves << std::setw(17) << t.contacts / t.rves
              << std::setprecision(4) << std::setw(16) << 1e6 * t.seconds / t.sphere_steps
              << std::setprecision(3) << std::setw(20)
              << 100.0 * t.rebuilds / (double(t.rves) * steps) << std::setw(12)
              << 1e3 * t.rebuild_seconds / t.rves << "\n";
    all.rves += t.rves, all.rebuilds += t.rebuilds, all.seconds += t.seconds;
    all.sphere_steps += t.sphere_steps;
  }
  std::cout << "all: " << all.rves << " RVEs x " << steps << " steps, " << std::setprecision(3)
            << all.seconds << " s, " << std::setprecision(4) << 1e6 * all.seconds / all.sphere_steps
            << " us/sphere-step, " << all.rebuilds << " rebuilds; state hash " << std::hex << hash.h
            << "\n";
  return 0;
}
