// The coupling as each solver sees it (preCICE/MUSCLE3 spirit: a tiny API).
//
// Client (mpm_app):                       Server (dem_app, every rank):
//   RveClient c;                            RveServerChannel ch;
//   c.connect(opts, hello);                 ch.accept(opts, hello);
//   c.initialise(inits);                    while (ch.next(header)) {     // F_INIT / O_I
//   for (...) c.step(header, requests);       ch.receive(requests);       // S
//   c.shutdown();                             compute...; ch.send(replies, report);  // O_F
//                                           }
// Every exchange: MPI_Ibcast(ControlHeader) from the client root, MPI_Iscatterv of the
// per-RVE payload in contiguous partitions (partition_contiguous(n_rve, server ranks)),
// then from each server rank one MPI_Isend of its replies and one of its RankReport to the
// client root (point-to-point, so that a stall names the silent ranks). Payloads travel
// as derived datatypes (MPI_Type_contiguous of the struct size in bytes) so counts are
// RVEs, not bytes. A RankReport with a fatal status makes the client throw PeerError.
// The client waits for every collective through a PeerWatch (peer_watch.hpp): a server rank
// that dies (or, on another host, a stall past coupling.peer_timeout_s) makes it throw
// PeerLost naming the rank, its pid and host, and the step.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <string>
#include <vector>

#include "mpmdem/connection.hpp"
#include "mpmdem/handshake.hpp"
#include "mpmdem/partition.hpp"
#include "mpmdem/peer_watch.hpp"
#include "mpmdem/protocol.hpp"
#include "mpmdem/rve_status.hpp"

namespace mpmdem {

struct ExchangeTiming {
  double exchange_s = 0.0;      // client wall time of the whole last exchange
  double max_compute_s = 0.0;   // slowest server rank's backend time in it
  double mean_compute_s = 0.0;  // mean over the server ranks (max / mean: the imbalance)
};

// MPI datatypes for the payload structs (MPI_Type_contiguous of sizeof(T) bytes).
class PayloadTypes {
 public:
  PayloadTypes() = default;
  ~PayloadTypes();
  PayloadTypes(const PayloadTypes&) = delete;
  PayloadTypes& operator=(const PayloadTypes&) = delete;
  void create();
  MPI_Datatype init = MPI_DATATYPE_NULL;
  MPI_Datatype request = MPI_DATATYPE_NULL;
  MPI_Datatype reply = MPI_DATATYPE_NULL;
  MPI_Datatype report = MPI_DATATYPE_NULL;
};

class RveClient {
 public:
  RveClient() = default;
  // Sends Abort if the client is still connected (the solver failed before shutdown()).
  ~RveClient();
  RveClient(const RveClient&) = delete;
  RveClient& operator=(const RveClient&) = delete;

  // Connect (see Connection::connect) and run the handshake; fills n_partitions and
  // program. Throws ConnectTimeout, HandshakeError (after disconnecting) or PeerError.
  void connect(const ConnectOptions& opts, HelloFields hello);
  // One RveInit per RVE, in global order; returns one reply per RVE.
  std::vector<protocol::RveReply> initialise(const std::vector<protocol::RveInit>& init);
  // One RveRequest per RVE; header.kind is set to kStep. Returns one reply per RVE.
  std::vector<protocol::RveReply> step(protocol::ControlHeader header,
                                       const std::vector<protocol::RveRequest>& requests);
  void step(protocol::ControlHeader header, const std::vector<protocol::RveRequest>& requests,
            std::vector<protocol::RveReply>& replies);
  // Servers save their RVEs under `path` (a directory; each rank writes its own file).
  void checkpoint(const std::string& path, std::int64_t step);
  // Load balance (kRebalance): the server ranks move RVE states so that rank r owns
  // `next[r]` (contiguous, in order, covering every RVE); later exchanges use it.
  void rebalance(const std::vector<Partition>& next, std::int64_t step);
  // Orderly end: Shutdown message, disconnect.
  void shutdown();
  // Give up (own error): Abort message carrying `message`, disconnect. Never throws;
  // bounded by a watchdog if the server no longer answers.
  void abort(const std::string& message) noexcept;

