// Joining several dem_app jobs into one DEM partition: see job_join.hpp.
#include "mpmdem/job_join.hpp"

#include <cassert>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <vector>

#include "mpmdem/connection.hpp"
#include "mpmdem/errors.hpp"

namespace mpmdem {

namespace {

constexpr int kDone = -1;     // Bcast over the group: every job has joined
constexpr int kGaveUp = -2;   // Bcast over the group: the client found no port for a job
constexpr int kJoinTag = 36;  // MPI_Intercomm_create's tag (any; the group is ours alone)

// Refusal codes of the check after each merge (Allreduce MAX over the merged group).
constexpr int kOk = 0;
constexpr int kOtherJobCount = 1;  // a server rank was started with another --jobs
constexpr int kOtherIndex = 2;     // the new job was started with another --job-index

// Bounds a wait that MPI cannot bound itself; ends the process if it expires.
Watchdog bound(double seconds, const std::string& what) {
  return Watchdog(seconds, [what, seconds] {
    std::fprintf(stderr, "error: %s did not complete within %g s\n", what.c_str(), seconds);
    std::fflush(stderr);
    std::_Exit(kExitPeerError);
  });
}

MPI_Comm merge(MPI_Comm intercomm, bool high) {
  MPI_Comm merged = MPI_COMM_NULL;
  MPMDEM_CHECK_MPI(MPI_Intercomm_merge(intercomm, high ? 1 : 0, &merged));
  MPMDEM_CHECK_MPI(MPI_Comm_set_errhandler(merged, MPI_ERRORS_RETURN));
  return merged;
}

// After job j joined `group` (root 0 = the client): every rank learns {jobs, j} and the
// group agrees on whether the launch is consistent. `mine_jobs`/`mine_job` are this rank's
// own (-1 for the client; mine_job -1 for ranks that joined earlier).
void check_join(MPI_Comm group, int jobs, int job, int mine_jobs, int mine_job) {
  int word[2] = {jobs, job};
  MPMDEM_CHECK_MPI(MPI_Bcast(word, 2, MPI_INT, 0, group));
  int verdict[3] = {kOk, -1, -1};  // code, the new job's own index, a rank's own job count
  if (mine_jobs >= 0 && mine_jobs != word[0]) verdict[0] = kOtherJobCount;
  if (mine_job >= 0 && mine_job != word[1]) verdict[0] = std::max(verdict[0], kOtherIndex);
  verdict[1] = mine_job;
  verdict[2] = mine_jobs == word[0] ? -1 : mine_jobs;
  int worst[3] = {};
  MPMDEM_CHECK_MPI(MPI_Allreduce(verdict, worst, 3, MPI_INT, MPI_MAX, group));
  if (worst[0] == kOk) return;
  std::ostringstream msg;
  msg << "joining DEM job " << word[1] << " of " << word[0] << " refused: ";
  if (worst[0] == kOtherIndex) {
    msg << "the job that answered on job " << word[1] << "'s port was started as job " << worst[1]
        << " (dem_app --job-index)";
  } else {
    msg << "a DEM rank was started for " << worst[2] << " jobs (dem_app --jobs), mpm_app joins "
        << word[0] << " (mpm_app --dem-jobs)";
  }
  msg << "; scripts/run starts every job with matching options";
  throw PeerError(msg.str());
}

// Frees the communicators of the join (MPI_Comm_disconnect on them hangs). They must not be
// left either: Open MPI 4.1's MPI_Finalize disconnects every communicator that spans jobs
// when more than one is left; with them left, 2 jobs on one machine ended with a DEM rank
// killed by SIGPIPE in 3 of 4 runs, and with SIGPIPE ignored MPI_Finalize hung in 5 of 6
// (measured); freed, 12 of 12 runs ended cleanly.
void free_all(std::vector<MPI_Comm>& comms) {
  for (MPI_Comm& c : comms) MPMDEM_CHECK_MPI(MPI_Comm_free(&c));
  comms.clear();
}

// The final intercommunicator: split the whole group into the client and the servers.
MPI_Comm split_sides(MPI_Comm group, bool server, MPI_Comm& side) {
  int rank = 0;
  MPMDEM_CHECK_MPI(MPI_Comm_rank(group, &rank));
  MPMDEM_CHECK_MPI(MPI_Comm_split(group, server ? 1 : 0, rank, &side));
  MPMDEM_CHECK_MPI(MPI_Comm_set_errhandler(side, MPI_ERRORS_RETURN));
  MPI_Comm inter = MPI_COMM_NULL;
  // Group rank 0 is the client, rank 1 the first server rank (job 0's rank 0).
  MPMDEM_CHECK_MPI(MPI_Intercomm_create(side, 0, group, server ? 0 : 1, kJoinTag, &inter));
  MPMDEM_CHECK_MPI(MPI_Comm_set_errhandler(inter, MPI_ERRORS_RETURN));
  return inter;
}

}  // namespace

std::filesystem::path job_port_file(const std::filesystem::path& base, int job, int jobs) {
  assert(job >= 0 && job < jobs);
  if (jobs <= 1 || base.empty()) return base;
  std::filesystem::path out = base;
  out.replace_filename(base.stem().string() + ".job" + std::to_string(job) +
                       base.extension().string());
  return out;
}

std::string job_service_name(const std::string& base, int job, int jobs) {
  assert(job >= 0 && job < jobs);
  return jobs <= 1 ? base : base + ".job" + std::to_string(job);
}

namespace {

// A join that fails ends the processes of every job at different moments: this process
// frees the join's communicators and gives its peers up (give_up_peers: a late write to one
// that is gone killed a DEM rank by SIGPIPE in 1 of 3 refused launches; MPI_Finalize bounded
// by 5 s).
template <class F>
MPI_Comm or_give_up(std::vector<MPI_Comm>& made, F&& join) {
  try {
    return join();
  } catch (...) {
    for (MPI_Comm& c : made) MPI_Comm_free(&c);  // unchecked: already failing
    made.clear();
    give_up_peers();
    throw;
  }
}

// The joins; `made` collects the communicators they create (freed on success here, on a
// failure by or_give_up).
MPI_Comm join_client(
    int jobs, const std::function<std::string(int job)>& find_port,
    const std::function<MPI_Comm(const std::string& port, MPI_Comm group)>& connect,
    std::vector<MPI_Comm>& made) {
  assert(jobs >= 2);
  MPI_Comm group = MPI_COMM_SELF;
  for (int j = 0; j < jobs; ++j) {
    std::string port;
    try {
      port = find_port(j);
    } catch (const PeerError&) {
      if (j > 0) {  // the jobs already joined would wait for a connect that never comes
        int word = kGaveUp;
        MPMDEM_CHECK_MPI(MPI_Bcast(&word, 1, MPI_INT, 0, group));
      }
      throw;
    }
    if (j > 0) MPMDEM_CHECK_MPI(MPI_Bcast(&j, 1, MPI_INT, 0, group));
    MPI_Comm inter = connect(port, group);
    group = merge(inter, false);
    made.push_back(inter);
    made.push_back(group);
    check_join(group, jobs, j, -1, -1);
  }
  int done = kDone;
  MPMDEM_CHECK_MPI(MPI_Bcast(&done, 1, MPI_INT, 0, group));
  MPI_Comm side = MPI_COMM_NULL;
  const MPI_Comm joined = split_sides(group, false, side);
  made.push_back(side);
  free_all(made);
  return joined;
}

MPI_Comm join_server(MPI_Comm accepted, int jobs, int job, double wait_s, MPI_Comm& servers,
                     std::vector<MPI_Comm>& made) {
  assert(jobs >= 2 && job >= 0 && job < jobs);
  made.push_back(accepted);
  MPI_Comm group = merge(accepted, true);
  made.push_back(group);
  check_join(group, jobs, job, jobs, job);
  for (;;) {
    int word = 0;
    {
      Watchdog w = bound(wait_s, "waiting for mpm_app to join the next DEM job");
      MPMDEM_CHECK_MPI(MPI_Bcast(&word, 1, MPI_INT, 0, group));
    }
    if (word == kDone) break;
    if (word == kGaveUp) {
      throw PeerError("mpm_app found no port of the next DEM job and gave up (see its log)");
    }
    if (word <= job || word >= jobs) {
      throw PeerError("mpm_app asked to join DEM job " + std::to_string(word) + " of " +
                      std::to_string(jobs) + " after job " + std::to_string(job) +
                      " (protocol violation)");
    }
    MPI_Comm inter = MPI_COMM_NULL;
    {
      Watchdog w = bound(wait_s, "connecting DEM job " + std::to_string(word));
      char none[1] = {'\0'};  // the port matters at the root (the client) only
      MPMDEM_CHECK_MPI(MPI_Comm_connect(none, MPI_INFO_NULL, 0, group, &inter));
    }
    MPMDEM_CHECK_MPI(MPI_Comm_set_errhandler(inter, MPI_ERRORS_RETURN));
    group = merge(inter, false);
    made.push_back(inter);
    made.push_back(group);
    check_join(group, jobs, word, jobs, -1);
  }
  const MPI_Comm joined = split_sides(group, true, servers);
  free_all(made);
  return joined;
}

}  // namespace

MPI_Comm join_jobs_as_client(
    int jobs, const std::function<std::string(int job)>& find_port,
    const std::function<MPI_Comm(const std::string& port, MPI_Comm group)>& connect) {
  std::vector<MPI_Comm> made;
  return or_give_up(made, [&] { return join_client(jobs, find_port, connect, made); });
}

MPI_Comm join_jobs_as_server(MPI_Comm accepted, int jobs, int job, double wait_s,
                             MPI_Comm& servers) {
  std::vector<MPI_Comm> made;
  return or_give_up(made, [&] { return join_server(accepted, jobs, job, wait_s, servers, made); });
}

}  // namespace mpmdem
