// PeerWatch::wait on real MPI requests (a singleton MPI_Init, no mpirun): the quiet time
// sleeps instead of polling, yet neither delays a completed request nor a dead rank's report.
#include <gtest/gtest.h>
#include <mpi.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <string>
#include <vector>

#include "mpmdem/errors.hpp"
#include "mpmdem/peer_watch.hpp"
#include "mpmdem/protocol.hpp"

namespace {

using mpmdem::PeerWatch;
using Clock = std::chrono::steady_clock;

class MpiEnvironment : public ::testing::Environment {
 public:
  void SetUp() override { MPI_Init(nullptr, nullptr); }
  void TearDown() override { MPI_Finalize(); }
};
const auto* const kMpi = ::testing::AddGlobalTestEnvironment(new MpiEnvironment);

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

TEST(PeerWatchWait, ACompletedRequestReturnsAtOnceWhateverTheQuietTime) {
  int out = 7, in = 0;
  MPI_Request send = MPI_REQUEST_NULL, recv = MPI_REQUEST_NULL;
  MPI_Irecv(&in, 1, MPI_INT, 0, 1, MPI_COMM_SELF, &recv);
  MPI_Isend(&out, 1, MPI_INT, 0, 1, MPI_COMM_SELF, &send);
  MPI_Wait(&send, MPI_STATUS_IGNORE);
  PeerWatch w;
  const auto t0 = Clock::now();
  w.wait(recv, "a test", 30.0);
  EXPECT_LT(seconds_since(t0), 5.0) << "slept through the quiet time with the reply there";
  EXPECT_EQ(in, 7);
}

TEST(PeerWatchWait, ADeadRankIsFoundDuringTheQuietTime) {
  const pid_t child = ::fork();
  if (child == 0) {
    for (;;) ::pause();
  }
  ASSERT_GT(child, 0);
  ::kill(child, SIGKILL);
  ::waitpid(child, nullptr, 0);
  mpmdem::protocol::RankIdentity id;
  std::memset(&id, 0, sizeof id);
  id.pid = static_cast<std::int32_t>(child);
  const std::string host = mpmdem::this_host_name();
  std::memcpy(id.host, host.data(), std::min(host.size(), sizeof id.host - 1));
  PeerWatch w;
  w.set_peers({id}, host);
  w.set_probe_interval(0.05);
  int in = 0;
  MPI_Request recv = MPI_REQUEST_NULL;  // nobody sends: only the probe can end the wait
  MPI_Irecv(&in, 1, MPI_INT, 0, 2, MPI_COMM_SELF, &recv);
  const auto t0 = Clock::now();
  try {
    w.wait(recv, "a test", 60.0);
    ADD_FAILURE() << "the wait ended without the dead rank's reply";
  } catch (const mpmdem::PeerLost& e) {
    EXPECT_EQ(e.kind(), mpmdem::PeerLost::Kind::kDied);
    EXPECT_TRUE(e.exact());
    EXPECT_EQ(e.hosts(), std::vector<std::string>{host});
  }
  EXPECT_LT(seconds_since(t0), 10.0) << "the quiet time delayed the dead rank's report";
  MPI_Cancel(&recv);
  MPI_Wait(&recv, MPI_STATUS_IGNORE);
}

// Three server ranks on other hosts (not probeable), one request each: ranks 0 and 2 answer,
// rank 1 does not (its host was cut off). Past the stall limit the wait names rank 1 alone.
TEST(PeerWatchWait, AStallNamesOnlyTheRanksThatDidNotAnswer) {
  std::vector<mpmdem::protocol::RankIdentity> peers(3);
  const std::string hosts[3] = {"node-b", "node-c", "node-b"};
  for (int r = 0; r < 3; ++r) {
    auto& id = peers[static_cast<std::size_t>(r)];
    std::memset(&id, 0, sizeof id);
    id.rank = r;
    id.pid = 1000 + r;
    std::memcpy(id.host, hosts[r].data(), hosts[r].size());
  }
  PeerWatch w;
  w.set_peers(peers, "node-a");
  w.set_stall_limit(0.3);
  w.set_probe_interval(0.05);
  int in[3] = {0, 0, 0}, out = 5;
  std::vector<MPI_Request> recvs(3, MPI_REQUEST_NULL);
  for (int r = 0; r < 3; ++r) MPI_Irecv(&in[r], 1, MPI_INT, 0, 10 + r, MPI_COMM_SELF, &recvs[r]);
  for (int r : {0, 2}) MPI_Send(&out, 1, MPI_INT, 0, 10 + r, MPI_COMM_SELF);
  const auto t0 = Clock::now();
  try {
    w.wait_each(recvs, {0, 1, 2}, "step 9");
    ADD_FAILURE() << "the wait ended without rank 1's reply";
  } catch (const mpmdem::PeerLost& e) {
    EXPECT_EQ(e.ranks(), std::vector<int>{1});
    const std::string what = e.what();
    EXPECT_NE(what.find("no reply from DEM server rank 1 (pid 1001 on host node-c) within 0.3 s"),
              std::string::npos)
        << what;
    EXPECT_NE(what.find("during step 9 (2 of 3 server ranks replied)"), std::string::npos) << what;
    // The host and its silent ranks, for a reader and for scripts/run --on-fault resume.
    EXPECT_NE(what.find("unreachable, hung or dead (host node-c: rank 1)"), std::string::npos)
        << what;
    EXPECT_EQ(e.hosts(), std::vector<std::string>{"node-c"});
    EXPECT_TRUE(e.exact()) << "one request per rank: the silent rank is known";
    EXPECT_EQ(e.kind(), mpmdem::PeerLost::Kind::kNoReply);
  }
  const double took = seconds_since(t0);
  EXPECT_GE(took, 0.3);
  EXPECT_LT(took, 5.0);
  EXPECT_EQ(in[0], 5);
  EXPECT_EQ(in[2], 5);
  MPI_Cancel(&recvs[1]);
  MPI_Wait(&recvs[1], MPI_STATUS_IGNORE);
}

}  // namespace
