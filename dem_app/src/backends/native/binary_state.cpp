// Binary state of a native RVE: see binary_state.hpp.
#include "backends/native/binary_state.hpp"

#include <cstring>
#include <fstream>
#include <stdexcept>
#include <type_traits>

namespace mpmdem::dem::native {

namespace {

// NAT5: sphere and contact vector fields xyz split (one array per component). NAT4
// (interleaved) is still read. NAT6: NAT5 with the contact law after the contacts'
// penetrations (kind, e_n, beta_n) and the contacts' normal_viscous: written for the
// frict_visco law only, so that the states (and checkpoints, consolidation keys) of frict
// RVEs keep their NAT5 bytes.
constexpr char kMagic[8] = {'M', 'P', 'M', 'D', 'N', 'A', 'T', '5'};
constexpr char kMagicNat6[8] = {'M', 'P', 'M', 'D', 'N', 'A', 'T', '6'};
constexpr char kMagicNat4[8] = {'M', 'P', 'M', 'D', 'N', 'A', 'T', '4'};
constexpr char kCheckpointMagic[8] = {'M', 'P', 'M', 'D', 'N', 'C', 'K', '1'};

class Out {
 public:
  template <typename T>
  void put(const T& v) {
    static_assert(std::is_standard_layout_v<T>);
    buf_.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  template <typename T>
  void put_vector(const std::vector<T>& v) {
    static_assert(std::is_standard_layout_v<T>);
    put<std::uint64_t>(v.size());
    buf_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  template <typename T, typename V>
  void put_split(const Split3<T, V>& v) {
    for (const auto& f : v.c) put_vector(f);
  }
  std::string take() { return std::move(buf_); }

 private:
  std::string buf_;
};

class In {
 public:
  explicit In(const std::string& b) : b_(b) {}
  template <typename T>
  void get(T& v) {
    need(sizeof v);
    std::memcpy(static_cast<void*>(&v), b_.data() + at_, sizeof v);
    at_ += sizeof v;
  }
  template <typename T>
  void get_vector(std::vector<T>& v) {
    std::uint64_t n = 0;
    get(n);
    if (n > (b_.size() - at_) / sizeof(T)) fail();
    v.resize(n);
    if (n) std::memcpy(static_cast<void*>(v.data()), b_.data() + at_, n * sizeof(T));
    at_ += n * sizeof(T);
  }
  // NAT5: three arrays; NAT4 (interleaved): one array of vectors.
  template <typename T, typename V>
  void get_split(Split3<T, V>& v, bool interleaved) {
    if (!interleaved) {
      for (auto& f : v.c) get_vector(f);
      if (v.c[1].size() != v.c[0].size() || v.c[2].size() != v.c[0].size()) fail();
      return;
    }
    std::vector<V> w;
    get_vector(w);
    v.resize(w.size());
    for (std::size_t k = 0; k < w.size(); ++k) v.set(k, w[k]);
  }
  bool done() const { return at_ == b_.size(); }
  [[noreturn]] static void fail() {
    throw std::runtime_error("native backend: truncated or invalid RVE state");
  }

 private:
  void need(std::size_t n) const {
    if (b_.size() - at_ < n) fail();
  }
  const std::string& b_;
  std::size_t at_ = 0;
};

template <typename Stream, typename Cell>
void cell_fields(Stream& s, Cell& c) {
  if constexpr (std::is_same_v<Stream, Out>) {
    s.put(c.hsize), s.put(c.trsf), s.put(c.vel_grad), s.put(c.next_vel_grad);
    s.put(c.vel_grad_changed), s.put(c.prev_vel_grad), s.put(c.vgrad_times_prev_h);
  } else {
    s.get(c.hsize), s.get(c.trsf), s.get(c.vel_grad), s.get(c.next_vel_grad);
    s.get(c.vel_grad_changed), s.get(c.prev_vel_grad), s.get(c.vgrad_times_prev_h);
  }
}

}  // namespace

std::string encode(const RveRecord& r) {
  Out o;
  const RveState& s = r.state;
  const bool nat6 = s.law.viscous();
  for (char c : nat6 ? kMagicNat6 : kMagic) o.put(c);
  cell_fields(o, s.cell);
  o.put(s.material);
  o.put(s.dt);
  o.put(s.iter);
  const Spheres& sp = s.spheres;
  o.put_vector(sp.radius), o.put_vector(sp.mass), o.put_vector(sp.inertia);
  o.put_split(sp.pos), o.put_split(sp.vel), o.put_split(sp.ang_vel);
  o.put_vector(sp.ori), o.put_vector(sp.ref_ori);
  const Contacts& c = s.contacts;
  o.put_vector(c.id1), o.put_vector(c.id2);
  o.put_split(c.cell), o.put_split(c.normal), o.put_split(c.shear_force);
  o.put_vector(c.penetration);
  if (nat6) {
    o.put(s.law.kind), o.put(s.law.restitution_n), o.put(s.law.beta_n);
    o.put_vector(c.normal_viscous);
  }
  o.put(r.point);
  o.put(r.p0);
  o.put(r.tilings);
  o.put(r.unbalanced);
  o.put_vector(std::vector<char>(r.packing.begin(), r.packing.end()));
  return o.take();
}

RveRecord decode(const std::string& blob) {
  In in(blob);
  char magic[8];
  for (char& c : magic) in.get(c);
  const bool nat4 = std::memcmp(magic, kMagicNat4, sizeof magic) == 0;
  const bool nat6 = std::memcmp(magic, kMagicNat6, sizeof magic) == 0;
  if (!nat4 && !nat6 && std::memcmp(magic, kMagic, sizeof magic) != 0) In::fail();
  RveRecord r;
  RveState& s = r.state;
  cell_fields(in, s.cell);
  in.get(s.material);
  in.get(s.dt);
  in.get(s.iter);
  Spheres& sp = s.spheres;
  in.get_vector(sp.radius), in.get_vector(sp.mass), in.get_vector(sp.inertia);
  in.get_split(sp.pos, nat4), in.get_split(sp.vel, nat4), in.get_split(sp.ang_vel, nat4);
  in.get_vector(sp.ori), in.get_vector(sp.ref_ori);
  Contacts& c = s.contacts;
  in.get_vector(c.id1), in.get_vector(c.id2);
  in.get_split(c.cell, nat4), in.get_split(c.normal, nat4), in.get_split(c.shear_force, nat4);
  in.get_vector(c.penetration);
  if (nat6) {
    ContactLaw law;
    in.get(law.kind), in.get(law.restitution_n), in.get(law.beta_n);
    if (!law.viscous()) In::fail();
    set_contact_law(s, law);
    in.get_vector(c.normal_viscous);
  }
  in.get(r.point);
  in.get(r.p0);
  in.get(r.tilings);
  in.get(r.unbalanced);
  std::vector<char> name;
  in.get_vector(name);
  r.packing.assign(name.begin(), name.end());
  const std::size_t n = sp.radius.size(), m = c.id1.size();
  const bool consistent = sp.mass.size() == n && sp.inertia.size() == n && sp.pos.size() == n &&
                          sp.vel.size() == n && sp.ang_vel.size() == n && sp.ori.size() == n &&
                          sp.ref_ori.size() == n && c.id2.size() == m && c.cell.size() == m &&
                          c.normal.size() == m && c.shear_force.size() == m &&
                          c.penetration.size() == m && (!c.viscous || c.normal_viscous.size() == m);
  if (!consistent || !in.done()) In::fail();
  for (std::size_t k = 0; k < m; ++k) {
    if (c.id1[k] >= n || c.id2[k] >= n) In::fail();
  }
  return r;
}

void write_checkpoint_header(std::ostream& out, std::uint64_t count) {
  out.write(kCheckpointMagic, sizeof kCheckpointMagic);
  out.write(reinterpret_cast<const char*>(&count), sizeof count);
}

void write_checkpoint_record(std::ostream& out, std::uint64_t gid, const std::string& blob) {
  const std::uint64_t head[2] = {gid, blob.size()};
  out.write(reinterpret_cast<const char*>(head), sizeof head);
  out.write(blob.data(), static_cast<std::streamsize>(blob.size()));
}

void read_checkpoint(const std::filesystem::path& file,
                     const std::function<void(std::uint64_t, const std::string&)>& fn) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read native checkpoint " + file.string());
  char magic[sizeof kCheckpointMagic] = {};
  std::uint64_t count = 0;
  in.read(magic, sizeof magic);
  in.read(reinterpret_cast<char*>(&count), sizeof count);
  if (!in || std::memcmp(magic, kCheckpointMagic, sizeof magic) != 0) {
    throw std::runtime_error(file.string() + " is not a native-backend checkpoint");
  }
  for (std::uint64_t i = 0; i < count; ++i) {
    std::uint64_t head[2] = {0, 0};
    in.read(reinterpret_cast<char*>(head), sizeof head);
    if (!in || head[1] > (std::uint64_t{1} << 36)) {  // no RVE state is 64 GB
      throw std::runtime_error(file.string() + " is truncated or corrupt");
    }
    std::string blob(head[1], '\0');
    in.read(blob.data(), static_cast<std::streamsize>(blob.size()));
    if (!in) throw std::runtime_error(file.string() + " is truncated");
    fn(head[0], blob);
  }
}

}  // namespace mpmdem::dem::native