  bool connected() const { return conn_.connected(); }
  int server_ranks() const { return conn_.remote_size(); }
  std::uint64_t n_rve() const { return n_rve_; }
  const std::vector<Partition>& partitions() const { return parts_; }
  const HandshakeResult& handshake() const { return hs_; }
  const std::vector<protocol::RankReport>& last_reports() const { return reports_; }
  const ExchangeTiming& last_timing() const { return timing_; }
  const PeerWatch& peer_watch() const { return watch_; }

 private:
  bool root() const { return conn_.local_rank() == 0; }
  void wait(MPI_Request& request, double quiet_s = 0.0);
  void send_header(const protocol::ControlHeader& header);
  void gather_reports(const char* what);
  void require_connected(const char* what) const;
  template <class T>
  void scatter(const std::vector<T>& items, MPI_Datatype type);
  // Client root: one MPI_Irecv per server rank r of counts[r] items at data + displs[r]
  // (tag), waited for through PeerWatch::wait_each.
  template <class T>
  void receive_each(T* data, const int* counts, const int* displs, MPI_Datatype type, int tag,
                    double quiet_s);
  // Returns the time waited [s]; `quiet_s` as in PeerWatch::wait.
  double gather(std::vector<protocol::RveReply>& replies, double quiet_s = 0.0);

  Connection conn_;
  HandshakeResult hs_;
  PayloadTypes types_;
  std::uint64_t n_rve_ = 0;
  std::vector<Partition> parts_;
  std::vector<int> counts_, displs_;  // per server rank, in RVEs
  std::vector<protocol::RankReport> reports_;
  ExchangeTiming timing_;
  bool broken_ = false;  // an MPI call failed: the intercommunicator is unusable
  std::string program_ = "mpm_app";
  PeerWatch watch_;
  std::string during_;  // what the current exchange is, for fault messages ("step 57")
  // The last two steps' waits for the replies [s]; the next step sleeps kQuietFraction of
  // the shorter one (so that a scene whose steps alternate between dear and cheap, with
  // lazy evaluation, does not sleep through a cheap step).
  double step_wait_s_[2] = {0.0, 0.0};
  static constexpr double kQuietFraction = 0.6;
};

class RveServerChannel {
 public:
  RveServerChannel() = default;
  RveServerChannel(const RveServerChannel&) = delete;
  RveServerChannel& operator=(const RveServerChannel&) = delete;

  // Collective over MPI_COMM_WORLD: accept one client and run the handshake (n_partitions
  // and program filled in). Throws HandshakeError (after disconnecting) or PeerError.
  void accept(const ConnectOptions& opts, HelloFields hello);
  const HandshakeResult& handshake() const { return hs_; }
  std::uint64_t n_rve() const { return n_rve_; }  // the client's count (authoritative)
  Partition my_partition() const { return mine_; }
  int rank() const { return conn_.local_rank(); }
  int ranks() const { return conn_.local_size(); }
  // Every server rank (MPI_COMM_WORLD, or all ranks of several joined jobs): RVE migrations.
  MPI_Comm comm() const { return conn_.local_comm(); }

  // Wait for the next exchange. false on Shutdown or Abort (see aborted()).
  bool next(protocol::ControlHeader& header);
  bool aborted() const { return aborted_; }
  const std::string& abort_message() const { return abort_message_; }

  // This rank's part of the scattered payload (my_partition().count items).
  void receive(std::vector<protocol::RveInit>& init);
  void receive(std::vector<protocol::RveRequest>& requests);
  // Replies of this rank's RVEs, then this rank's report.
  void send(const std::vector<protocol::RveReply>& replies, const protocol::RankReport& report);
  // Report only (kCheckpoint, kRebalance).
  void send_report(const protocol::RankReport& report);
  // kRebalance: the new partition of every rank (broadcast by the client); set_partition
  // makes this rank's part the one later exchanges use.
  std::vector<Partition> receive_partition();
  void set_partition(Partition mine) { mine_ = mine; }
  void close();  // collective disconnect

 private:
  Connection conn_;
  HandshakeResult hs_;
  PayloadTypes types_;
  std::uint64_t n_rve_ = 0;
  Partition mine_{0, 0};
  bool aborted_ = false;
  std::string abort_message_;
};

}  // namespace mpmdem
