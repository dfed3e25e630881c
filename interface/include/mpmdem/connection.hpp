// Finding the other program: the server (dem_app) opens an MPI port and makes it known
// (MPI_Publish_name through ompi-server, and a port file in the run directory); the client
// (mpm_app) finds it within a timeout and connects. The result is an intercommunicator
// with MPI_ERRORS_RETURN, on which every call is checked (MPMDEM_CHECK_MPI).
//
// Both programs must run under mpirun started with the same `--ompi-server file:URI`
// (Open MPI 4 cannot connect two separately launched jobs otherwise).
#pragma once

#include <mpi.h>

#include <condition_variable>
#include <filesystem>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

namespace mpmdem {

// Initialises MPI (MPI_THREAD_FUNNELED by default) unless it already is, and finalises it
// on destruction if it initialised it (bounded: if MPI_Finalize blocks for 30 s on a dead
// peer, or 5 s once a connection was abandoned, the process exits with kExitPeerError). Sets
// MPI_ERRORS_RETURN on MPI_COMM_WORLD and MPI_COMM_SELF. Throws PeerError if the thread level is
// too low.
class MpiSession {
 public:
  MpiSession(int* argc, char*** argv, int required = MPI_THREAD_FUNNELED);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  int rank() const { return rank_; }
  int size() const { return size_; }

 private:
  bool owns_ = false;
  int rank_ = 0;
  int size_ = 1;
};

// Runs `on_expire` on its own thread if not cancelled within `seconds` (bounds MPI calls
// that cannot time out by themselves: accept, connect, a disconnect from a dead peer).
// `on_expire` must not call MPI (MPI_THREAD_FUNNELED); it usually prints and _Exit()s.
class Watchdog {
 public:
  Watchdog(double seconds, std::function<void()> on_expire);
  ~Watchdog();  // cancels
  Watchdog(const Watchdog&) = delete;
  Watchdog& operator=(const Watchdog&) = delete;
  void cancel();

 private:
  std::mutex mutex_;
  std::condition_variable cv_;
  bool cancelled_ = false;
  std::thread thread_;
};

// The coupling's peers are gone or the coupling failed before it was made (a refused join):
// MPI_Finalize is bounded by 5 s instead of 30 (MpiSession), and SIGPIPE is ignored (a late
// write to a peer that has exited must not kill this process with 141 instead of its code).
void give_up_peers();

struct ConnectOptions {
  std::string service_name = "mpmdem";  // MPI_Publish_name / MPI_Lookup_name key
  std::filesystem::path port_file;      // <run_dir>/<coupling.port_file>; empty: none
  double timeout_s = 60.0;              // coupling.connect_timeout_s
  double peer_timeout_s = 0.0;          // client: coupling.peer_timeout_s (0: no stall limit)
  bool publish = true;                  // server: also MPI_Publish_name (needs ompi-server)
  // Several separately launched DEM jobs form the server (job_join.hpp): the client joins
  // `jobs` of them; a server is job `job_index` (0-based) of `jobs`. 1: one job, as always.
  int jobs = 1;
  int job_index = 0;
  std::string config_file;  // for messages only
};

// An established intercommunicator to the other program. Move-only. The destructor makes
// no MPI call (a collective disconnect would block on a dead peer): call disconnect().
class Connection {
 public:
  // Server side, collective over `local`: open a port, publish it, write the port file,
  // accept one client (with opts.jobs > 1: this job's own port, then the join of the jobs). A
  // watchdog ends the process (exit kExitPeerError, port file removed) if no client connects within
  // opts.timeout_s.
  static Connection accept(const ConnectOptions& opts, MPI_Comm local = MPI_COMM_WORLD);
  // Client side, collective over `local`: wait for the port file or the published name,
  // then connect. Throws ConnectTimeout naming the service, the port file and the timeout.
  // A watchdog ends the process if MPI_Comm_connect itself hangs past the timeout.
  static Connection connect(const ConnectOptions& opts, MPI_Comm local = MPI_COMM_SELF);

  Connection() = default;
  Connection(Connection&& other) noexcept;
  Connection& operator=(Connection&& other) noexcept;
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;
  ~Connection();

  MPI_Comm intercomm() const { return intercomm_; }
  // This side's own ranks: `local` of accept/connect, or, for a server of several jobs, the
  // intracommunicator of every server rank (ranks in job order).
  MPI_Comm local_comm() const { return local_comm_; }
  bool connected() const { return intercomm_ != MPI_COMM_NULL; }
  int local_rank() const { return local_rank_; }
  int local_size() const { return local_size_; }
  int remote_size() const { return remote_size_; }
  // Collective MPI_Comm_disconnect (both sides must call it). Throws PeerError.
  void disconnect();
  // Forget the intercommunicator without any MPI call (after the peer died). MPI_Finalize
  // is then bounded by 5 s instead of 30 (MpiSession): it cannot complete with a dead peer.
  void abandon();

 private:
  MPI_Comm intercomm_ = MPI_COMM_NULL;
  MPI_Comm local_comm_ = MPI_COMM_NULL;
  int local_rank_ = 0;
  int local_size_ = 1;
  int remote_size_ = 0;
};

}  // namespace mpmdem
