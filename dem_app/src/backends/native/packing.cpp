// Packing files and random clouds: see packing.hpp.
#include "backends/native/packing.hpp"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <random>
#include <sstream>
#include <stdexcept>

namespace mpmdem::dem::native {

namespace {

class Reader {
 public:
  explicit Reader(const std::filesystem::path& file) : file_(file), in_(file) {
    if (!in_) throw std::runtime_error("cannot read native packing " + file.string());
  }
  // Next line, which must start with `tag`; the rest as a stream.
  std::istringstream line(const std::string& tag) {
    std::string text;
    while (std::getline(in_, text)) {
      ++line_no_;
      if (!text.empty() && text[0] != '#') break;
    }
    std::istringstream s(text);
    std::string word;
    if (!tag.empty()) {
      s >> word;
      if (word != tag) fail("expected '" + tag + "', found '" + word + "'");
    }
    return s;
  }
  template <typename T>
  void read(std::istringstream& s, T* v, int n) {
    for (int i = 0; i < n; ++i) {
      if (!(s >> v[i])) fail("too few numbers");
    }
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error(file_.string() + " line " + std::to_string(line_no_) + ": " + what);
  }

 private:
  std::filesystem::path file_;
  std::ifstream in_;
  int line_no_ = 0;
};

void read_matrix(Reader& r, const std::string& tag, Eigen::Matrix3d& m) {
  auto s = r.line(tag);
  double v[9];
  r.read(s, v, 9);
  for (int i = 0; i < 9; ++i) m(i / 3, i % 3) = v[i];
}

void write_matrix(std::ostream& out, const char* tag, const Eigen::Matrix3d& m) {
  out << tag;
  for (int i = 0; i < 9; ++i) out << ' ' << m(i / 3, i % 3);
  out << '\n';
}

}  // namespace

RveState read_packing(const std::filesystem::path& file) {
  Reader r(file);
  RveState s;
  {
    auto l = r.line(kPackingMagic);
    int version = 0;
    r.read(l, &version, 1);
    if (version != 1) r.fail("unsupported version " + std::to_string(version));
  }
  {
    auto l = r.line("dt");
    r.read(l, &s.dt, 1);
    if (!(s.dt > 0)) r.fail("dt must be > 0");
  }
  {
    auto l = r.line("material");
    double v[4];
    r.read(l, v, 4);
    s.material = Material{v[0], v[1], v[2], v[3]};
  }
  read_matrix(r, "hsize", s.cell.hsize);
  read_matrix(r, "trsf", s.cell.trsf);
  read_matrix(r, "vel_grad", s.cell.vel_grad);
  read_matrix(r, "prev_vel_grad", s.cell.prev_vel_grad);
  std::size_t n = 0;
  {
    auto l = r.line("spheres");
    r.read(l, &n, 1);
  }
  s.spheres.resize(n);
  auto& sp = s.spheres;
  for (std::size_t i = 0; i < n; ++i) {
    auto l = r.line("");
    double v[20];
    r.read(l, v, 20);
    sp.radius[i] = v[0];
    sp.mass[i] = v[1];
    sp.inertia[i] = v[2];
    sp.pos.set(i, Vec3(v[3], v[4], v[5]));
    sp.vel.set(i, Vec3(v[6], v[7], v[8]));
    sp.ang_vel.set(i, Vec3(v[9], v[10], v[11]));
    sp.ori[i] = Quat(v[12], v[13], v[14], v[15]);
    sp.ref_ori[i] = Quat(v[16], v[17], v[18], v[19]);
    if (!(sp.radius[i] > 0 && sp.mass[i] > 0 && sp.inertia[i] > 0)) {
      r.fail("radius, mass and inertia must be > 0");
    }
  }
  std::size_t m = 0;
  {
    auto l = r.line("contacts");
    r.read(l, &m, 1);
  }
  for (std::size_t k = 0; k < m; ++k) {
    auto l = r.line("");
    long ids[5];
    r.read(l, ids, 5);
    double v[13];
    r.read(l, v, 13);
    if (ids[0] < 0 || ids[1] < 0 || static_cast<std::size_t>(ids[0]) >= n ||
        static_cast<std::size_t>(ids[1]) >= n) {
      r.fail("contact between unknown spheres");
    }
    const std::size_t c = s.contacts.add(
        static_cast<std::uint32_t>(ids[0]), static_cast<std::uint32_t>(ids[1]),
        to_cell_dist(Eigen::Vector3i(static_cast<int>(ids[2]), static_cast<int>(ids[3]),
                                     static_cast<int>(ids[4]))));
    // kn and ks follow from the radii (contact_stiffness); YADE's saved values agree to an
    // ulp or two (its own rounding of the same formula).
    const FrictPhys phys = contact_stiffness(s, c);
    if (!(std::abs(phys.kn - v[0]) <= 1e-12 * phys.kn &&
          std::abs(phys.ks - v[1]) <= 1e-12 * phys.ks)) {
      r.fail("contact kn, ks differ from the radii and the material's");
    }
    // One friction angle per RVE (FrictPhys: tan of the smaller of the two, both the same).
    if (v[2] != std::tan(s.material.friction_angle)) {
      r.fail("contact friction differs from the material's (one material per RVE)");
    }
    s.contacts.normal.set(c, Vec3(v[3], v[4], v[5]));
    s.contacts.shear_force.set(c, Vec3(v[6], v[7], v[8]));
    // The normal force is kn max(pen, 0) n (Contacts::normal_force). YADE does not save
    // penetrationDepth (exported as 0): then the penetration |Fn| / kn reproduces the saved
    // normal force (to rounding) until the first step recomputes both.
    s.contacts.penetration[c] = v[12] > 0 ? v[12] : Vec3(v[9], v[10], v[11]).norm() / v[0];
  }
  return s;
}

void write_packing(const RveState& s, const std::filesystem::path& file) {
  std::ofstream out(file);
  if (!out) throw std::runtime_error("cannot write native packing " + file.string());
  out << std::setprecision(17);
  out << kPackingMagic << " 1\n"
      << "dt " << s.dt << '\n';
  const Material& m = s.material;
  out << "material " << m.young << ' ' << m.ks_kn << ' ' << m.density << ' ' << m.friction_angle
      << '\n';
  write_matrix(out, "hsize", s.cell.hsize);
  write_matrix(out, "trsf", s.cell.trsf);
  write_matrix(out, "vel_grad", s.cell.vel_grad);
  write_matrix(out, "prev_vel_grad", s.cell.prev_vel_grad);
  const auto& sp = s.spheres;
  out << "spheres " << sp.size() << '\n';
  auto vec = [&](const Vec3& v) { out << ' ' << v[0] << ' ' << v[1] << ' ' << v[2]; };
  auto quat = [&](const Quat& q) {
    out << ' ' << q.w() << ' ' << q.x() << ' ' << q.y() << ' ' << q.z();
  };
  for (std::size_t i = 0; i < sp.size(); ++i) {
    out << sp.radius[i] << ' ' << sp.mass[i] << ' ' << sp.inertia[i];
    vec(sp.pos[i]);
    vec(sp.vel[i]);
    vec(sp.ang_vel[i]);
    quat(sp.ori[i]);
    quat(sp.ref_ori[i]);
    out << '\n';
  }
  const auto& c = s.contacts;
  out << "contacts " << c.size() << '\n';
  for (std::size_t k = 0; k < c.size(); ++k) {
    out << c.id1[k] << ' ' << c.id2[k] << ' ' << c.cell[k][0] << ' ' << c.cell[k][1] << ' '
        << c.cell[k][2] << ' ' << contact_stiffness(s, k).kn << ' ' << contact_stiffness(s, k).ks
        << ' ' << std::tan(s.material.friction_angle);
    vec(c.normal[k]);
    vec(c.shear_force[k]);
    vec(normal_force(s, k));
    out << ' ' << c.penetration[k] << '\n';
  }
  if (!out) throw std::runtime_error("error while writing native packing " + file.string());
}

RveState build_cloud(const CloudParams& p) {
  RveState s;
  s.material = p.material;
  std::mt19937_64 rng(p.seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::vector<double> radii(static_cast<std::size_t>(p.n_spheres));
  double vol = 0;
  for (auto& r : radii) {
    r = p.r_min + (p.r_max - p.r_min) * uni(rng);
    vol += 4.0 / 3.0 * M_PI * r * r * r;
  }
  const double edge = std::cbrt(vol / (1.0 - p.porosity));
  s.cell.hsize = edge * Eigen::Matrix3d::Identity();
  for (double r : radii) {
    bool placed = false;
    for (int attempt = 0; attempt < 10000 && !placed; ++attempt) {
      const Vec3 x(edge * uni(rng), edge * uni(rng), edge * uni(rng));
      placed = true;
      for (std::size_t j = 0; j < s.spheres.size() && placed; ++j) {
        Vec3 d = x - s.spheres.pos[j];
        for (int a = 0; a < 3; ++a) d[a] -= edge * std::round(d[a] / edge);
        placed = d.norm() > r + s.spheres.radius[j];
      }
      if (placed) {
        const double mass = p.material.density * 4.0 / 3.0 * M_PI * r * r * r;
        s.spheres.push_back(r, mass, 0.4 * mass * r * r, x);
      }
    }
    if (!placed) {
      throw std::runtime_error("cannot place " + std::to_string(p.n_spheres) +
                               " spheres at porosity " + std::to_string(p.porosity));
    }
  }
  // YADE: O.dt = 0.5 * PWaveTimeStep(), PWaveTimeStep = min r / sqrt(E / rho).
  double r_min = radii.empty() ? 0 : radii[0];
  for (double r : radii) r_min = std::min(r_min, r);
  s.dt = 0.5 * r_min / std::sqrt(p.material.young / p.material.density);
  return s;
}

}  // namespace mpmdem::dem::native
