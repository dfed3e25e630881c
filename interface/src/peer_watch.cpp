// Liveness of the server ranks while the client waits: see peer_watch.hpp.
#include "mpmdem/peer_watch.hpp"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cassert>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <sstream>
#include <thread>

#include "mpmdem/errors.hpp"

namespace mpmdem {

namespace {

std::string host_of(const protocol::RankIdentity& id) {
  return std::string(id.host, strnlen(id.host, sizeof id.host));
}

std::string list(const std::vector<int>& ranks, const PeerWatch& w) {
  std::string out;
  for (std::size_t i = 0; i < ranks.size(); ++i) {
    if (i > 0) out += i + 1 == ranks.size() ? " and " : ", ";
    out += w.describe(ranks[i]);
  }
  return out;
}

// The hosts of `ranks` (one per rank) and a summary by host: "host c: ranks 2, 3".
std::vector<std::string> hosts_of(const std::vector<int>& ranks, const PeerWatch& w) {
  std::vector<std::string> hosts;
  for (int r : ranks) {
    const auto i = static_cast<std::size_t>(r);
    hosts.push_back(r >= 0 && i < w.peers().size() ? host_of(w.peers()[i]) : std::string());
  }
  return hosts;
}

std::string by_host(const std::vector<int>& ranks, const std::vector<std::string>& hosts) {
  std::vector<std::string> order;
  for (const std::string& h : hosts)
    if (std::find(order.begin(), order.end(), h) == order.end()) order.push_back(h);
  std::string out;
  for (const std::string& h : order) {
    std::string those;
    int n = 0;
    for (std::size_t i = 0; i < ranks.size(); ++i) {
      if (hosts[i] != h) continue;
      those += (n++ ? ", " : "") + std::to_string(ranks[i]);
    }
    out += (out.empty() ? "" : "; ") + std::string("host ") + h + (n > 1 ? ": ranks " : ": rank ") +
           those;
  }
  return out;
}

}  // namespace

std::string this_host_name() {
  char buf[256] = {};
  if (::gethostname(buf, sizeof buf - 1) != 0) return "unknown";
  return buf;
}

protocol::RankIdentity own_identity(int rank) {
  protocol::RankIdentity id;
  std::memset(&id, 0, sizeof id);
  id.rank = rank;
  id.pid = static_cast<std::int32_t>(::getpid());
  const std::string host = this_host_name();
  std::memcpy(id.host, host.data(), std::min(host.size(), sizeof id.host - 1));
  return id;
}

void PeerWatch::set_peers(std::vector<protocol::RankIdentity> peers, std::string this_host) {
  peers_ = std::move(peers);
  this_host_ = std::move(this_host);
}

bool PeerWatch::probeable(const protocol::RankIdentity& id) const {
  return id.pid > 0 && !this_host_.empty() && host_of(id) == this_host_;
}

std::vector<int> PeerWatch::dead_ranks() const {
  std::vector<int> dead;
  for (std::size_t r = 0; r < peers_.size(); ++r) {
    const protocol::RankIdentity& id = peers_[r];
    if (!probeable(id)) continue;
    // EPERM: the process exists (another user's); only ESRCH means it is gone. A zombie
    // (killed, not yet reaped by its mpirun) still answers, but mpirun reaps at once.
    if (::kill(static_cast<pid_t>(id.pid), 0) != 0 && errno == ESRCH)
      dead.push_back(static_cast<int>(r));
  }
  return dead;
}

std::string PeerWatch::describe(int rank) const {
  std::ostringstream s;
  s << "DEM server rank " << rank;
  if (rank >= 0 && static_cast<std::size_t>(rank) < peers_.size()) {
    const protocol::RankIdentity& id = peers_[static_cast<std::size_t>(rank)];
    s << " (pid " << id.pid << " on host " << host_of(id) << ")";
  }
  return s.str();
}

void PeerWatch::wait(MPI_Request& request, const std::string& during, double quiet_s) const {
  std::vector<MPI_Request> one{request};
  wait_each(one, {}, during, quiet_s);
  request = one.front();
}

void PeerWatch::wait_each(std::vector<MPI_Request>& requests, const std::vector<int>& from,
                          const std::string& during, double quiet_s) const {
  assert(from.empty() || from.size() == requests.size());
  using Clock = std::chrono::steady_clock;
  const auto seconds = [](double s) {
    return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
  };
  const auto start = Clock::now();
  const auto quiet_end = start + seconds(std::max(quiet_s, 0.0));
  auto next_probe = start + seconds(probe_interval_s_);
  std::chrono::microseconds pause(20);
  std::vector<int> pending;  // indices of the requests not complete yet
  for (;;) {
    pending.clear();
    for (std::size_t i = 0; i < requests.size(); ++i) {
      int done = 0;  // MPI_Test of a completed (null) request says done
      MPMDEM_CHECK_MPI(MPI_Test(&requests[i], &done, MPI_STATUS_IGNORE));
      if (!done) pending.push_back(static_cast<int>(i));
    }
    if (pending.empty()) return;
    if (const auto t = Clock::now(); t < quiet_end) {
      std::this_thread::sleep_for(std::min(quiet_end, next_probe) - t);
    } else {
      std::this_thread::sleep_for(pause);
      pause = std::min(pause * 2, std::chrono::microseconds(1000));
    }
    const auto now = Clock::now();
    if (now < next_probe) continue;
    next_probe = now + seconds(probe_interval_s_);
    if (const std::vector<int> dead = dead_ranks(); !dead.empty()) {
      const std::vector<std::string> hosts = hosts_of(dead, *this);
      throw PeerLost(list(dead, *this) + " died" + " during " + during +
                         " (the process no longer exists; " + by_host(dead, hosts) + ")",
                     dead, hosts, PeerLost::Kind::kDied, true);
    }
    const double waited = std::chrono::duration<double>(now - start).count();
    if (stall_limit_s_ > 0.0 && waited > stall_limit_s_) {
      std::ostringstream msg;
      std::vector<int> named;
      if (!from.empty()) {  // one request per server rank: the silent ones are known
        for (int i : pending) named.push_back(from[static_cast<std::size_t>(i)]);
        msg << "no reply from " << list(named, *this) << " within " << stall_limit_s_
            << " s (coupling.peer_timeout_s) during " << during << " ("
            << requests.size() - pending.size() << " of " << requests.size()
            << " server ranks replied): unreachable, hung or dead ("
            << by_host(named, hosts_of(named, *this)) << ")";
      } else {
        for (std::size_t r = 0; r < peers_.size(); ++r)
          if (!probeable(peers_[r])) named.push_back(static_cast<int>(r));
        msg << "no reply from the DEM server within " << stall_limit_s_
            << " s (coupling.peer_timeout_s) during " << during;
        if (!named.empty()) {
          msg << "; ranks on other hosts, which cannot be probed: " << list(named, *this);
        } else {
          msg << "; every server rank still runs on this host (a hung backend?)";
        }
      }
      msg << ". Raise coupling.peer_timeout_s if one exchange can legitimately take longer";
      throw PeerLost(msg.str(), named, hosts_of(named, *this), PeerLost::Kind::kNoReply,
                     !from.empty());
    }
  }
}

}  // namespace mpmdem
