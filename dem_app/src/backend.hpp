// An RVE backend: owns the RVEs of one server rank and advances them.
// The server loop (server_loop.cpp) handles the protocol; a backend only does mechanics.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>

#include "mpmdem/protocol.hpp"

namespace mpmdem::dem {

struct BackendContext {
  std::uint64_t first_rve = 0;  // global id of this rank's first RVE
  std::uint64_t n_rve = 0;      // RVEs owned by this rank
  std::uint32_t outputs = 0;    // protocol::OutputBits requested by the scene
  int rank = 0;
  int n_ranks = 1;  // ranks of the server
  std::filesystem::path run_dir;
};

class RveBackend {
 public:
  virtual ~RveBackend() = default;
  virtual std::string name() const = 0;
  // Called once after the handshake; allocates this rank's RVEs.
  virtual void setup(const BackendContext& ctx) = 0;
  // Set each owned RVE's starting stress; fill one reply per RVE.
  virtual void initialise(const protocol::RveInit* init, protocol::RveReply* reply) = 0;
  // Advance each owned RVE by its request; fill one reply per RVE. Faults inside an RVE go
  // into RveReply::status; an exception means the whole rank failed.
  virtual void step(const protocol::ControlHeader& header, const protocol::RveRequest* req,
                    protocol::RveReply* reply) = 0;
  // Save every owned RVE under `dir`; restore() reads the RVEs of this rank's range from a
  // directory written by any partition of the same RVEs (load balance moves RVEs).
  virtual void checkpoint(const std::filesystem::path& dir) = 0;
  virtual void restore(const std::filesystem::path& dir) = 0;
  // Load balance (MessageKind::kRebalance). export_rve: the whole state of one owned RVE
  // (global id) as bytes, for adopt() on another rank's backend of the same kind; the RVE
  // must continue there as it would have here. adopt: own [first_rve, first_rve + n_rve)
  // from now on; RVEs in both the old and the new range stay, the others are dropped, and
  // `incoming` holds the exported states of the new ones (global id -> bytes).
  virtual std::string export_rve(std::uint64_t gid) = 0;
  virtual void adopt(std::uint64_t first_rve, std::uint64_t n_rve,
                     std::map<std::uint64_t, std::string> incoming) = 0;
  // Detail of the faults (RVE ids, step) found by the last initialise()/step(), for
  // RankReport::message; empty when every reply has status kOk or kNoContacts.
  virtual std::string last_fault_message() const { return {}; }
};

}  // namespace mpmdem::dem
