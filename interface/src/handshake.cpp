// The Hello exchange and its compatibility check: see handshake.hpp.
#include "mpmdem/handshake.hpp"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <vector>

#include "mpmdem/errors.hpp"
#include "mpmdem/peer_watch.hpp"

#ifndef MPMDEM_VERSION
#define MPMDEM_VERSION "unknown"
#endif

namespace mpmdem {

namespace {

constexpr int kLabelSize = 256;

template <std::size_t N>
void copy_text(char (&dst)[N], const std::string& src) {
  std::memset(dst, 0, N);
  std::memcpy(dst, src.data(), std::min(src.size(), N - 1));
}

template <std::size_t N>
std::string text(const char (&src)[N]) {
  return std::string(src, strnlen(src, N));
}

std::string hex(std::uint64_t v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "0x%016llx", static_cast<unsigned long long>(v));
  return buf;
}

std::string side_name(const protocol::Hello& h, const char* fallback) {
  const std::string name = text(h.program);
  return name.empty() ? fallback : name;
}

std::string with_file(const std::string& value, const std::string& file) {
  return file.empty() ? value : value + " (" + file + ")";
}

}  // namespace

protocol::Hello make_hello(const HelloFields& f) {
  protocol::Hello h;
  std::memset(&h, 0, sizeof h);
  h.magic = protocol::kMagic;
  h.version_major = protocol::kVersionMajor;
  h.version_minor = protocol::kVersionMinor;
  if (const char* fake = std::getenv("MPMDEM_TEST_FAKE_VERSION_MAJOR"); fake && *fake) {
    h.version_major = static_cast<std::uint16_t>(std::strtoul(fake, nullptr, 10));
  }
  h.request_size = sizeof(protocol::RveRequest);
  h.reply_size = sizeof(protocol::RveReply);
  h.n_rve = f.n_rve;
  h.n_partitions = f.n_partitions;
  h.outputs = f.outputs;
  h.config_hash = f.config_hash;
  copy_text(h.program, f.program);
  copy_text(h.program_version, MPMDEM_VERSION);
  copy_text(h.backend, f.backend);
  return h;
}

std::string output_names(std::uint32_t bits) {
  static const char* const kNames[] = {"rotation", "porosity", "coordination", "unbalanced_force"};
  std::string out;
  for (int b = 0; b < 32; ++b) {
    if (!(bits & (1u << b))) continue;
    if (!out.empty()) out += ", ";
    out += b < 4 ? kNames[b] : "bit" + std::to_string(b);
  }
  return out.empty() ? "none" : out;
}

std::optional<std::string> check_compatible(const protocol::Hello& client,
                                            const protocol::Hello& server,
                                            const std::string& client_config,
                                            const std::string& server_config) {
  const std::string c = side_name(client, "client");
  const std::string s = side_name(server, "server");
  std::vector<std::string> problems;

  // Nothing else is meaningful if these differ.
  if (client.magic != protocol::kMagic || server.magic != protocol::kMagic) {
    return "protocol magic differs: " + c + " " + hex(client.magic) + " vs " + s + " " +
           hex(server.magic) + " (expected " + hex(protocol::kMagic) +
           "; not an mpmdem peer, or another byte order)";
  }
  if (client.version_major != server.version_major) {
    return "protocol major version differs: " + c + " " + std::to_string(client.version_major) +
           "." + std::to_string(client.version_minor) + " (" + text(client.program_version) +
           ") vs " + s + " " + std::to_string(server.version_major) + "." +
           std::to_string(server.version_minor) + " (" + text(server.program_version) +
           "); build both programs from the same source";
  }

  if (client.request_size != server.request_size || client.reply_size != server.reply_size) {
    problems.push_back(
        "wire struct sizes differ: " + c + " RveRequest " + std::to_string(client.request_size) +
        " B / RveReply " + std::to_string(client.reply_size) + " B vs " + s + " " +
        std::to_string(server.request_size) + " B / " + std::to_string(server.reply_size) +
        " B; build both programs with the same compiler and source");
  }
  if (server.n_rve != 0 && server.n_rve != client.n_rve) {
    problems.push_back("RVE count differs: " + c + " " + std::to_string(client.n_rve) +
                       " material points vs " + s + " " + std::to_string(server.n_rve) + " RVEs");
  }
  if (client.n_partitions != server.n_partitions) {
    problems.push_back("partition count differs: " + c + " sees " +
                       std::to_string(client.n_partitions) + " server ranks vs " + s + " runs on " +
                       std::to_string(server.n_partitions));
  }
  if (const std::uint32_t unknown = client.outputs & ~protocol::kKnownOutputs) {
    problems.push_back(c + " asks for unknown outputs (bits " + output_names(unknown) + ")");
  }
  if (const std::uint32_t missing = client.outputs & protocol::kKnownOutputs & ~server.outputs) {
    problems.push_back("outputs requested by " + c + " (coupling.outputs: " +
                       output_names(missing) + ") cannot be provided by " + s + " backend '" +
                       text(server.backend) + "' (provides: " + output_names(server.outputs) + ")");
  }
  if (text(client.backend) != text(server.backend)) {
    problems.push_back("backend differs: " + c + " scene says coupling.backend '" +
                       text(client.backend) + "' vs " + s + " running backend '" +
                       text(server.backend) + "'");
  }
  if (client.config_hash != server.config_hash) {
    problems.push_back("coupling section hash differs: " + c + " " +
                       with_file(hex(client.config_hash), client_config) + " vs " + s + " " +
                       with_file(hex(server.config_hash), server_config) +
                       "; start both programs with the same coupling: section");
  }
  if (problems.empty()) return std::nullopt;
  std::string out;
  for (const auto& p : problems) out += (out.empty() ? "" : "\n") + p;
  return out;
}

