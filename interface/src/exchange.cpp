// Exchanges over the intercommunicator: see exchange.hpp and docs/protocol.md.
#include "mpmdem/exchange.hpp"

#include <algorithm>
#include <cassert>
#include <chrono>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <sstream>
#include <thread>

#include "mpmdem/errors.hpp"

namespace mpmdem {

using protocol::ControlHeader;
using protocol::MessageKind;
using protocol::RankReport;
using protocol::RveInit;
using protocol::RveReply;
using protocol::RveRequest;
using protocol::RveStatus;

namespace {

// Tags of the point-to-point messages from each server rank to the client root: the replies
// and the RankReport go one message per rank (not MPI_Igatherv/MPI_Igather) so that a client
// that waits in vain can name the ranks that did not answer (PeerWatch::wait_each).
constexpr int kTagReplies = 41;
constexpr int kTagReport = 42;

// Waits for a non-blocking MPI operation without spinning: Open MPI's blocking calls poll a
// core at 100% (mpi_yield_when_idle only yields it), which on a small machine takes a core
// from the DEM ranks while mpm_app waits for their replies (and from mpm_app while the
// servers wait for the next step). Sleeps grow from 20 us to 1 ms: the added latency is
// under 1 ms per exchange, against DEM work of tens of ms.
void wait_politely(MPI_Request& request) {
  int done = 0;
  std::chrono::microseconds pause(20);
  for (;;) {
    MPMDEM_CHECK_MPI(MPI_Test(&request, &done, MPI_STATUS_IGNORE));
    if (done) return;
    std::this_thread::sleep_for(pause);
    pause = std::min(pause * 2, std::chrono::microseconds(1000));
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------
namespace {

MPI_Datatype contiguous_bytes(std::size_t n) {
  MPI_Datatype t = MPI_DATATYPE_NULL;
  MPMDEM_CHECK_MPI(MPI_Type_contiguous(static_cast<int>(n), MPI_BYTE, &t));
  MPMDEM_CHECK_MPI(MPI_Type_commit(&t));
  return t;
}

void free_type(MPI_Datatype& t) {
  int finalised = 0;
  MPI_Finalized(&finalised);
  if (t != MPI_DATATYPE_NULL && !finalised) MPI_Type_free(&t);
  t = MPI_DATATYPE_NULL;
}

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

PayloadTypes::~PayloadTypes() {
  free_type(init);
  free_type(request);
  free_type(reply);
  free_type(report);
}

void PayloadTypes::create() {
  if (init != MPI_DATATYPE_NULL) return;
  init = contiguous_bytes(sizeof(RveInit));
  request = contiguous_bytes(sizeof(RveRequest));
  reply = contiguous_bytes(sizeof(RveReply));
  report = contiguous_bytes(sizeof(RankReport));
}

// ---------------------------------------------------------------------------------------
// Client
RveClient::~RveClient() {
  if (connected()) abort(program_ + " ended without an orderly shutdown");
}

void RveClient::require_connected(const char* what) const {
  if (!connected())
    throw PeerError(std::string("RveClient::") + what + " called while not connected");
}

void RveClient::connect(const ConnectOptions& opts, HelloFields hello) {
  if (connected()) throw PeerError("RveClient::connect called twice");
  // MPI counts are int (in RVEs, thanks to the derived datatypes).
  if (hello.n_rve > static_cast<std::uint64_t>(INT_MAX)) {
    throw PeerError("too many RVEs for one coupling (" + std::to_string(hello.n_rve) +
                    " > 2^31-1): MPI counts are int");
  }
  conn_ = Connection::connect(opts);
  types_.create();
  hello.n_partitions = conn_.remote_size();
  if (hello.program.empty()) hello.program = "mpm_app";
  program_ = hello.program;
  try {
    hs_ = exchange_hello(conn_.intercomm(), true, make_hello(hello), opts.config_file);
  } catch (const HandshakeError&) {
    conn_.disconnect();
    throw;
  }
  if (auto note = minor_version_note(hs_.client, hs_.server))
    std::cerr << "mpm_app: " << *note << '\n';
  watch_.set_peers(hs_.servers, this_host_name());
  watch_.set_stall_limit(opts.peer_timeout_s);
  n_rve_ = hello.n_rve;
  parts_ = partition_contiguous(n_rve_, conn_.remote_size());
  counts_.clear();
  displs_.clear();
  for (const auto& p : parts_) {
    counts_.push_back(static_cast<int>(p.count));
    displs_.push_back(static_cast<int>(p.offset));
  }
}

void RveClient::wait(MPI_Request& request, double quiet_s) {
  watch_.wait(request, during_, quiet_s);
}

void RveClient::send_header(const ControlHeader& header) {
  ControlHeader h = header;
  const int root_arg = root() ? MPI_ROOT : MPI_PROC_NULL;
  switch (static_cast<MessageKind>(h.kind)) {
    case MessageKind::kInitialise:
      during_ = "the initialisation";
      break;
    case MessageKind::kStep:
      during_ = "step " + std::to_string(h.step);
      break;
    case MessageKind::kCheckpoint:
      during_ = "the checkpoint after step " + std::to_string(h.step);
      break;
    case MessageKind::kRebalance:
      during_ = "the rebalance after step " + std::to_string(h.step);
      break;
    default:
      during_ = "the end of the run";
  }
  try {
    MPI_Request request = MPI_REQUEST_NULL;
    MPMDEM_CHECK_MPI(MPI_Ibcast(&h, sizeof h, MPI_BYTE, root_arg, conn_.intercomm(), &request));
    wait(request);
  } catch (...) {
    broken_ = true;
    throw;
  }
}

template <class T>
void RveClient::scatter(const std::vector<T>& items, MPI_Datatype type) {
  if (root() && items.size() != n_rve_) {
    throw PeerError("coupling exchange got " + std::to_string(items.size()) + " items for " +
                    std::to_string(n_rve_) + " RVEs");
  }
  const int root_arg = root() ? MPI_ROOT : MPI_PROC_NULL;
  try {
    MPI_Request request = MPI_REQUEST_NULL;
    MPMDEM_CHECK_MPI(MPI_Iscatterv(items.data(), counts_.data(), displs_.data(), type, nullptr, 0,
                                   type, root_arg, conn_.intercomm(), &request));
    wait(request);
  } catch (...) {
    broken_ = true;
    throw;
  }
}

template <class T>
void RveClient::receive_each(T* data, const int* counts, const int* displs, MPI_Datatype type,
                             int tag, double quiet_s) {
  if (!root()) return;  // the root alone receives (other client ranks sat out the gathers)
  const int n = conn_.remote_size();
  std::vector<MPI_Request> requests(static_cast<std::size_t>(n), MPI_REQUEST_NULL);
  std::vector<int> from(static_cast<std::size_t>(n));
  try {
    for (int r = 0; r < n; ++r) {
      const auto i = static_cast<std::size_t>(r);
      from[i] = r;
      MPMDEM_CHECK_MPI(
          MPI_Irecv(data + displs[i], counts[i], type, r, tag, conn_.intercomm(), &requests[i]));
    }
    watch_.wait_each(requests, from, during_, quiet_s);
  } catch (...) {
    broken_ = true;
    throw;
  }
}

double RveClient::gather(std::vector<RveReply>& replies, double quiet_s) {
  replies.resize(n_rve_);
  const double t0 = now_s();
  receive_each(replies.data(), counts_.data(), displs_.data(), types_.reply, kTagReplies, quiet_s);
  return now_s() - t0;
}

void RveClient::gather_reports(const char* what) {
  const int n = conn_.remote_size();
  reports_.resize(static_cast<std::size_t>(n));
  std::vector<int> ones(static_cast<std::size_t>(n), 1), index(static_cast<std::size_t>(n));
  for (int r = 0; r < n; ++r) index[static_cast<std::size_t>(r)] = r;
  receive_each(reports_.data(), ones.data(), index.data(), types_.report, kTagReport, 0.0);
  timing_.max_compute_s = 0.0;
  timing_.mean_compute_s = 0.0;
  for (const auto& r : reports_) {
    timing_.max_compute_s = std::max(timing_.max_compute_s, r.compute_s);
    timing_.mean_compute_s += r.compute_s / static_cast<double>(reports_.size());
  }
  for (std::size_t i = 0; i < reports_.size(); ++i) {
    const RankReport& r = reports_[i];
    if (!is_fatal(r.status)) continue;
    std::ostringstream msg;
    msg << "DEM server rank " << i << " failed during " << what << ": " << status_name(r.status);
    if (r.first_fault_rve >= 0) msg << " at RVE " << r.first_fault_rve;
    if (r.n_faults > 1) msg << " (" << r.n_faults << " faulty RVEs on that rank)";
    const std::string detail(r.message, strnlen(r.message, sizeof r.message));
    if (!detail.empty()) msg << ": " << detail;
    throw PeerError(msg.str());
  }
}

std::vector<RveReply> RveClient::initialise(const std::vector<RveInit>& init) {
  require_connected("initialise");
  const double t0 = now_s();
  ControlHeader h{};
  h.kind = static_cast<std::int32_t>(MessageKind::kInitialise);
  send_header(h);
  scatter(init, types_.init);
  std::vector<RveReply> replies;
  gather(replies);
  gather_reports("initialise");
  timing_.exchange_s = now_s() - t0;
  return replies;
}

std::vector<RveReply> RveClient::step(ControlHeader header,
                                      const std::vector<RveRequest>& requests) {
  std::vector<RveReply> replies;
  step(header, requests, replies);
  return replies;
}

void RveClient::step(ControlHeader header, const std::vector<RveRequest>& requests,
                     std::vector<RveReply>& replies) {
  require_connected("step");
  const double t0 = now_s();
  header.kind = static_cast<std::int32_t>(MessageKind::kStep);
  send_header(header);
  scatter(requests, types_.request);
  // The replies cannot come before the servers have computed: sleep through most of the
  // recent steps' wait instead of polling it (steps rarely get 40 % faster from one to the
  // next; when one does, the reply is late by the difference).
  const double quiet = kQuietFraction * std::min(step_wait_s_[0], step_wait_s_[1]);
  step_wait_s_[1] = step_wait_s_[0];
  step_wait_s_[0] = gather(replies, quiet);
  gather_reports("step");
  timing_.exchange_s = now_s() - t0;
}

void RveClient::checkpoint(const std::string& path, std::int64_t step) {
  require_connected("checkpoint");
  ControlHeader h{};
  if (path.size() >= sizeof h.path) {
    throw PeerError("checkpoint path longer than " + std::to_string(sizeof h.path - 1) +
                    " characters: " + path);
  }
  const double t0 = now_s();
  h.kind = static_cast<std::int32_t>(MessageKind::kCheckpoint);
  h.step = step;
  std::memcpy(h.path, path.data(), path.size());
  send_header(h);
  gather_reports("checkpoint");
  timing_.exchange_s = now_s() - t0;
}

void RveClient::rebalance(const std::vector<Partition>& next, std::int64_t step) {
  require_connected("rebalance");
  std::uint64_t expect = 0;
  for (const Partition& p : next) {
    assert(p.offset == expect);
    expect += p.count;
  }
  assert(next.size() == parts_.size() && expect == n_rve_);
  const double t0 = now_s();
  ControlHeader h{};
  h.kind = static_cast<std::int32_t>(MessageKind::kRebalance);
  h.step = step;
  send_header(h);
  std::vector<std::uint64_t> offsets;
  for (const Partition& p : next) offsets.push_back(p.offset);
  offsets.push_back(n_rve_);
  const int root_arg = root() ? MPI_ROOT : MPI_PROC_NULL;
  try {
    MPI_Request request = MPI_REQUEST_NULL;
    MPMDEM_CHECK_MPI(MPI_Ibcast(offsets.data(), static_cast<int>(offsets.size()), MPI_UINT64_T,
                                root_arg, conn_.intercomm(), &request));
    wait(request);
  } catch (...) {
    broken_ = true;
    throw;
  }
  gather_reports("rebalance");
  parts_ = next;
  for (std::size_t r = 0; r < parts_.size(); ++r) {
    counts_[r] = static_cast<int>(parts_[r].count);
    displs_[r] = static_cast<int>(parts_[r].offset);
  }
  timing_.exchange_s = now_s() - t0;
}

void RveClient::shutdown() {
  if (!connected()) return;
  ControlHeader h{};
  h.kind = static_cast<std::int32_t>(MessageKind::kShutdown);
  send_header(h);
  conn_.disconnect();
}

void RveClient::abort(const std::string& message) noexcept {
  if (!connected()) return;
  if (broken_) {  // the intercommunicator failed: do not wait on it
    conn_.abandon();
    return;
  }
  Watchdog watchdog(10.0, [] {
    std::fprintf(stderr, "DEM server did not acknowledge the abort within 10 s\n");
    std::fflush(stderr);
    std::_Exit(kExitPeerError);
  });
  try {
    ControlHeader h{};
    h.kind = static_cast<std::int32_t>(MessageKind::kAbort);
    std::memcpy(h.path, message.data(), std::min(message.size(), sizeof h.path - 1));
    send_header(h);
    conn_.disconnect();
  } catch (...) {
    conn_.abandon();
  }
}

// ---------------------------------------------------------------------------------------
// Server
void RveServerChannel::accept(const ConnectOptions& opts, HelloFields hello) {
  conn_ = Connection::accept(opts, MPI_COMM_WORLD);
  types_.create();
  hello.n_partitions = conn_.local_size();
  if (hello.program.empty()) hello.program = "dem_app";
  try {
    hs_ = exchange_hello(conn_.intercomm(), false, make_hello(hello), opts.config_file);
  } catch (const HandshakeError&) {
    conn_.disconnect();
    throw;
  }
  if (conn_.local_rank() == 0) {
    if (auto note = minor_version_note(hs_.client, hs_.server))
      std::cerr << "dem_app: " << *note << '\n';
  }
  n_rve_ = hs_.client.n_rve;
  mine_ = partition_contiguous(n_rve_,
                               conn_.local_size())[static_cast<std::size_t>(conn_.local_rank())];
}

bool RveServerChannel::next(ControlHeader& header) {
  std::memset(&header, 0, sizeof header);
  MPI_Request request = MPI_REQUEST_NULL;
  MPMDEM_CHECK_MPI(MPI_Ibcast(&header, sizeof header, MPI_BYTE, 0, conn_.intercomm(), &request));
  wait_politely(request);
  header.path[sizeof header.path - 1] = '\0';
  switch (static_cast<MessageKind>(header.kind)) {
    case MessageKind::kInitialise:
    case MessageKind::kStep:
    case MessageKind::kCheckpoint:
    case MessageKind::kRebalance:
      return true;
    case MessageKind::kShutdown:
      return false;
    case MessageKind::kAbort:
      aborted_ = true;
      abort_message_ = header.path;
      return false;
    case MessageKind::kHello:
      break;
  }
  throw PeerError("unexpected message kind " + std::to_string(header.kind) +
                  " from the client (protocol violation)");
}

void RveServerChannel::receive(std::vector<RveInit>& init) {
  init.resize(mine_.count);
  MPI_Request request = MPI_REQUEST_NULL;
  MPMDEM_CHECK_MPI(MPI_Iscatterv(nullptr, nullptr, nullptr, types_.init, init.data(),
                                 static_cast<int>(mine_.count), types_.init, 0, conn_.intercomm(),
                                 &request));
  wait_politely(request);
}

void RveServerChannel::receive(std::vector<RveRequest>& requests) {
  requests.resize(mine_.count);
  MPI_Request request = MPI_REQUEST_NULL;
  MPMDEM_CHECK_MPI(MPI_Iscatterv(nullptr, nullptr, nullptr, types_.request, requests.data(),
                                 static_cast<int>(mine_.count), types_.request, 0,
                                 conn_.intercomm(), &request));
  wait_politely(request);
}

void RveServerChannel::send(const std::vector<RveReply>& replies, const RankReport& report) {
  assert(replies.size() == mine_.count);
  MPI_Request request = MPI_REQUEST_NULL;
  MPMDEM_CHECK_MPI(MPI_Isend(replies.data(), static_cast<int>(mine_.count), types_.reply, 0,
                             kTagReplies, conn_.intercomm(), &request));
  wait_politely(request);
  send_report(report);
}

void RveServerChannel::send_report(const RankReport& report) {
  MPI_Request request = MPI_REQUEST_NULL;
  MPMDEM_CHECK_MPI(
      MPI_Isend(&report, 1, types_.report, 0, kTagReport, conn_.intercomm(), &request));
  wait_politely(request);
}

std::vector<Partition> RveServerChannel::receive_partition() {
  std::vector<std::uint64_t> offsets(static_cast<std::size_t>(conn_.local_size()) + 1);
  MPI_Request request = MPI_REQUEST_NULL;
  MPMDEM_CHECK_MPI(MPI_Ibcast(offsets.data(), static_cast<int>(offsets.size()), MPI_UINT64_T, 0,
                              conn_.intercomm(), &request));
  wait_politely(request);
  std::vector<Partition> parts;
  for (std::size_t r = 0; r + 1 < offsets.size(); ++r) {
    if (offsets[r + 1] < offsets[r] || offsets.front() != 0 || offsets.back() != n_rve_) {
      throw PeerError("kRebalance: the client sent an invalid partition (protocol violation)");
    }
    parts.push_back({offsets[r], offsets[r + 1] - offsets[r]});
  }
  return parts;
}

void RveServerChannel::close() {
  conn_.disconnect();
}

}  // namespace mpmdem
