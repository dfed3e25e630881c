// Peer-fault detection without MPI: the liveness probe of PeerWatch on real processes.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <string>
#include <vector>

#include "mpmdem/peer_watch.hpp"
#include "mpmdem/protocol.hpp"

namespace {

using mpmdem::PeerWatch;
namespace protocol = mpmdem::protocol;

protocol::RankIdentity identity(int rank, pid_t pid, const std::string& host) {
  protocol::RankIdentity id;
  std::memset(&id, 0, sizeof id);
  id.rank = rank;
  id.pid = static_cast<std::int32_t>(pid);
  std::memcpy(id.host, host.data(), std::min(host.size(), sizeof id.host - 1));
  return id;
}

// A child that sleeps until killed.
pid_t sleeper() {
  const pid_t pid = ::fork();
  if (pid == 0) {
    for (;;) ::pause();
  }
  return pid;
}

TEST(PeerWatch, OwnIdentityIsThisProcessOnThisHost) {
  const protocol::RankIdentity me = mpmdem::own_identity(3);
  EXPECT_EQ(me.rank, 3);
  EXPECT_EQ(me.pid, static_cast<std::int32_t>(::getpid()));
  EXPECT_EQ(std::string(me.host), mpmdem::this_host_name());
  EXPECT_FALSE(mpmdem::this_host_name().empty());
}

TEST(PeerWatch, FindsTheKilledRankOnlyAfterItDied) {
  const std::string host = mpmdem::this_host_name();
  const pid_t a = sleeper(), b = sleeper();
  ASSERT_GT(a, 0);
  ASSERT_GT(b, 0);
  PeerWatch w;
  w.set_peers({identity(0, a, host), identity(1, b, host)}, host);
  EXPECT_TRUE(w.dead_ranks().empty()) << "both ranks are alive";
  ::kill(b, SIGKILL);
  ::waitpid(b, nullptr, 0);  // reaped, as mpirun does with its ranks
  EXPECT_EQ(w.dead_ranks(), std::vector<int>{1});
  EXPECT_EQ(w.describe(1),
            "DEM server rank 1 (pid " + std::to_string(b) + " on host " + host + ")");
  ::kill(a, SIGKILL);
  ::waitpid(a, nullptr, 0);
  EXPECT_EQ(w.dead_ranks(), (std::vector<int>{0, 1}));
}

TEST(PeerWatch, RanksOnOtherHostsAreNotProbed) {
  const pid_t gone = sleeper();
  ::kill(gone, SIGKILL);
  ::waitpid(gone, nullptr, 0);
  PeerWatch w;
  // The same pid on another host says nothing about this host's process table.
  w.set_peers({identity(0, gone, "some-other-node")}, mpmdem::this_host_name());
  EXPECT_TRUE(w.dead_ranks().empty());
  EXPECT_EQ(w.describe(0),
            "DEM server rank 0 (pid " + std::to_string(gone) + " on host some-other-node)");
  EXPECT_EQ(w.describe(7), "DEM server rank 7");
}

TEST(Protocol, RankIdentityLayout) {
  EXPECT_EQ(sizeof(protocol::RankIdentity), 128u);
  EXPECT_EQ(offsetof(protocol::RankIdentity, pid), 4u);
  EXPECT_EQ(offsetof(protocol::RankIdentity, host), 8u);
  EXPECT_GE(protocol::kVersionMajor, 3) << "RankIdentity arrived with protocol 3.0";
}

}  // namespace
