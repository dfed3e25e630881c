// MPI-port connection between the two programs: see connection.hpp.
#include "mpmdem/connection.hpp"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>
#include <system_error>
#include <utility>
#include <vector>

#include "mpmdem/errors.hpp"
#include "mpmdem/job_join.hpp"

namespace mpmdem {

std::string mpi_error_string(int code) {
  char text[MPI_MAX_ERROR_STRING] = {};
  int len = 0;
  if (MPI_Error_string(code, text, &len) != MPI_SUCCESS) return "MPI error " + std::to_string(code);
  return std::string(text, static_cast<std::size_t>(len));
}

void check_mpi(int rc, const char* what, const char* file, int line) {
  if (rc == MPI_SUCCESS) return;
  std::ostringstream msg;
  msg << what << " failed (" << file << ":" << line << "): " << mpi_error_string(rc);
  throw PeerError(msg.str());
}

namespace {
std::atomic<bool> g_abandoned{false};  // a connection was given up after its peer died
}  // namespace

void give_up_peers() {
  g_abandoned = true;
  // Peers that are gone have closed their TCP connections; a late write of Open MPI's to
  // one would kill this process by SIGPIPE (exit 141 instead of its own code; seen with
  // several DEM jobs). Ignored, the write fails and MPI_Finalize is bounded (MpiSession).
  std::signal(SIGPIPE, SIG_IGN);
}

void Connection::abandon() {
  intercomm_ = MPI_COMM_NULL;
  give_up_peers();
}

// ---------------------------------------------------------------------------------------
MpiSession::MpiSession(int* argc, char*** argv, int required) {
  int initialised = 0;
  MPI_Initialized(&initialised);
  if (!initialised) {
    int provided = MPI_THREAD_SINGLE;
    if (MPI_Init_thread(argc, argv, required, &provided) != MPI_SUCCESS)
      throw PeerError("MPI_Init_thread failed");
    owns_ = true;
    if (provided < required) {
      throw PeerError("the MPI library provides thread level " + std::to_string(provided) +
                      ", mpmdem needs " + std::to_string(required) + " (MPI_THREAD_FUNNELED)");
    }
  }
  // Errors outside a communicator (MPI_Lookup_name, MPI_Open_port) are raised on these.
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
  MPI_Comm_set_errhandler(MPI_COMM_SELF, MPI_ERRORS_RETURN);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiSession::~MpiSession() {
  if (!owns_) return;
  int finalised = 0;
  MPI_Finalized(&finalised);
  if (finalised) return;
  // MPI_Finalize waits for connected processes; a peer that died would block it forever.
  const double limit = g_abandoned ? 5.0 : 30.0;
  Watchdog bound(limit, [limit] {
    std::fprintf(stderr, "MPI_Finalize did not complete within %g s (coupled peer gone?)\n", limit);
    std::fflush(stderr);
    std::_Exit(kExitPeerError);
  });
  MPI_Finalize();
}

// ---------------------------------------------------------------------------------------
Watchdog::Watchdog(double seconds, std::function<void()> on_expire) {
  const auto deadline = std::chrono::steady_clock::now() +
                        std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                            std::chrono::duration<double>(seconds));
  thread_ = std::thread([this, deadline, fn = std::move(on_expire)] {
    std::unique_lock<std::mutex> lock(mutex_);
    if (!cv_.wait_until(lock, deadline, [this] { return cancelled_; })) fn();
  });
}

Watchdog::~Watchdog() {
  cancel();
}

void Watchdog::cancel() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    cancelled_ = true;
  }
  cv_.notify_all();
  if (thread_.joinable()) thread_.join();
}

