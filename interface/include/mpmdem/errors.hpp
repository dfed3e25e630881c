// Typed errors of the coupling (the second tier of error handling: faults of the peer, of
// the MPI runtime or of the launch, each with a message that says what to change) and the
// process exit codes both programs use for them.
#pragma once

#include <mpi.h>

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace mpmdem {

// Exit codes shared by mpm_app and dem_app (0 = success).
inline constexpr int kExitConfigError = 2;     // bad scene / command line
inline constexpr int kExitHandshakeError = 3;  // peers disagree (version, config hash, ...)
inline constexpr int kExitPeerError = 4;       // no peer, MPI failure, peer reported an error

// The other side failed, disappeared, or an MPI call on the coupling failed.
class PeerError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A server rank died or stopped answering during an exchange (peer fault); ranks() are the
// ranks named in the message (dead ones, or the unprobeable ones after a stall) and hosts()
// their hosts (one per rank). exact(): the named ranks are exactly the ones at fault (a
// probed death, or a stall of one message per rank); false after a stall of a collective,
// which names every rank it cannot probe.
class PeerLost : public PeerError {
 public:
  enum class Kind { kDied, kNoReply };
  PeerLost(const std::string& what, std::vector<int> ranks, std::vector<std::string> hosts = {},
           Kind kind = Kind::kNoReply, bool exact = false)
      : PeerError(what),
        ranks_(std::move(ranks)),
        hosts_(std::move(hosts)),
        kind_(kind),
        exact_(exact) {}
  const std::vector<int>& ranks() const { return ranks_; }
  const std::vector<std::string>& hosts() const { return hosts_; }
  Kind kind() const { return kind_; }
  bool exact() const { return exact_; }

 private:
  std::vector<int> ranks_;
  std::vector<std::string> hosts_;
  Kind kind_;
  bool exact_;
};

// No peer found / accepted within the connect timeout.
class ConnectTimeout : public PeerError {
 public:
  using PeerError::PeerError;
};

// The handshake found the two sides incompatible; the message names both values.
class HandshakeError : public PeerError {
 public:
  using PeerError::PeerError;
};

// Text of an MPI error code ("MPI_ERR_PORT: invalid port").
std::string mpi_error_string(int code);

// Throws PeerError("<what> failed at <file>:<line>: <MPI error string>") if rc != MPI_SUCCESS.
void check_mpi(int rc, const char* what, const char* file, int line);

}  // namespace mpmdem

// Wrap every MPI call on the coupling path: MPMDEM_CHECK_MPI(MPI_Bcast(...));
#define MPMDEM_CHECK_MPI(call) ::mpmdem::check_mpi((call), #call, __FILE__, __LINE__)
