// Native packing files: a written packing reads back bit for bit (full precision text), and a
// malformed file is refused naming its line; a binary state of version NAT4 is still read.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

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

// The binary state as version NAT4 wrote it: vector fields xyz interleaved.
class Nat4Writer {
 public:
  template <typename T>
  void put(const T& v) {
    b_.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  template <typename T>
  void put_vector(const std::vector<T>& v) {
    put<std::uint64_t>(v.size());
    b_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  template <typename T, typename V>
  void put_interleaved(const Split3<T, V>& v) {
    std::vector<V> w(v.size());
    for (std::size_t k = 0; k < v.size(); ++k) w[k] = v[k];
    put_vector(w);
  }
  std::string encode(const RveRecord& r) {
    for (char c : std::string("MPMDNAT4")) put(c);
    const RveState& s = r.state;
    put(s.cell.hsize), put(s.cell.trsf), put(s.cell.vel_grad), put(s.cell.next_vel_grad);
    put(s.cell.vel_grad_changed), put(s.cell.prev_vel_grad), put(s.cell.vgrad_times_prev_h);
    put(s.material), put(s.dt), put(s.iter);
    const Spheres& sp = s.spheres;
    put_vector(sp.radius), put_vector(sp.mass), put_vector(sp.inertia);
    put_interleaved(sp.pos), put_interleaved(sp.vel), put_interleaved(sp.ang_vel);
    put_vector(sp.ori), put_vector(sp.ref_ori);
    const Contacts& c = s.contacts;
    put_vector(c.id1), put_vector(c.id2), put_interleaved(c.cell);
    put_interleaved(c.normal), put_interleaved(c.shear_force), put_vector(c.penetration);
    put(r.point), put(r.p0), put(r.tilings), put(r.unbalanced);
    put_vector(std::vector<char>(r.packing.begin(), r.packing.end()));
    return b_;
  }

 private:
  std::string b_;
};

TEST(NativePacking, Nat4StateIsStillRead) {
  CloudParams p;
  p.n_spheres = 20;
  p.seed = 3;
  RveRecord a;
  a.state = build_cloud(p);
  a.state.spheres.vel.set(2, Vec3(1.0 / 3.0, -2e-7, M_PI));
  a.state.spheres.ang_vel.set(5, Vec3(-1, 1e-3, 7));
  a.state.contacts.add(1, 2, CellDist(0, -1, 1));
  a.state.contacts.add(4, 3, CellDist(2, 0, -3));
  a.state.contacts.normal.set(1, Vec3(0, 0.6, 0.8));
  a.state.contacts.shear_force.set(1, Vec3(1e-9 / 3.0, 0, -1));
  a.point = 17, a.p0 = 1e4 / 3.0, a.tilings = 1, a.unbalanced = 0.25, a.packing = "col100_s1";
  const RveRecord b = decode(Nat4Writer().encode(a));
  EXPECT_EQ(encode(a), encode(b));
  EXPECT_EQ(b.state.contacts.cell[1], CellDist(2, 0, -3));
  EXPECT_EQ(b.state.spheres.vel[2], Vec3(1.0 / 3.0, -2e-7, M_PI));
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