// ---------------------------------------------------------------------------------------
namespace {

std::string format_seconds(double s) {
  std::ostringstream out;
  out << s;
  return out.str();
}

// Write atomically: a reader never sees a partial port name.
void write_port_file(const std::filesystem::path& file, const std::string& port) {
  std::filesystem::path tmp = file;
  tmp += ".tmp." + std::to_string(::getpid());
  {
    std::ofstream out(tmp);
    out << port << '\n';
    if (!out) {
      throw PeerError("cannot write the port file " + file.string() + " (" + std::strerror(errno) +
                      "); coupling.port_file is relative to the run directory, which must "
                      "be writable");
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, file, ec);
  if (ec)
    throw PeerError("cannot rename " + tmp.string() + " to " + file.string() + ": " + ec.message());
}

bool read_port_file(const std::filesystem::path& file, std::string& port) {
  std::ifstream in(file);
  if (!in) return false;
  std::string line;
  std::getline(in, line);
  if (line.empty() || line.size() >= MPI_MAX_PORT_NAME) return false;
  port = line;
  return true;
}

void remove_quietly(const std::filesystem::path& file) {
  if (file.empty()) return;
  std::error_code ec;
  std::filesystem::remove(file, ec);
}

std::string launch_hint() {
  return "check that both programs run under mpirun with the same --ompi-server file:URI "
         "(scripts/run and scripts/lib/pair.sh do this)";
}

}  // namespace

Connection Connection::accept(const ConnectOptions& opts, MPI_Comm local) {
  Connection c;
  // Name-service and port errors are raised on MPI_COMM_WORLD: report, do not abort.
  MPMDEM_CHECK_MPI(MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN));
  MPMDEM_CHECK_MPI(MPI_Comm_set_errhandler(local, MPI_ERRORS_RETURN));
  MPMDEM_CHECK_MPI(MPI_Comm_rank(local, &c.local_rank_));
  MPMDEM_CHECK_MPI(MPI_Comm_size(local, &c.local_size_));
  c.local_comm_ = local;
  // Job `job_index` of several DEM jobs accepts on its own port (job_join.hpp).
  const std::string service = job_service_name(opts.service_name, opts.job_index, opts.jobs);
  const std::filesystem::path own_port_file =
      job_port_file(opts.port_file, opts.job_index, opts.jobs);

  // Rank 0 opens and announces the port; the others learn whether that worked, so that a
  // failure (e.g. an unwritable run directory) ends every rank instead of leaving the
  // others in MPI_Comm_accept.
  std::vector<char> port(MPI_MAX_PORT_NAME + 1, '\0');
  bool published = false;
  bool port_open = false;
  std::string failure;
  if (c.local_rank_ == 0) {
    try {
      MPMDEM_CHECK_MPI(MPI_Open_port(MPI_INFO_NULL, port.data()));
      port_open = true;
      if (opts.publish) {
        const int rc = MPI_Publish_name(service.c_str(), MPI_INFO_NULL, port.data());
        published = rc == MPI_SUCCESS;
        if (!published) {
          std::cerr << "dem_app: warning: could not publish service '" << service << "' ("
                    << mpi_error_string(rc) << "); no ompi-server? Clients must find the port file "
                    << (own_port_file.empty() ? std::string("(none configured!)")
                                              : own_port_file.string())
                    << std::endl;
        }
      }
      if (!own_port_file.empty()) write_port_file(own_port_file, port.data());
    } catch (const PeerError& e) {
      failure = e.what();
    }
  }
  int ok = failure.empty() ? 1 : 0;
  MPMDEM_CHECK_MPI(MPI_Bcast(&ok, 1, MPI_INT, 0, local));
  if (!ok) {
    if (c.local_rank_ == 0) {
      if (published) MPI_Unpublish_name(service.c_str(), MPI_INFO_NULL, port.data());
      if (port_open) MPI_Close_port(port.data());
      throw PeerError(failure);
    }
    throw PeerError("rank 0 could not open or announce the MPI port");
  }
  if (c.local_rank_ == 0) {
    std::cerr << "dem_app: waiting for mpm_app on service '" << service << "'"
              << (own_port_file.empty() ? std::string()
                                        : " (port file " + own_port_file.string() + ")")
              << ", timeout " << format_seconds(opts.timeout_s) << " s" << std::endl;
  }

