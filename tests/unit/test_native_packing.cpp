// Native packing files: a written packing reads back bit for bit (full precision text), and a
// malformed file is refused naming its line.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "backends/native/binary_state.hpp"
#include "backends/native/packing.hpp"

namespace {

using namespace mpmdem::dem::native;

std::filesystem::path temp_file(const std::string& name) {
  return std::filesystem::temp_directory_path() /
         ("mpmdem_native_" + std::to_string(::getpid()) + "_" + name);
}

TEST(NativePacking, WrittenPackingReadsBackBitForBit) {
  CloudParams p;
  p.n_spheres = 30;
  p.seed = 5;
  RveRecord a;
  a.state = build_cloud(p);
  a.state.spheres.vel.set(3, Vec3(1.0 / 3.0, -2e-7, M_PI));
  a.state.spheres.ori[4] = Quat(Eigen::AngleAxisd(0.3, Vec3(1, 2, 3).normalized()));
  a.state.contacts.add(1, 2, CellDist(0, -1, 1));
  a.state.contacts.normal.set(0, Vec3(0, 0.6, 0.8));
  a.state.contacts.penetration[0] = 1e-5 / 3.0;
  a.state.contacts.shear_force.set(0, Vec3(1e-9 / 3.0, 0, -1));
  a.state.cell.trsf(0, 1) = 1e-3 / 3.0;
  const auto file = temp_file("pack.native.txt");
  write_packing(a.state, file);
  RveRecord b;
  b.state = read_packing(file);
  std::filesystem::remove(file);
  EXPECT_EQ(encode(a), encode(b));
  EXPECT_EQ(b.state.spheres.size(), 30u);
}

TEST(NativePacking, MalformedFileNamesItsLine) {
  const auto file = temp_file("bad.native.txt");
  {
    std::ofstream out(file);
    out << "mpmdem-native-packing 1\ndt 1e-7\nmaterial 6e8 0.8 2500\n";
  }
  try {
    read_packing(file);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("line 3"), std::string::npos) << e.what();
  }
  std::filesystem::remove(file);
  EXPECT_THROW(read_packing(temp_file("missing.native.txt")), std::runtime_error);
}

}  // namespace
