// The `remote` provider: every material point is an RVE on the DEM server (dem_app),
// reached over MPI ports through mpmdem::RveClient. One exchange per MPM step.
// Material point p travels in wire slot slot_[p] (coupling.rve_order; partition.hpp): the
// requests are packed into slots and the replies unpacked, and the load balance works on
// slots, since the server ranks own ranges of slots.
#include "constitutive/remote.hpp"

#include <cassert>
#include <cstring>
#include <exception>
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "constitutive/lazy_evaluation.hpp"
#include "constitutive/load_balancer.hpp"
#include "constitutive/rve_point_state.hpp"
#include "mpmdem/exchange.hpp"
#include "mpmdem/partition.hpp"
#include "parallel.hpp"

namespace mpmdem::mpm {

namespace {

using RowMajor3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;

// "on host b ranks 0-1, on host c ranks 2-3": where the server ranks run (they are numbered
// job after job, so each host's ranks form one range unless a job spans hosts).
std::string ranks_by_host(const std::vector<protocol::RankIdentity>& servers) {
  std::string out;
  for (std::size_t r = 0; r < servers.size();) {
    const std::string host(servers[r].host, strnlen(servers[r].host, sizeof servers[r].host));
    std::size_t last = r;
    while (last + 1 < servers.size() &&
           host == std::string(servers[last + 1].host,
                               strnlen(servers[last + 1].host, sizeof servers[last + 1].host)))
      ++last;
    out += (out.empty() ? "on host " : ", on host ") + host +
           (last == r ? " rank " + std::to_string(r)
                      : " ranks " + std::to_string(r) + "-" + std::to_string(last));
    r = last + 1;
  }
  return out;
}

class RemoteProvider : public ConstitutiveProvider {
 public:
  RemoteProvider(const Scene& scene, std::size_t n_points, const std::string& run_dir)
      : slot_(n_points),
        lazy_(scene.coupling.lazy_tolerance),
        balancer_(scene.coupling.load_balance_threshold, scene.coupling.load_balance_min_interval,
                  scene.coupling.load_balance_smoothing) {
    const std::vector<std::uint64_t> order = rve_order(n_points, scene.coupling.rve_order);
    for (std::size_t s = 0; s < order.size(); ++s) slot_[order[s]] = s;
    ConnectOptions opts;
    opts.service_name = scene.coupling.service_name;
    opts.port_file = std::filesystem::path(run_dir) / scene.coupling.port_file;
    opts.timeout_s = scene.coupling.connect_timeout_s;
    opts.peer_timeout_s = scene.coupling.peer_timeout_s;
    opts.config_file = scene.source_file;
    opts.jobs = scene.coupling.dem_jobs;
    HelloFields hello;
    hello.program = "mpm_app";
    hello.backend = scene.coupling.backend;
    hello.n_rve = n_points;
    hello.outputs = scene.coupling.outputs;
    hello.config_hash = scene.coupling.hash;
    client_.connect(opts, hello);
    std::cerr << "mpm_app: connected to dem_app (backend '" << scene.coupling.backend << "', "
              << client_.server_ranks() << " rank(s)";
    if (opts.jobs > 1) std::cerr << " in " << opts.jobs << " jobs";
    std::cerr << ", " << n_points << " RVEs; " << ranks_by_host(client_.handshake().servers) << ")"
              << std::endl;
  }

  // An exception in the solver unwinds through here: tell the server to stop.
  ~RemoteProvider() override {
    if (client_.connected()) client_.abort("mpm_app stopped before the end of the run");
  }

  std::string name() const override { return "remote"; }

  void initialise(const std::vector<Mat3>& initial_stress,
                  std::vector<PointResponse>& out) override {
    std::vector<protocol::RveInit> init(initial_stress.size());
    for (std::size_t p = 0; p < init.size(); ++p) {
      protocol::RveInit& r = init[slot_[p]];
      Eigen::Map<RowMajor3>(r.stress) = initial_stress[p];
      r.point = p;
    }
    const auto replies = client_.initialise(init);
    particles_ = 0;
    for (const protocol::RveReply& r : replies) particles_ += r.n_substeps;
    to_responses(replies, out);
  }

  std::int64_t rve_particles() const override { return particles_; }

  ProviderTiming last_timing() const override {
    const ExchangeTiming& t = client_.last_timing();
    return {t.exchange_s, t.max_compute_s, t.mean_compute_s};
  }

