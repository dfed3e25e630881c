// How a run ended, mapped once to summary.json's status and mpm_app's exit code
// (run_status.hpp), as docs/outputs.md states them.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "errors.hpp"
#include "mpmdem/config/schema.hpp"
#include "mpmdem/errors.hpp"
#include "output/run_directory.hpp"
#include "run_status.hpp"

using mpmdem::mpm::RunStatus;

TEST(RunStatus, EachEndHasItsSummaryStatusAndExitCode) {
  struct Case {
    RunStatus status;
    const char* text;
    int code;
    bool failure;
  };
  const Case cases[] = {
      {RunStatus::kComplete, "complete", 0, false},
      {RunStatus::kTruncated, "truncated", 0, false},
      {RunStatus::kInterrupted, "interrupted", 130, false},
      {RunStatus::kConfigError, "failed", 2, true},
      {RunStatus::kRefused, "failed", 3, true},
      {RunStatus::kFailed, "failed", 4, true},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    EXPECT_STREQ(mpmdem::mpm::status_text(c.status), c.text);
    EXPECT_EQ(mpmdem::mpm::exit_code(c.status), c.code);
    EXPECT_EQ(mpmdem::mpm::is_failure(c.status), c.failure);
  }
  // The interface's exit codes, which dem_app returns too, are the same numbers.
  EXPECT_EQ(mpmdem::mpm::exit_code(RunStatus::kConfigError), mpmdem::kExitConfigError);
  EXPECT_EQ(mpmdem::mpm::exit_code(RunStatus::kRefused), mpmdem::kExitHandshakeError);
  EXPECT_EQ(mpmdem::mpm::exit_code(RunStatus::kFailed), mpmdem::kExitPeerError);
}

TEST(RunStatus, AFaultEndsTheRunAsItsKind) {
  using mpmdem::mpm::failure_status;
  EXPECT_EQ(failure_status(mpmdem::mpm::SceneError("grid.cell_size", "is 0")),
            RunStatus::kConfigError);
  EXPECT_EQ(failure_status(mpmdem::config::ConfigError("s.yaml", 3, "solver.cfl", "is 2")),
            RunStatus::kConfigError);
  EXPECT_EQ(failure_status(mpmdem::mpm::RunDirectoryError("runs/x holds a run")),
            RunStatus::kConfigError);
  EXPECT_EQ(failure_status(mpmdem::HandshakeError("config hash differs")), RunStatus::kRefused);
  EXPECT_EQ(failure_status(mpmdem::PeerError("DEM rank 1 died")), RunStatus::kFailed);
  EXPECT_EQ(failure_status(mpmdem::mpm::SimulationError("non-finite stress")), RunStatus::kFailed);
  EXPECT_EQ(failure_status(std::runtime_error("disk full")), RunStatus::kFailed);
}