  // Non-root ranks wait a little longer so that rank 0 prints the message first.
  const double limit = opts.timeout_s + (c.local_rank_ == 0 ? 0.0 : 5.0);
  const bool root = c.local_rank_ == 0;
  const std::filesystem::path port_file = own_port_file;
  const std::string timeout_text = format_seconds(opts.timeout_s);
  Watchdog watchdog(limit, [root, port_file, timeout_text] {
    if (root) {
      remove_quietly(port_file);
      std::fprintf(stderr,
                   "dem_app: error: no mpm_app connected within %s s "
                   "(coupling.connect_timeout_s); is it running with the same "
                   "--ompi-server?\n",
                   timeout_text.c_str());
      std::fflush(stderr);
    }
    std::_Exit(kExitPeerError);
  });

  const int rc = MPI_Comm_accept(port.data(), MPI_INFO_NULL, 0, local, &c.intercomm_);
  watchdog.cancel();
  if (root) {
    remove_quietly(own_port_file);
    if (published) MPI_Unpublish_name(service.c_str(), MPI_INFO_NULL, port.data());
    MPI_Close_port(port.data());
  }
  if (rc != MPI_SUCCESS) {
    throw PeerError("MPI_Comm_accept failed: " + mpi_error_string(rc) + "; " + launch_hint());
  }
  MPMDEM_CHECK_MPI(MPI_Comm_set_errhandler(c.intercomm_, MPI_ERRORS_RETURN));
  if (opts.jobs > 1) {
    MPI_Comm servers = MPI_COMM_NULL;
    c.intercomm_ = join_jobs_as_server(c.intercomm_, opts.jobs, opts.job_index,
                                       opts.timeout_s + 10.0, servers);
    c.local_comm_ = servers;
    MPMDEM_CHECK_MPI(MPI_Comm_rank(servers, &c.local_rank_));
    MPMDEM_CHECK_MPI(MPI_Comm_size(servers, &c.local_size_));
  }
  MPMDEM_CHECK_MPI(MPI_Comm_remote_size(c.intercomm_, &c.remote_size_));
  return c;
}

namespace {

// Client: the port of the server job named by `service`/`port_file`, polled every 0.2 s
// until `deadline`. Throws ConnectTimeout.
std::string find_port(const ConnectOptions& opts, const std::string& service,
                      const std::filesystem::path& port_file,
                      std::chrono::steady_clock::time_point deadline) {
  std::vector<char> port(MPI_MAX_PORT_NAME + 1, '\0');
  std::string name;
  for (;;) {
    if (!port_file.empty() && read_port_file(port_file, name)) return name;
    if (opts.publish &&
        MPI_Lookup_name(service.c_str(), MPI_INFO_NULL, port.data()) == MPI_SUCCESS) {
      return port.data();
    }
    if (std::chrono::steady_clock::now() >= deadline) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  std::ostringstream msg;
  msg << "no DEM server found within " << format_seconds(opts.timeout_s)
      << " s (coupling.connect_timeout_s): service '" << service
      << "' is not published and the port file "
      << (port_file.empty() ? std::string("(none)") : port_file.string())
      << " does not exist: start dem_app first (with --run-dir set to this run's output "
         "folder), or "
      << launch_hint();
  throw ConnectTimeout(msg.str());
}

// Client: MPI_Comm_connect of `local` (collective) to `port`, bounded by a watchdog (a
// connect to a port nobody accepts on may hang).
MPI_Comm connect_port(const std::string& port, MPI_Comm local, const std::string& service,
                      std::chrono::steady_clock::time_point deadline) {
  const double remaining = std::max(
      5.0, std::chrono::duration<double>(deadline - std::chrono::steady_clock::now()).count());
  Watchdog watchdog(remaining, [service] {
    std::fprintf(stderr,
                 "mpm_app: error: MPI_Comm_connect to DEM server '%s' did not complete "
                 "(stale port file? server died?)\n",
                 service.c_str());
    std::fflush(stderr);
    std::_Exit(kExitPeerError);
  });
  std::vector<char> name(MPI_MAX_PORT_NAME + 1, '\0');
  std::copy(port.begin(), port.end(), name.begin());
  MPI_Comm intercomm = MPI_COMM_NULL;
  const int rc = MPI_Comm_connect(name.data(), MPI_INFO_NULL, 0, local, &intercomm);
  watchdog.cancel();
  if (rc != MPI_SUCCESS) {
    throw PeerError("MPI_Comm_connect to DEM server '" + service +
                    "' failed: " + mpi_error_string(rc) + "; " + launch_hint());
  }
  MPMDEM_CHECK_MPI(MPI_Comm_set_errhandler(intercomm, MPI_ERRORS_RETURN));
  return intercomm;
}

}  // namespace

Connection Connection::connect(const ConnectOptions& opts, MPI_Comm local) {
  using clock = std::chrono::steady_clock;
  Connection c;
  // Name-service and port errors are raised on MPI_COMM_WORLD: report, do not abort.
  MPMDEM_CHECK_MPI(MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN));
  MPMDEM_CHECK_MPI(MPI_Comm_set_errhandler(local, MPI_ERRORS_RETURN));
  MPMDEM_CHECK_MPI(MPI_Comm_rank(local, &c.local_rank_));
  MPMDEM_CHECK_MPI(MPI_Comm_size(local, &c.local_size_));
  c.local_comm_ = local;