  void update(const std::vector<Mat3>& dF, double dt, std::int64_t step, double time,
              std::vector<PointResponse>& out) override {
    // Points are independent: pack the requests on the solver's threads (the counts are
    // integers, so the result does not depend on the thread count).
    const auto n = static_cast<std::ptrdiff_t>(dF.size());
    requests_.resize(dF.size());
    lazy_.prepare(dF.size());
    std::int64_t runs = 0;
#pragma omp parallel for schedule(static) if (n > kParallelMin) reduction(+ : runs)
    for (std::ptrdiff_t p = 0; p < n; ++p) {
      protocol::RveRequest& r = requests_[slot_[p]];
      r.flags = 0;
      r.reserved = 0;
      Mat3 run_dF;
      if (lazy_.decide(static_cast<std::size_t>(p), dF[p], dt, run_dF, r.dt)) {
        Eigen::Map<RowMajor3>(r.dF) = run_dF;  // row-major: dF[3*i + j] = dF_ij
        ++runs;
      } else {
        Eigen::Map<RowMajor3>(r.dF) = Mat3::Identity();
        r.flags = protocol::kFlagSkip;  // the server returns the RVE's last reply
      }
    }
    lazy_.count(runs, n - runs);
    protocol::ControlHeader header;
    std::memset(&header, 0, sizeof header);
    header.step = step;
    header.time = time;
    header.dt = dt;
    client_.step(header, requests_, replies_);
    step_parts_ = client_.partitions();
    to_responses(replies_, out);
    if (auto next = balancer_.observe(step, replies_, client_.partitions())) {
      const double t0 = MPI_Wtime();
      client_.rebalance(*next, step);
      balancer_.applied(step);
      std::cerr << "mpm_app: [step " << step << "] load balance: RVEs moved between the "
                << client_.server_ranks() << " DEM ranks; smoothed-cost imbalance "
                << balancer_.last_imbalance_before() << " -> "
                << balancer_.last_imbalance_predicted() << " (" << (MPI_Wtime() - t0) << " s)"
                << std::endl;
    }
  }

  bool last_rve_costs(std::vector<double>& cost_s, std::vector<int>& rank) const override {
    cost_s.resize(slot_.size());
    rank.resize(slot_.size());
    // The partition the last step ran on (a migration after it changes the next step's).
    assert(!step_parts_.empty() && "last_rve_costs() before the first step");
    for (std::size_t p = 0; p < slot_.size(); ++p) {
      cost_s[p] = replies_[slot_[p]].cost_s;
      rank[p] = owner_of(step_parts_, slot_[p]);
    }
    return true;
  }

  int dem_ranks() const override {
    return client_.server_ranks();
  }
  std::int64_t rebalances() const override {
    return balancer_.rebalances();
  }
  std::int64_t rve_evaluations() const override {
    return lazy_.evaluations();
  }
  std::int64_t rve_skipped() const override {
    return lazy_.skipped();
  }
  std::vector<double> save_state() const override {
    return lazy_.save();
  }
  void load_state(const std::vector<double>& s) override {
    if (!s.empty()) lazy_.load(s);  // empty: a checkpoint written before lazy evaluation
  }

  // The servers were started with --restore: ask them for the state they restored.
  void resume(const std::vector<Mat3>& stress, std::vector<PointResponse>& out) override {
    requests_.assign(stress.size(), protocol::RveRequest{});
    for (protocol::RveRequest& r : requests_) {
      Eigen::Map<RowMajor3>(r.dF) = Mat3::Identity();
      r.flags = protocol::kFlagQueryOnly;
    }
    protocol::ControlHeader header;
    std::memset(&header, 0, sizeof header);
    client_.step(header, requests_, replies_);
    to_responses(replies_, out);
  }

  void checkpoint(const std::string& dir, std::int64_t step) override {
    client_.checkpoint(dir, step);
  }

  void finish() override {
    client_.shutdown();
  }

 private:
  void to_responses(const std::vector<protocol::RveReply>& replies,
                    std::vector<PointResponse>& out) const {
    out.resize(replies.size());
    const auto n = static_cast<std::ptrdiff_t>(replies.size());
#pragma omp parallel for schedule(static) if (n > kParallelMin)
    for (std::ptrdiff_t p = 0; p < n; ++p) {
      const protocol::RveReply& r = replies[slot_[p]];
      PointResponse& o = out[p];
      o.stress = Eigen::Map<const RowMajor3>(r.stress);
      o.stiffness = r.stiffness;
      o.rotation = Eigen::Vector3d(r.rotation[0], r.rotation[1], r.rotation[2]);
      o.porosity = r.porosity;
      o.coordination = r.coordination;
      o.unbalanced_force = r.unbalanced_force;
      read_rve_status(r.status, o);
    }
  }

  std::vector<std::size_t> slot_;  // material point -> wire slot (coupling.rve_order)
  RveClient client_;
  LazyEvaluation lazy_;
  LoadBalancer balancer_;
  std::int64_t particles_ = 0;
  std::vector<protocol::RveRequest> requests_;
  std::vector<protocol::RveReply> replies_;
  std::vector<Partition> step_parts_;  // the server ranks' slots in the last step
};

}  // namespace

std::unique_ptr<ConstitutiveProvider> make_remote_provider(const Scene& scene, std::size_t n_points,
                                                           const std::string& run_dir) {
  return std::make_unique<RemoteProvider>(scene, n_points, run_dir);
}

}  // namespace mpmdem::mpm
