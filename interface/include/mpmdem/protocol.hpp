// mpmdem wire protocol: the contract between mpm_app (client) and dem_app (RVE server).
//
// Everything that crosses the MPI intercommunicator is declared here, as plain fixed-size
// structs sent as raw bytes (MPI_BYTE). Both sides run on the same architecture (the
// handshake checks the struct sizes and endianness via kMagic), so no packing is needed.
//
// A change to any struct layout or to the meaning of a field bumps kVersionMajor;
// a backward-compatible addition (new flag bit, new message kind) bumps kVersionMinor.
// The handshake refuses a peer with a different major version.
//
// Message sequence (see docs/protocol.md):
//   connect [-> job join, several DEM jobs] -> Hello exchange (both directions) -> RankIdentity
//   gather -> [Initialise] -> Step* -> [Checkpoint]
//   -> ... -> Shutdown.
// Every exchange starts with the client broadcasting a ControlHeader; the server ranks then
// take part in the collective(s) that the header's kind names.
#pragma once

#include <cstdint>
#include <type_traits>

namespace mpmdem::protocol {

// 1.1: particles in kInitialise replies. 2.0: RveReply::cost_s; kRebalance (load balance).
// 2.1: kFlagSkip (lazy RVE evaluation). 3.0: RankIdentity gather after the handshake (peer
// faults: the client names and probes the server ranks). 4.0: RveInit::point (the RVE order on
// the wire is the client's choice, coupling.rve_order). 5.0: replies and RankReports travel
// as one point-to-point message per server rank (tags 41, 42), not as gathers. 5.1: the
// server may be several dem_app jobs, joined before the Hello (job_join.hpp; only between
// programs started with mpm_app --dem-jobs K / dem_app --jobs K, K > 1: a one-job coupling's
// messages are those of 5.0).
inline constexpr std::uint16_t kVersionMajor = 5;
inline constexpr std::uint16_t kVersionMinor = 1;

// "MPMD" in ASCII; a peer that reads another value speaks another protocol or byte order.
inline constexpr std::uint32_t kMagic = 0x4D504D44u;

// Kinds of exchange, carried in ControlHeader::kind. Values are fixed forever.
enum class MessageKind : std::int32_t {
  kHello = 1,       // symmetric Hello exchange right after connect
  kInitialise = 2,  // scatter RveInit (one per RVE), gather RveReply
  kStep = 3,        // scatter RveRequest, gather RveReply
  kCheckpoint = 4,  // servers save their RVE states under ControlHeader::path
  kShutdown = 5,    // orderly end; both sides disconnect
  kAbort = 6,       // client gives up (its own error); servers exit non-zero after cleanup
  kRebalance = 7,   // (2.0) new contiguous partition: the client broadcasts n_ranks + 1
                    // uint64 offsets; server ranks move RVE states among themselves, then
                    // each sends its RankReport
};

// Optional per-RVE outputs, requested by the scene (Hello::outputs). A server computes only
// the ones asked for; fields of RveReply that were not asked for are zero.
enum OutputBits : std::uint32_t {
  kOutputRotation = 1u << 0,        // RveReply::rotation
  kOutputPorosity = 1u << 1,        // RveReply::porosity
  kOutputCoordination = 1u << 2,    // RveReply::coordination
  kOutputUnbalancedForce = 1u << 3  // RveReply::unbalanced_force
};
inline constexpr std::uint32_t kKnownOutputs = 0xFu;

// RveRequest::flags.
enum RequestFlags : std::uint32_t {
  kFlagQueryOnly = 1u << 0,  // apply nothing; report the current state (dF ignored)
  kFlagSkip = 1u << 1,       // (2.1) lazy evaluation: apply nothing and return the RVE's last
                             // reply as it is (n_substeps 0); dF ignored
};

// Per-RVE status in RveReply::status. Non-zero is not always fatal: see each value.
enum class RveStatus : std::int32_t {
  kOk = 0,
  kNoContacts = 1,    // packing lost all contacts: stress is exactly zero (not fatal)
  kNonFinite = 2,     // NaN/Inf inside the RVE: fatal for the run
  kExploding = 3,     // kinetic energy blew up: fatal for the run
  kBackendError = 4,  // backend raised an error; RankReport::message says which
};

// (3.0) Right after a successful handshake every server rank sends its own to the client
// root (MPI_Gather): the client names a rank that dies by pid and host, and probes the ranks
// on its own host for liveness while it waits (interface/include/mpmdem/peer_watch.hpp).
struct RankIdentity {
  std::int32_t rank;  // rank in the server's MPI_COMM_WORLD
  std::int32_t pid;   // process id on `host`
  char host[120];     // gethostname(), NUL-terminated
};

// Sent by the client at the start of every exchange (MPI_Bcast over the intercommunicator).
struct ControlHeader {
  std::int32_t kind;  // MessageKind
  std::int32_t reserved;
  std::int64_t step;  // MPM step number (0 for Hello/Initialise)
  double time;        // simulated time at the end of this step [s]
  double dt;          // MPM time increment of this step [s]
  char path[224];     // kCheckpoint: directory to write into (NUL-terminated); else empty
};

// Exchanged in both directions right after connect.
struct Hello {
  std::uint32_t magic;          // kMagic
  std::uint16_t version_major;  // kVersionMajor of the sender
  std::uint16_t version_minor;  // kVersionMinor of the sender
  std::uint32_t request_size;   // sizeof(RveRequest) of the sender
  std::uint32_t reply_size;     // sizeof(RveReply) of the sender
  std::uint64_t n_rve;          // number of RVEs (= material points) the run couples
  std::int32_t n_partitions;    // client: remote group size it sees; server: its rank count
  std::uint32_t outputs;        // OutputBits the scene asks for
  std::uint64_t config_hash;    // FNV-1a 64 of the canonical `coupling:` section
  char program[16];             // "mpm_app", "dem_app", "element_test", ...
  char program_version[32];     // e.g. "0.1.0"
  char backend[32];             // server: backend name; client: backend the scene names
};

// Initial state of one RVE (MessageKind::kInitialise): the stress it must start from.
struct RveInit {
  double stress[9];     // Cauchy stress, tension positive, row-major [Pa]
  std::uint64_t point;  // (4.0) the client's name of this RVE (mpm_app: its material point).
                        // The server draws the RVE's packing from it and names the RVE by
                        // it, so results do not depend on the RVE's place (slot) on the wire
};

// One RVE's work for one coupling step (MessageKind::kStep).
struct RveRequest {
  // Incremental deformation gradient of this step, row-major: dF[3*i + j] = dF_ij =
  // d x_i(t_{n+1}) / d x_j(t_n). It includes rotation; det(dF) > 0.
  double dF[9];
  double dt;            // time over which dF is applied [s]
  std::uint32_t flags;  // RequestFlags
  std::uint32_t reserved;
};

// One RVE's answer (kInitialise and kStep).
struct RveReply {
  double stress[9];         // Cauchy stress after the step, tension positive, row-major [Pa]
  double rotation[3];       // mean particle rotation vector (axis * angle) [rad] if requested
  double porosity;          // [-] if requested
  double coordination;      // mean contacts per particle [-] if requested
  double unbalanced_force;  // YADE's unbalancedForce() [-] if requested
  double stiffness;         // constrained (P-wave) modulus estimate for the CFL step [Pa]
  double cost_s;            // (2.0) backend wall time spent on this RVE in this exchange [s]
  std::int32_t status;      // RveStatus
  std::int32_t n_substeps;  // kStep: DEM substeps used; kInitialise (since 1.1): particles in
                            // the RVE; 0 for closed-form backends
};

// One per server rank after every exchange (MPI_Gather): errors and timing.
struct RankReport {
  std::int32_t rank;
  std::int32_t status;           // 0 ok; otherwise the worst RveStatus on this rank
  std::int32_t n_faults;         // RVEs with a non-zero status
  std::int32_t first_fault_rve;  // global id of the first faulty RVE, -1 if none
  double compute_s;              // wall time spent in the backend for this exchange
  char message[232];             // NUL-terminated human-readable detail when status != 0
};

static_assert(sizeof(ControlHeader) == 256, "ControlHeader layout changed: bump kVersionMajor");
static_assert(sizeof(Hello) == 120, "Hello layout changed: bump kVersionMajor");
static_assert(sizeof(RveInit) == 80, "RveInit layout changed: bump kVersionMajor");
static_assert(sizeof(RveRequest) == 88, "RveRequest layout changed: bump kVersionMajor");
static_assert(sizeof(RveReply) == 144, "RveReply layout changed: bump kVersionMajor");
static_assert(sizeof(RankReport) == 256, "RankReport layout changed: bump kVersionMajor");
static_assert(sizeof(RankIdentity) == 128, "RankIdentity layout changed: bump kVersionMajor");
static_assert(std::is_trivially_copyable_v<ControlHeader> &&
              std::is_standard_layout_v<ControlHeader>);
static_assert(std::is_trivially_copyable_v<Hello> && std::is_standard_layout_v<Hello>);
static_assert(std::is_trivially_copyable_v<RveInit> && std::is_standard_layout_v<RveInit>);
static_assert(std::is_trivially_copyable_v<RveRequest> && std::is_standard_layout_v<RveRequest>);
static_assert(std::is_trivially_copyable_v<RveReply> && std::is_standard_layout_v<RveReply>);
static_assert(std::is_trivially_copyable_v<RankReport> && std::is_standard_layout_v<RankReport>);
static_assert(std::is_trivially_copyable_v<RankIdentity> &&
              std::is_standard_layout_v<RankIdentity>);

}  // namespace mpmdem::protocol
