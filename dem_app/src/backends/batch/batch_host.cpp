// The host batch path: see batch_host.hpp.
#include "backends/batch/batch_host.hpp"

#include <cmath>
#include <cstddef>

#include "backends/batch/rve_step.hpp"

namespace mpmdem::dem::batch {

namespace {

// A thread group of one: every phase runs in order, reductions and scans are the value itself.
struct HostCtx {
  int tid() const { return 0; }
  int nt() const { return 1; }
  void sync() const {}
  double max_all(double x) const { return x; }
  int max_all(int x) const { return x; }
  int scan(int x, int* total) const {
    *total = x;
    return 0;
  }
  int atomic_add(int* p, int x) const {
    const int old = *p;
    *p += x;
    return old;
  }
};

}  // namespace

void step_batch_host(const BatchView& v, const BatchParams& p, int threads) {
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads) if (threads > 1 && v.n_rve > 1)
  for (int r = 0; r < v.n_rve; ++r) {
    HostCtx ctx;
    rve_step(v, p, r, ctx);
  }
}

}  // namespace mpmdem::dem::batch
