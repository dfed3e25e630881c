// The handshake right after connect: both sides exchange protocol::Hello, then both run the
// same pure check (check_compatible) on the pair, so both reach the same verdict and print
// the same message naming both values. Exchange on the intercommunicator:
//   1. client root bcasts its Hello (MPI_ROOT), the server ranks receive it;
//   2. server rank 0 bcasts its Hello (MPI_ROOT; other server ranks MPI_PROC_NULL);
//   3. if magic and major version agree: the same two broadcasts of a 256-byte
//      NUL-terminated label (the config file each side read), used in messages only;
//   4. (3.0) if compatible: every server rank sends its protocol::RankIdentity (pid, host) to
//      the client root (MPI_Gather), which keeps them in HandshakeResult::servers.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "mpmdem/protocol.hpp"

namespace mpmdem {

// What one side says about itself. For the server: n_rve = 0 means "whatever the client
// says", outputs = the outputs its backend can provide (capability mask).
struct HelloFields {
  std::string program;  // "mpm_app", "dem_app", ...
  std::string backend;  // client: coupling.backend of its scene; server: its backend
  std::uint64_t n_rve = 0;
  int n_partitions = 0;  // client: remote group size; server: its rank count
  std::uint32_t outputs = 0;
  std::uint64_t config_hash = 0;
};

// Fills magic, versions and struct sizes of this build. Test hook: the environment variable
// MPMDEM_TEST_FAKE_VERSION_MAJOR overrides version_major (to test the refusal end to end).
protocol::Hello make_hello(const HelloFields& fields);

// nullopt if the pair can work together; otherwise one line per problem, each naming both
// values. Minor version differences are accepted (see minor_version_note).
std::optional<std::string> check_compatible(const protocol::Hello& client,
                                            const protocol::Hello& server,
                                            const std::string& client_config = "",
                                            const std::string& server_config = "");
// "peer speaks protocol 1.2, this build 1.0" when only the minor versions differ.
std::optional<std::string> minor_version_note(const protocol::Hello& client,
                                              const protocol::Hello& server);

// Names of the output bits ("rotation, porosity").
std::string output_names(std::uint32_t bits);

struct HandshakeResult {
  protocol::Hello client;
  protocol::Hello server;
  std::string client_config;
  std::string server_config;
  std::vector<protocol::RankIdentity> servers;  // client root: one per server rank, by rank
};

// Run the exchange on the side given by `is_client`. Throws HandshakeError (with the
// check_compatible message) on mismatch, PeerError on MPI failure. Does not disconnect.
HandshakeResult exchange_hello(MPI_Comm intercomm, bool is_client, const protocol::Hello& mine,
                               const std::string& my_config);

}  // namespace mpmdem
