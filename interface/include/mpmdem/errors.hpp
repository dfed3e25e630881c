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
// ranks named in the message (dead ones, or the unprobeable ones after a stall).
class PeerLost : public PeerError {
 public:
  PeerLost(const std::string& what, std::vector<int> ranks)
      : PeerError(what), ranks_(std::move(ranks)) {}
  const std::vector<int>& ranks() const { return ranks_; }

 private:
  std::vector<int> ranks_;
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
