// The RVE server loop: see server_loop.hpp.
#include "server_loop.hpp"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <fstream>
#include <iostream>
#include <mutex>
#include <thread>
#include <vector>

#include "migration.hpp"
#include "mpmdem/errors.hpp"
#include "mpmdem/exchange.hpp"
#include "substep_tally.hpp"

namespace mpmdem::dem {

using protocol::ControlHeader;
using protocol::MessageKind;
using protocol::RankReport;
using protocol::RveReply;
using protocol::RveStatus;

namespace {

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

RankReport make_report(int rank) {
  RankReport r;
  std::memset(&r, 0, sizeof r);
  r.rank = rank;
  r.first_fault_rve = -1;
  return r;
}

void set_error(RankReport& r, const std::string& message) {
  r.status = static_cast<std::int32_t>(RveStatus::kBackendError);
  std::memset(r.message, 0, sizeof r.message);
  std::memcpy(r.message, message.data(), std::min(message.size(), sizeof r.message - 1));
}

// Status of the rank = the first fatal RVE status, else the first non-zero one.
void summarise(const std::vector<RveReply>& replies, std::uint64_t first_rve, RankReport& r) {
  for (std::size_t i = 0; i < replies.size(); ++i) {
    const std::int32_t s = replies[i].status;
    if (s == 0) continue;
    ++r.n_faults;
    if (r.first_fault_rve < 0) r.first_fault_rve = static_cast<std::int32_t>(first_rve + i);
    if (r.status == 0 || (!is_fatal(r.status) && is_fatal(s))) {
      r.status = s;
      if (is_fatal(s)) r.first_fault_rve = static_cast<std::int32_t>(first_rve + i);
    }
  }
}

// Ends the server if the client stays silent for too long while the server waits for its
// next message (a client killed with SIGKILL leaves the server blocked in MPI_Bcast
// forever: Open MPI does not report the peer's death). Time spent computing is not counted.
class IdleWatchdog {
 public:
  IdleWatchdog(double seconds, bool root) : seconds_(seconds), root_(root) {
    if (seconds_ > 0.0) thread_ = std::thread([this] { run(); });
  }
  ~IdleWatchdog() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    cv_.notify_all();
    if (thread_.joinable()) thread_.join();
  }
  IdleWatchdog(const IdleWatchdog&) = delete;
  IdleWatchdog& operator=(const IdleWatchdog&) = delete;
  void arm() { set(true); }
  void disarm() { set(false); }

 private:
  void set(bool armed) {
    if (seconds_ <= 0.0) return;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      armed_ = armed;
      since_ = std::chrono::steady_clock::now();
    }
    cv_.notify_all();
  }
  void run() {
    // Non-root ranks wait a little longer so that rank 0 prints first.
    const auto limit = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(seconds_ + (root_ ? 0.0 : 5.0)));
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stop_) {
      if (!armed_) {
        cv_.wait(lock);
        continue;
      }
      const auto deadline = since_ + limit;
      if (cv_.wait_until(lock, deadline) == std::cv_status::timeout && armed_ && !stop_ &&
          std::chrono::steady_clock::now() >= since_ + limit) {
        // Every rank says why it ends: mpirun may tear the job down before the root's
        // message is forwarded when a non-root rank's watchdog fires first.
        std::fprintf(stderr,
                     "dem_app: error: no message from mpm_app for %g s (--idle-timeout)%s; "
                     "assuming it died, exiting\n",
                     seconds_, root_ ? "" : " (non-root rank, after a 5 s grace)");
        std::fflush(stderr);
        std::_Exit(kExitPeerError);
      }
    }
  }

  double seconds_;
  bool root_;
  std::mutex mutex_;
  std::condition_variable cv_;
  bool armed_ = false;
  bool stop_ = false;
  std::chrono::steady_clock::time_point since_;
  std::thread thread_;
};

// Resident set size and its peak [MB] of this process, from /proc/self/status (0 elsewhere).
void memory_mb(double& rss, double& peak) {
  rss = peak = 0.0;
  std::ifstream f("/proc/self/status");
  std::string key;
  double kb = 0.0;
  while (f >> key) {
    if (key == "VmRSS:" && f >> kb) rss = kb / 1024.0;
    if (key == "VmHWM:" && f >> kb) peak = kb / 1024.0;
  }
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// One line per rank at the end: per-step cost of kStep exchanges (scripts/bench_dem reads it).
// compute = backend->step(); exchange = receive + compute + send (after the header arrived).
void print_timing(int rank, std::size_t n_rve, const std::vector<double>& compute,
                  const std::vector<double>& exchange) {
  if (compute.empty()) return;
  double rss = 0.0, peak = 0.0;
  memory_mb(rss, peak);
  double total = 0.0;
  for (double t : compute) total += t;
  const double per = n_rve ? 1e3 / static_cast<double>(n_rve) : 0.0;
  std::fprintf(stderr,
               "dem_app: timing rank %d: %zu steps, %zu RVEs, compute per step median %.4f ms "
               "mean %.4f ms, per RVE-step median %.4f ms; exchange per step median %.4f ms; "
               "RSS %.1f MB, peak %.1f MB\n",
               rank, compute.size(), n_rve, 1e3 * median(compute),
               1e3 * total / static_cast<double>(compute.size()), per * median(compute),
               1e3 * median(exchange), rss, peak);
  std::fflush(stderr);
}

void fail_all(std::vector<RveReply>& replies) {
  for (auto& reply : replies) {
    std::memset(&reply, 0, sizeof reply);
    reply.status = static_cast<std::int32_t>(RveStatus::kBackendError);
  }
}

}  // namespace

