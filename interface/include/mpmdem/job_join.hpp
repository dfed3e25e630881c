// One DEM partition from several separately launched dem_app jobs (docs/cluster.md).
//
// Debian 12's Open MPI 4.1.4 connects two mpirun jobs only when each job's ranks run on the
// node of their own mpirun (open-mpi/ompi#6818: the other job's mpirun segfaults in
// orte_rml_base_parse_uris otherwise). A DEM side on K nodes is therefore K jobs, one per
// node, each accepting on its own port. mpm_app joins them one after another:
//
//   client (group G = mpm_app)                 job j (its MPI_COMM_WORLD)
//   find job j's port (port file / name)
//   j > 0: Bcast j over G  ─────────────────►  ranks already in G learn "join job j"
//   MPI_Comm_connect(port, G)  ─────────────►  MPI_Comm_accept(port, WORLD)
//   G = MPI_Intercomm_merge(low)               G = MPI_Intercomm_merge(high)
//   Bcast {K, j} over G  ───────────────────►  every rank checks K and, new ranks, j
//   Allreduce(MAX) of a refusal code ◄──────►  (so that a wrong launch ends every side)
//   ... next job ...
//   Bcast -1 over G (done)
//   MPI_Comm_split(G): mpm_app | the DEM ranks (in job order, then by rank in the job)
//   MPI_Intercomm_create: the intercommunicator the protocol runs on, the same shape as
//   with one job (client group: mpm_app; remote group: every DEM rank).
//
// The intermediate communicators stay as they are: MPI_Comm_disconnect on a merged one hangs
// with Open MPI 4.1.4 (measured, issue 36); disconnecting the final intercommunicator alone
// ends the coupling cleanly. With one job (K = 1) nothing of this runs: the port and service
// names and the wire are those of a single dem_app job.
#pragma once

#include <mpi.h>

#include <filesystem>
#include <functional>
#include <string>

namespace mpmdem {

// The port file and service name of job `job` of `jobs` (jobs == 1: `base` unchanged;
// otherwise "<stem>.job<j><ext>" and "<service>.job<j>").
std::filesystem::path job_port_file(const std::filesystem::path& base, int job, int jobs);
std::string job_service_name(const std::string& base, int job, int jobs);

// Client side: joins `jobs` (>= 2) server jobs. `find_port(j)` returns job j's port name
// (this process only; throws ConnectTimeout); `connect(port, group)` connects `group`
// collectively to it and returns the intercommunicator (bounded by its own watchdog).
// Returns the intercommunicator to all server ranks. Throws PeerError, ConnectTimeout.
MPI_Comm join_jobs_as_client(
    int jobs, const std::function<std::string(int job)>& find_port,
    const std::function<MPI_Comm(const std::string& port, MPI_Comm group)>& connect);

// Server side, collective over this job's ranks: `accepted` is the intercommunicator of this
// job's MPI_Comm_accept. Takes part in the joins of the later jobs, then returns the
// intercommunicator to the client (local group: every server rank of every job, in job
// order) and, in `servers`, the intracommunicator of those ranks (RVE migrations).
// `wait_s` bounds each wait for the client's next word (the client looks for the next
// job's port for up to coupling.connect_timeout_s). Throws PeerError.
MPI_Comm join_jobs_as_server(MPI_Comm accepted, int jobs, int job, double wait_s,
                             MPI_Comm& servers);

}  // namespace mpmdem
