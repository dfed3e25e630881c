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
  EXPECT_THROW(w.wait(recv, "a test", 60.0), mpmdem::PeerLost);
  EXPECT_LT(seconds_since(t0), 10.0) << "the quiet time delayed the dead rank's report";
  MPI_Cancel(&recv);
  MPI_Wait(&recv, MPI_STATUS_IGNORE);
}

}  // namespace