int serve(const ServerOptions& opts, const BackendMaker& make_backend) {
  // F_INIT: connect, agree, set up this rank's RVEs.
  RveServerChannel channel;
  HelloFields hello;
  hello.program = "dem_app";
  hello.backend = opts.backend;
  hello.n_rve = 0;  // the client's count is authoritative
  hello.outputs = opts.outputs;
  hello.config_hash = opts.config_hash;
  channel.accept(opts.connect, hello);
  const bool root = channel.rank() == 0;

  BackendContext ctx;
  ctx.first_rve = channel.my_partition().offset;
  ctx.n_rve = channel.my_partition().count;
  ctx.outputs = channel.handshake().client.outputs;
  ctx.rank = channel.rank();
  ctx.n_ranks = channel.ranks();
  ctx.run_dir = opts.run_dir;
  if (root) {
    std::cerr << "dem_app: connected; serving " << channel.n_rve() << " RVEs on " << channel.ranks()
              << " rank(s) with backend '" << opts.backend << "'" << std::endl;
  }

  // A failing set-up is reported on every exchange, so the client aborts with the reason.
  std::string setup_error;
  std::unique_ptr<RveBackend> backend;
  try {
    backend = make_backend(ctx);
    backend->setup(ctx);
    if (!opts.restore_dir.empty()) backend->restore(opts.restore_dir);
  } catch (const std::exception& e) {
    setup_error = "rank " + std::to_string(ctx.rank) + " backend set-up failed: " + e.what();
  }

  std::vector<protocol::RveInit> init;
  std::vector<protocol::RveRequest> requests;
  std::vector<RveReply> replies(ctx.n_rve);
  ControlHeader header;
  std::int64_t steps = 0, rebalances = 0;
  std::vector<Partition> parts = partition_contiguous(channel.n_rve(), channel.ranks());
  IdleWatchdog idle(opts.idle_timeout_s, root);
  std::vector<double> step_compute_s, step_exchange_s;  // per kStep exchange (timing line)
  SubstepTally substeps;
  for (;;) {
    idle.arm();
    const bool more = channel.next(header);
    idle.disarm();
    if (!more) break;
    const double t_exchange = now_s();
    RankReport report = make_report(ctx.rank);
    const auto kind = static_cast<MessageKind>(header.kind);
    // O_I: this rank's part of the payload.
    if (kind == MessageKind::kInitialise) channel.receive(init);
    if (kind == MessageKind::kStep) channel.receive(requests);
    std::vector<Partition> next_parts;
    if (kind == MessageKind::kRebalance) next_parts = channel.receive_partition();

    // S: compute.
    const double t0 = now_s();
    if (!setup_error.empty()) {
      fail_all(replies);
      set_error(report, setup_error);
    } else {
      try {
        if (kind == MessageKind::kInitialise) {
          backend->initialise(init.data(), replies.data());
        } else if (kind == MessageKind::kStep) {
          backend->step(header, requests.data(), replies.data());
          substeps.add(replies.data(), replies.size());
          ++steps;
        } else if (kind == MessageKind::kRebalance) {
          // Every rank knows the old partition (the default one or the last one sent).
          migrate(*backend, parts, next_parts, ctx.rank, channel.comm());
          parts = next_parts;
          const Partition mine = parts[static_cast<std::size_t>(ctx.rank)];
          ctx.first_rve = mine.offset;
          ctx.n_rve = mine.count;
          channel.set_partition(mine);
          replies.assign(ctx.n_rve, RveReply{});
          ++rebalances;
        } else if (kind == MessageKind::kCheckpoint) {
          std::filesystem::path dir = header.path;
          if (dir.is_relative()) dir = opts.run_dir / dir;
          std::error_code ec;
          std::filesystem::create_directories(dir, ec);
          backend->checkpoint(dir);
        }
        if (kind == MessageKind::kInitialise || kind == MessageKind::kStep) {
          summarise(replies, ctx.first_rve, report);
        }
        if (report.status != 0 && kind != MessageKind::kCheckpoint) {
          const std::string why = backend->last_fault_message();
          if (!why.empty()) {
            std::memset(report.message, 0, sizeof report.message);
            std::memcpy(report.message, why.data(),
                        std::min(why.size(), sizeof report.message - 1));
          }
        }
      } catch (const std::exception& e) {
        fail_all(replies);
        set_error(report, std::string(backend->name()) + " backend: " + e.what());
      }
    }
    report.compute_s = now_s() - t0;

    // O_F: answer. The replies are gathered with a non-blocking collective that needs the
    // client's progress: a killed client would leave the rank waiting here, so the idle
    // watchdog covers this wait too.
    idle.arm();
    if (kind == MessageKind::kCheckpoint || kind == MessageKind::kRebalance) {
      channel.send_report(report);
    } else {
      channel.send(replies, report);
    }
    idle.disarm();
    if (kind == MessageKind::kStep) {
      step_compute_s.push_back(report.compute_s);
      step_exchange_s.push_back(now_s() - t_exchange);
    }
  }
  print_timing(ctx.rank, ctx.n_rve, step_compute_s, step_exchange_s);
  if (const std::string line = substeps.line(ctx.rank); !line.empty()) {
    std::fprintf(stderr, "%s\n", line.c_str());
    std::fflush(stderr);
  }

  // Shutdown or Abort: both sides disconnect.
  const bool aborted = channel.aborted();
  const std::string why = channel.abort_message();
  channel.close();
  if (root) {
    if (aborted) {
      std::cerr << "dem_app: mpm_app aborted the run: " << (why.empty() ? "(no reason given)" : why)
                << std::endl;
    } else {
      std::cerr << "dem_app: shutdown after " << steps << " steps";
      if (rebalances > 0) std::cerr << " and " << rebalances << " load-balance migration(s)";
      std::cerr << std::endl;
    }
  }
  return aborted ? kExitPeerError : 0;
}

}  // namespace mpmdem::dem