  if (opts.jobs > 1) {  // several DEM jobs: joined one after another (job_join.hpp)
    if (c.local_size_ != 1) throw PeerError("joining several DEM jobs needs a one-rank client");
    const auto job_deadline = [&opts] {
      return clock::now() + std::chrono::duration_cast<clock::duration>(
                                std::chrono::duration<double>(opts.timeout_s));
    };
    c.intercomm_ = join_jobs_as_client(
        opts.jobs,
        [&](int j) {
          return find_port(opts, job_service_name(opts.service_name, j, opts.jobs),
                           job_port_file(opts.port_file, j, opts.jobs), job_deadline());
        },
        [&](const std::string& port, MPI_Comm group) {
          return connect_port(port, group, opts.service_name, job_deadline());
        });
    MPMDEM_CHECK_MPI(MPI_Comm_remote_size(c.intercomm_, &c.remote_size_));
    return c;
  }

  const auto deadline = clock::now() + std::chrono::duration_cast<clock::duration>(
                                           std::chrono::duration<double>(opts.timeout_s));
  std::string port;
  int found = 1;
  std::string failure;
  if (c.local_rank_ == 0) {
    try {
      port = find_port(opts, opts.service_name, opts.port_file, deadline);
    } catch (const ConnectTimeout& e) {
      found = 0;
      failure = e.what();
    }
  }
  if (c.local_size_ > 1) MPMDEM_CHECK_MPI(MPI_Bcast(&found, 1, MPI_INT, 0, local));
  if (!found) {
    throw ConnectTimeout(failure.empty() ? "no DEM server found by client rank 0" : failure);
  }
  c.intercomm_ = connect_port(port, local, opts.service_name, deadline);
  MPMDEM_CHECK_MPI(MPI_Comm_remote_size(c.intercomm_, &c.remote_size_));
  return c;
}

Connection::Connection(Connection&& other) noexcept
    : intercomm_(std::exchange(other.intercomm_, MPI_COMM_NULL)),
      local_comm_(other.local_comm_),
      local_rank_(other.local_rank_),
      local_size_(other.local_size_),
      remote_size_(other.remote_size_) {}

Connection& Connection::operator=(Connection&& other) noexcept {
  if (this != &other) {
    intercomm_ = std::exchange(other.intercomm_, MPI_COMM_NULL);
    local_comm_ = other.local_comm_;
    local_rank_ = other.local_rank_;
    local_size_ = other.local_size_;
    remote_size_ = other.remote_size_;
  }
  return *this;
}

// No MPI call here: a collective disconnect from a destructor would block if the peer is
// gone. Orderly paths call disconnect() explicitly.
Connection::~Connection() = default;

void Connection::disconnect() {
  if (!connected()) return;
  MPMDEM_CHECK_MPI(MPI_Comm_disconnect(&intercomm_));
  intercomm_ = MPI_COMM_NULL;
}

}  // namespace mpmdem
