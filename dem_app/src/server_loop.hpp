// The RVE server loop (MUSCLE3 submodel shape): accept one mpm_app, agree in the
// handshake, create this rank's backend for its partition, then
//   while (channel.next(header)) { receive; compute; send; }
// until Shutdown or Abort. A backend exception becomes a RankReport with kBackendError and
// the message; the server keeps serving so the client can abort cleanly.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>

#include "backend.hpp"
#include "mpmdem/connection.hpp"

namespace mpmdem::dem {

struct ServerOptions {
  ConnectOptions connect;         // service name, port file, timeout, config file
  std::string backend;            // name, announced in the Hello
  std::uint32_t outputs = 0;      // what the backend can provide
  std::uint64_t config_hash = 0;  // hash of the canonical coupling section
  std::filesystem::path run_dir;
  std::filesystem::path restore_dir;  // empty: start from the client's kInitialise
  double idle_timeout_s = 0.0;        // > 0: exit if the client is silent this long
};

using BackendMaker = std::function<std::unique_ptr<RveBackend>(const BackendContext&)>;

// Collective over MPI_COMM_WORLD (and, with several jobs, over theirs: connect.jobs). Returns 0
// after Shutdown, kExitPeerError after the client aborted. Throws HandshakeError (exit 3) and
// PeerError (exit 4).
int serve(const ServerOptions& opts, const BackendMaker& make_backend);

}  // namespace mpmdem::dem