std::optional<std::string> minor_version_note(const protocol::Hello& client,
                                              const protocol::Hello& server) {
  if (client.version_major != server.version_major || client.version_minor == server.version_minor)
    return std::nullopt;
  return "note: protocol minor versions differ (" + side_name(client, "client") + " " +
         std::to_string(client.version_major) + "." + std::to_string(client.version_minor) + ", " +
         side_name(server, "server") + " " + std::to_string(server.version_major) + "." +
         std::to_string(server.version_minor) +
         "); compatible, features newer than the older side are not used";
}

HandshakeResult exchange_hello(MPI_Comm intercomm, bool is_client, const protocol::Hello& mine,
                               const std::string& my_config) {
  int rank = 0;
  MPMDEM_CHECK_MPI(MPI_Comm_rank(intercomm, &rank));
  const int send_root = rank == 0 ? MPI_ROOT : MPI_PROC_NULL;
  HandshakeResult r;
  protocol::Hello* const own = is_client ? &r.client : &r.server;
  protocol::Hello* const other = is_client ? &r.server : &r.client;
  *own = mine;
  std::memset(other, 0, sizeof *other);

  // 1. client -> server, 2. server -> client.
  if (is_client) {
    MPMDEM_CHECK_MPI(MPI_Bcast(own, sizeof *own, MPI_BYTE, send_root, intercomm));
    MPMDEM_CHECK_MPI(MPI_Bcast(other, sizeof *other, MPI_BYTE, 0, intercomm));
  } else {
    MPMDEM_CHECK_MPI(MPI_Bcast(other, sizeof *other, MPI_BYTE, 0, intercomm));
    MPMDEM_CHECK_MPI(MPI_Bcast(own, sizeof *own, MPI_BYTE, send_root, intercomm));
  }

  // 3. config labels, only between peers that speak the same major version.
  if (r.client.magic == protocol::kMagic && r.server.magic == protocol::kMagic &&
      r.client.version_major == r.server.version_major) {
    char my_label[kLabelSize] = {};
    char other_label[kLabelSize] = {};
    std::memcpy(my_label, my_config.data(),
                std::min<std::size_t>(my_config.size(), kLabelSize - 1));
    if (is_client) {
      MPMDEM_CHECK_MPI(MPI_Bcast(my_label, kLabelSize, MPI_CHAR, send_root, intercomm));
      MPMDEM_CHECK_MPI(MPI_Bcast(other_label, kLabelSize, MPI_CHAR, 0, intercomm));
    } else {
      MPMDEM_CHECK_MPI(MPI_Bcast(other_label, kLabelSize, MPI_CHAR, 0, intercomm));
      MPMDEM_CHECK_MPI(MPI_Bcast(my_label, kLabelSize, MPI_CHAR, send_root, intercomm));
    }
    other_label[kLabelSize - 1] = '\0';
    (is_client ? r.client_config : r.server_config) = my_config;
    (is_client ? r.server_config : r.client_config) = other_label;
  }

  if (auto problem = check_compatible(r.client, r.server, r.client_config, r.server_config)) {
    throw HandshakeError("handshake refused: " + *problem);
  }

  // 4. who the server ranks are (pid, host), for naming and probing them later.
  if (is_client) {
    int remote = 0;
    MPMDEM_CHECK_MPI(MPI_Comm_remote_size(intercomm, &remote));
    if (rank == 0) r.servers.resize(static_cast<std::size_t>(remote));
    MPMDEM_CHECK_MPI(MPI_Gather(nullptr, 0, MPI_BYTE, r.servers.data(),
                                sizeof(protocol::RankIdentity), MPI_BYTE, send_root, intercomm));
  } else {
    const protocol::RankIdentity me = own_identity(rank);
    MPMDEM_CHECK_MPI(MPI_Gather(&me, sizeof me, MPI_BYTE, nullptr, 0, MPI_BYTE, 0, intercomm));
  }
  return r;
}

}  // namespace mpmdem
