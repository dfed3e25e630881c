// The key of a consolidated native RVE state: see consolidation_key.hpp.
#include "backends/native/consolidation_key.hpp"

#include <cmath>
#include <cstdio>
#include <type_traits>

#include "backends/native/binary_state.hpp"
#include "backends/native/packing.hpp"
#include "mpmdem/config_hash.hpp"

namespace mpmdem::dem::native {

namespace {

template <typename T>
void put(std::string& b, const T& v) {
  static_assert(std::is_trivially_copyable_v<T>);
  b.append(reinterpret_cast<const char*>(&v), sizeof v);
}

std::string encode_state(const RveState& s) {
  RveRecord r;
  r.state = s;
  return encode(r);
}

}  // namespace

std::string ConsolidationKey::name() const {
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(fnv1a64(bytes)));
  return hex;
}

StateHash state_hash(const RveState& s) {
  const std::string blob = encode_state(s);
  return {fnv1a64(blob), blob.size()};
}

namespace {

// The bits of the fixed consolidation run of code_fingerprint with the given contact law.
std::uint64_t fingerprint_run(const ContactLaw& law) {
  {
    // 24 spheres of a loose cloud squeezed by 15 % (so that neighbours overlap), servoed for
    // 600 steps towards an anisotropic stress: contacts made and lost, sliding, damping and
    // the servo's rate law all act on the bits.
    CloudParams c;
    c.n_spheres = 24;
    c.porosity = 0.7;
    c.material.friction_angle = std::atan(0.5);
    c.seed = 36;
    RveState s = build_cloud(c);
    set_contact_law(s, law);
    s.cell.hsize *= 0.85;
    for (std::size_t i = 0; i < s.spheres.size(); ++i)
      s.spheres.pos.set(i, 0.85 * s.spheres.pos[i]);
    NeighbourList nl;
    ConsolidationParams p;
    p.max_steps = 600;
    p.stress_tol = 1e-12;
    p.keep_on_failure = true;
    consolidate(s, nl, Eigen::Vector3d(-2e5, -3e5, -1e5), p);
    finish_preparation(s, nl, p.damping);
    return state_hash(s).hash;
  }
}

}  // namespace

std::uint64_t code_fingerprint() {
  static const std::uint64_t fingerprint = fingerprint_run(ContactLaw{});
  return fingerprint;
}

std::uint64_t visco_fingerprint() {
  static const std::uint64_t fingerprint = fingerprint_run(frict_visco_law(0.5));
  return fingerprint;
}

ConsolidationKey consolidation_key(const StateHash& packing, const double (&stress)[9],
                                   const ConsolidationParams& p, double verlet_skin,
                                   const ContactLaw& law) {
  ConsolidationKey k;
  std::string& b = k.bytes;
  b = "mpmdem-consolidation-key";
  put(b, kKeyVersion);
  // the binary state's format: the magic at the head of every encoded state
  b += encode_state(RveState{}).substr(0, 8);
  put(b, code_fingerprint());
  put(b, packing.hash);
  put(b, packing.size);
  for (double v : stress) put(b, v);
  put(b, p.stress_tol);
  put(b, p.unbalanced_tol);
  put(b, static_cast<std::int64_t>(p.max_steps));
  put(b, p.max_strain_rate);
  put(b, p.damping);
  put(b, verlet_skin);
  // The frict_visco law (also in the packing's hash: its NAT6 state) and the bits of its own
  // fixed run; nothing for frict, whose keys are those of before the law was a choice.
  if (law.viscous()) {
    b += "frict_visco";
    put(b, law.beta_n);
    put(b, visco_fingerprint());
  }
  return k;
}

}  // namespace mpmdem::dem::native
