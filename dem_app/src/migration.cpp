// Moving RVE states between server ranks (see migration.hpp and docs/protocol.md).
#include "migration.hpp"

#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>

namespace mpmdem::dem {

namespace {

constexpr int kTagSize = 7101;
constexpr int kTagData = 7102;

// Rank owning global RVE id `gid` under `parts` (contiguous, in order).
int owner(const std::vector<Partition>& parts, std::uint64_t gid) {
  const int r = owner_of(parts, gid);
  if (r < 0) throw std::logic_error("RVE " + std::to_string(gid) + " is in no partition");
  return r;
}

void check(int rc, const char* what, int peer) {
  if (rc == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int len = 0;
  MPI_Error_string(rc, text, &len);
  throw std::runtime_error(std::string("load balance: ") + what + " with rank " +
                           std::to_string(peer) + " failed: " + std::string(text, len));
}

}  // namespace

void migrate(RveBackend& backend, const std::vector<Partition>& old_parts,
             const std::vector<Partition>& next, int rank, MPI_Comm comm) {
  const auto me = static_cast<std::size_t>(rank);
  const Partition mine_old = old_parts[me], mine_next = next[me];

  // Outgoing: my old RVEs that another rank owns next, in ascending id (MPI keeps the order
  // of messages between two ranks with the same tag, so the receiver reads them in order).
  std::vector<std::string> blobs;
  std::vector<std::uint64_t> sizes;
  std::vector<int> dest;
  for (std::uint64_t gid = mine_old.offset; gid < mine_old.offset + mine_old.count; ++gid) {
    const int to = owner(next, gid);
    if (to == rank) continue;
    blobs.push_back(backend.export_rve(gid));
    sizes.push_back(blobs.back().size());
    dest.push_back(to);
  }
  std::vector<MPI_Request> requests(2 * blobs.size(), MPI_REQUEST_NULL);
  for (std::size_t i = 0; i < blobs.size(); ++i) {
    check(MPI_Isend(&sizes[i], 1, MPI_UINT64_T, dest[i], kTagSize, comm, &requests[2 * i]),
          "sending an RVE size", dest[i]);
    check(MPI_Isend(blobs[i].data(), static_cast<int>(blobs[i].size()), MPI_BYTE, dest[i], kTagData,
                    comm, &requests[2 * i + 1]),
          "sending an RVE state", dest[i]);
  }

  // Incoming: my next RVEs that another rank owned, in ascending id.
  std::map<std::uint64_t, std::string> incoming;
  for (std::uint64_t gid = mine_next.offset; gid < mine_next.offset + mine_next.count; ++gid) {
    const int from = owner(old_parts, gid);
    if (from == rank) continue;
    std::uint64_t size = 0;
    check(MPI_Recv(&size, 1, MPI_UINT64_T, from, kTagSize, comm, MPI_STATUS_IGNORE),
          "receiving an RVE size", from);
    std::string blob(size, '\0');
    check(MPI_Recv(blob.data(), static_cast<int>(size), MPI_BYTE, from, kTagData, comm,
                   MPI_STATUS_IGNORE),
          "receiving an RVE state", from);
    incoming.emplace(gid, std::move(blob));
  }
  if (!requests.empty()) {
    check(MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE),
          "completing the sends", rank);
  }
  backend.adopt(mine_next.offset, mine_next.count, std::move(incoming));
}

}  // namespace mpmdem::dem
