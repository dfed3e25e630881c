// The wire protocol's pure parts: partitions, the handshake verdict, struct layouts.
#include <gtest/gtest.h>

#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <string>

#include "mpmdem/exchange.hpp"
#include "mpmdem/handshake.hpp"
#include "mpmdem/partition.hpp"
#include "mpmdem/protocol.hpp"

namespace {

using mpmdem::check_compatible;
using mpmdem::HelloFields;
using mpmdem::make_hello;
using mpmdem::partition_contiguous;
namespace protocol = mpmdem::protocol;

// --- partitions ----------------------------------------------------------------------------

TEST(Partition, ContiguousNearlyEqualAndComplete) {
  for (std::uint64_t n : {0ull, 1ull, 5ull, 11ull, 64ull, 65882ull}) {
    for (int parts : {1, 2, 3, 7, 16, 384}) {
      const auto p = partition_contiguous(n, parts);
      ASSERT_EQ(p.size(), static_cast<std::size_t>(parts));
      std::uint64_t next = 0, lo = ~0ull, hi = 0;
      for (const auto& q : p) {
        EXPECT_EQ(q.offset, next) << "n=" << n << " parts=" << parts;  // contiguous, ordered
        next += q.count;
        lo = std::min(lo, q.count);
        hi = std::max(hi, q.count);
      }
      EXPECT_EQ(next, n) << "partitions must cover every RVE exactly once";
      EXPECT_LE(hi - lo, 1u) << "sizes differ by at most one";
    }
  }
}

TEST(Partition, LargerPartitionsComeFirst) {
  const auto p = partition_contiguous(11, 3);  // 4, 4, 3
  EXPECT_EQ(p[0].count, 4u);
  EXPECT_EQ(p[1].count, 4u);
  EXPECT_EQ(p[2].count, 3u);
  EXPECT_EQ(p[2].offset, 8u);
}

TEST(Partition, NoPartsGivesNothing) {
  EXPECT_TRUE(partition_contiguous(10, 0).empty());
}

// --- handshake verdict -------------------------------------------------------------------

struct Pair {
  protocol::Hello client, server;
};

Pair compatible_pair() {
  HelloFields c;
  c.program = "mpm_app";
  c.backend = "elastic";
  c.n_rve = 1000;
  c.n_partitions = 2;
  c.outputs = 0;
  c.config_hash = 0x1234abcdull;
  HelloFields s = c;
  s.program = "dem_app";
  s.n_rve = 0;  // the server accepts the client's count
  return {make_hello(c), make_hello(s)};
}

void expect_names(const std::string& msg, std::initializer_list<const char*> parts) {
  for (const char* p : parts) {
    EXPECT_NE(msg.find(p), std::string::npos) << "message lacks '" << p << "': " << msg;
  }
}

TEST(Handshake, MakeHelloFillsIdentity) {
  const auto h = compatible_pair().client;
  EXPECT_EQ(h.magic, protocol::kMagic);
  EXPECT_EQ(h.version_major, protocol::kVersionMajor);
  EXPECT_EQ(h.version_minor, protocol::kVersionMinor);
  EXPECT_EQ(h.request_size, sizeof(protocol::RveRequest));
  EXPECT_EQ(h.reply_size, sizeof(protocol::RveReply));
  EXPECT_STREQ(h.program, "mpm_app");
  EXPECT_STREQ(h.backend, "elastic");
}

TEST(Handshake, CompatiblePairPasses) {
  const auto p = compatible_pair();
  EXPECT_FALSE(check_compatible(p.client, p.server).has_value());
}

TEST(Handshake, ConfigHashMismatchNamesBothHashesAndFiles) {
  auto p = compatible_pair();
  p.server.config_hash = 0xfeedull;
  const auto msg = check_compatible(p.client, p.server, "configs/a.yaml", "configs/b.yaml");
  ASSERT_TRUE(msg.has_value());
  expect_names(*msg,
               {"coupling section hash differs", "mpm_app 0x000000001234abcd (configs/a.yaml)",
                "dem_app 0x000000000000feed (configs/b.yaml)"});
}

TEST(Handshake, MajorVersionMismatchNamesBothVersions) {
  auto p = compatible_pair();
  p.server.version_major = 7;
  p.server.config_hash = 1;  // nothing else is reported once the major version differs
  const auto msg = check_compatible(p.client, p.server);
  ASSERT_TRUE(msg.has_value());
  const std::string mine = "mpm_app " + std::to_string(protocol::kVersionMajor) + ".";
  expect_names(*msg, {"protocol major version differs", mine.c_str(), "dem_app 7."});
  EXPECT_EQ(msg->find("hash"), std::string::npos);
}

TEST(Handshake, MinorVersionDifferenceIsAcceptedWithANote) {
  auto p = compatible_pair();
  p.server.version_minor = static_cast<std::uint16_t>(p.client.version_minor + 3);
  EXPECT_FALSE(check_compatible(p.client, p.server).has_value());
  const auto note = mpmdem::minor_version_note(p.client, p.server);
  ASSERT_TRUE(note.has_value());
  expect_names(*note, {"minor", "mpm_app", "dem_app"});
  EXPECT_FALSE(mpmdem::minor_version_note(p.client, p.client).has_value());
}

TEST(Handshake, MagicMismatchIsRefused) {
  auto p = compatible_pair();
  p.server.magic = 0x444d504du;  // byte-swapped
  const auto msg = check_compatible(p.client, p.server);
  ASSERT_TRUE(msg.has_value());
  expect_names(*msg, {"magic", "0x000000004d504d44", "0x00000000444d504d"});
}

TEST(Handshake, StructSizeMismatchNamesBothSizes) {
  auto p = compatible_pair();
  p.server.reply_size = 136;  // a 1.x server
  const auto msg = check_compatible(p.client, p.server);
  ASSERT_TRUE(msg.has_value());
  expect_names(*msg, {"struct sizes differ", "RveReply 144 B", "/ 136 B"});
}

TEST(Handshake, RveCountIsTheClientsUnlessTheServerWasGivenOne) {
  auto p = compatible_pair();
  EXPECT_FALSE(check_compatible(p.client, p.server).has_value());  // server n_rve = 0
  p.server.n_rve = 999;
  const auto msg = check_compatible(p.client, p.server);
  ASSERT_TRUE(msg.has_value());
  expect_names(*msg, {"RVE count differs", "mpm_app 1000", "dem_app 999"});
}

TEST(Handshake, PartitionCountMismatchNamesBoth) {
  auto p = compatible_pair();
  p.server.n_partitions = 3;
  const auto msg = check_compatible(p.client, p.server);
  ASSERT_TRUE(msg.has_value());
  expect_names(*msg, {"partition count differs", "sees 2", "runs on 3"});
}

TEST(Handshake, OutputsTheBackendCannotProvideAreRefused) {
  auto p = compatible_pair();
  p.client.outputs = protocol::kOutputRotation | protocol::kOutputPorosity;
  p.server.outputs = protocol::kOutputPorosity;  // capability mask
  const auto msg = check_compatible(p.client, p.server);
  ASSERT_TRUE(msg.has_value());
  expect_names(*msg,
               {"outputs requested by mpm_app", "rotation", "'elastic'", "provides: porosity"});
  EXPECT_EQ(msg->find("rotation, porosity"), std::string::npos) << "porosity is available";
  p.server.outputs = protocol::kKnownOutputs;
  EXPECT_FALSE(check_compatible(p.client, p.server).has_value());
}

TEST(Handshake, BackendMismatchNamesBoth) {
  auto p = compatible_pair();
  std::strcpy(p.server.backend, "yade");
  const auto msg = check_compatible(p.client, p.server);
  ASSERT_TRUE(msg.has_value());
  expect_names(*msg, {"backend differs", "'elastic'", "'yade'"});
}

TEST(Handshake, EveryProblemIsReported) {
  auto p = compatible_pair();
  p.server.config_hash = 2;
  std::strcpy(p.server.backend, "yade");
  const auto msg = check_compatible(p.client, p.server);
  ASSERT_TRUE(msg.has_value());
  expect_names(*msg, {"backend differs", "hash differs"});
}

TEST(Handshake, FakeMajorVersionHookForTests) {
  ::setenv("MPMDEM_TEST_FAKE_VERSION_MAJOR", "42", 1);
  const auto h = make_hello(HelloFields{});
  ::unsetenv("MPMDEM_TEST_FAKE_VERSION_MAJOR");
  EXPECT_EQ(h.version_major, 42);
  EXPECT_EQ(make_hello(HelloFields{}).version_major, protocol::kVersionMajor);
}

TEST(Handshake, OutputNames) {
  EXPECT_EQ(mpmdem::output_names(0), "none");
  EXPECT_EQ(mpmdem::output_names(protocol::kOutputRotation | protocol::kOutputCoordination),
            "rotation, coordination");
}

// --- status classification ---------------------------------------------------------------

TEST(Status, OnlyFaultsAreFatal) {
  EXPECT_FALSE(mpmdem::is_fatal(static_cast<int>(protocol::RveStatus::kOk)));
  EXPECT_FALSE(mpmdem::is_fatal(static_cast<int>(protocol::RveStatus::kNoContacts)));
  EXPECT_TRUE(mpmdem::is_fatal(static_cast<int>(protocol::RveStatus::kNonFinite)));
  EXPECT_TRUE(mpmdem::is_fatal(static_cast<int>(protocol::RveStatus::kExploding)));
  EXPECT_TRUE(mpmdem::is_fatal(static_cast<int>(protocol::RveStatus::kBackendError)));
  EXPECT_TRUE(mpmdem::is_fatal(99));
}

// --- layouts (docs/protocol.md documents these offsets) ----------------------------------

TEST(Layout, DocumentedOffsets) {
  EXPECT_EQ(offsetof(protocol::ControlHeader, step), 8u);
  EXPECT_EQ(offsetof(protocol::ControlHeader, path), 32u);
  EXPECT_EQ(offsetof(protocol::Hello, n_rve), 16u);
  EXPECT_EQ(offsetof(protocol::Hello, config_hash), 32u);
  EXPECT_EQ(offsetof(protocol::Hello, program), 40u);
  EXPECT_EQ(offsetof(protocol::RveInit, point), 72u);
  EXPECT_EQ(offsetof(protocol::RveRequest, dt), 72u);
  EXPECT_EQ(offsetof(protocol::RveRequest, flags), 80u);
  EXPECT_EQ(offsetof(protocol::RveReply, rotation), 72u);
  EXPECT_EQ(offsetof(protocol::RveReply, stiffness), 120u);
  EXPECT_EQ(offsetof(protocol::RveReply, cost_s), 128u);
  EXPECT_EQ(offsetof(protocol::RveReply, status), 136u);
  EXPECT_EQ(offsetof(protocol::RveReply, n_substeps), 140u);
  EXPECT_EQ(offsetof(protocol::RankReport, compute_s), 16u);
  EXPECT_EQ(offsetof(protocol::RankReport, message), 24u);
  EXPECT_EQ(sizeof(protocol::RankReport::message), 232u);
}

}  // namespace
