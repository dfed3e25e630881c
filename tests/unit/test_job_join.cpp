// Names of the DEM jobs' ports (interface job_join.hpp): one job keeps the names of the
// scene; job j of several gets its own, so that each accepts on its own port.
#include <gtest/gtest.h>

#include "mpmdem/job_join.hpp"

namespace {

TEST(JobJoin, OneJobKeepsTheScenesNames) {
  EXPECT_EQ(mpmdem::job_port_file("/run/dem_port.txt", 0, 1), "/run/dem_port.txt");
  EXPECT_EQ(mpmdem::job_service_name("mpmdem", 0, 1), "mpmdem");
}

TEST(JobJoin, EachOfSeveralJobsHasItsOwnPortFileAndService) {
  EXPECT_EQ(mpmdem::job_port_file("/run/dem_port.txt", 0, 3), "/run/dem_port.job0.txt");
  EXPECT_EQ(mpmdem::job_port_file("/run/dem_port.txt", 2, 3), "/run/dem_port.job2.txt");
  EXPECT_EQ(mpmdem::job_port_file("/run/port", 1, 2), "/run/port.job1");
  EXPECT_EQ(mpmdem::job_port_file("", 1, 2), "") << "no port file stays none";
  EXPECT_EQ(mpmdem::job_service_name("mpmdem", 1, 2), "mpmdem.job1");
}

}  // namespace
