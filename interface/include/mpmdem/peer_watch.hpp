// Liveness of the server ranks while the client waits for an exchange (peer faults).
//
// Open MPI 4.1 does not report a peer process killed with SIGKILL: a collective on the
// intercommunicator just never completes. The client therefore waits through PeerWatch,
// which tests the request without spinning (sleeps of 20 us growing to 1 ms) and, every
// probe interval, checks the server ranks it knows (protocol::RankIdentity from the
// handshake): a rank on this host whose process is gone (kill(pid, 0) fails with ESRCH)
// ends the wait at once; ranks on other hosts cannot be probed, so a stall limit (no
// completion for that long, coupling.peer_timeout_s) ends it too. Either way PeerLost is
// thrown, naming the rank(s), their pid and host, and what the client was waiting for. Waits
// with one request per server rank (the replies) name exactly the ranks that did not answer.
#pragma once

#include <mpi.h>

#include <string>
#include <vector>

#include "mpmdem/protocol.hpp"

namespace mpmdem {

class PeerWatch {
 public:
  PeerWatch() = default;
  // The server ranks (index = rank) as they introduced themselves; `this_host` is the
  // client's host name (ranks with another host name are not probed).
  void set_peers(std::vector<protocol::RankIdentity> peers, std::string this_host);
  // Longest wait for one request with no completion [s]; 0 or less: no limit.
  void set_stall_limit(double seconds) { stall_limit_s_ = seconds; }
  void set_probe_interval(double seconds) { probe_interval_s_ = seconds; }
  double stall_limit() const { return stall_limit_s_; }

  // Waits for `request` (MPI_Test). Throws PeerError if MPI reports an error, PeerLost if
  // a server rank died or the stall limit passed; `during` says what the client waited
  // for ("step 57"), for the message. `quiet_s`: a time in which the request is not
  // expected to complete (the peers are computing); it is slept in long sleeps, still
  // probing the peers every probe interval, instead of polled. Polling wakes the process
  // ~1000 times a second, and on a machine whose cores all run DEM ranks each wake-up
  // takes a core from one of them.
  void wait(MPI_Request& request, const std::string& during, double quiet_s = 0.0) const;
  // The same for several requests, `from[i]` the server rank request i waits for (or empty:
  // not per rank). Past the stall limit it names the ranks whose requests are not complete
  // (on another host: unreachable, hung or dead), not every rank it cannot probe.
  void wait_each(std::vector<MPI_Request>& requests, const std::vector<int>& from,
                 const std::string& during, double quiet_s = 0.0) const;

  // Server ranks on this host whose process no longer exists.
  std::vector<int> dead_ranks() const;
  // "DEM server rank 1 (pid 1234 on host node7)".
  std::string describe(int rank) const;
  const std::vector<protocol::RankIdentity>& peers() const { return peers_; }

 private:
  bool probeable(const protocol::RankIdentity& id) const;

  std::vector<protocol::RankIdentity> peers_;
  std::string this_host_;
  double stall_limit_s_ = 0.0;
  double probe_interval_s_ = 0.25;
};

// This process as a RankIdentity (pid, host name) for the handshake.
protocol::RankIdentity own_identity(int rank);
// The host name of this process (gethostname).
std::string this_host_name();

}  // namespace mpmdem
