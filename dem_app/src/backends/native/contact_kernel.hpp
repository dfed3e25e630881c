// The contact update of one DEM step over a range of contacts, one loop without branches
// over the structure-of-arrays contact state (rve_state.hpp's Split3 fields):
// Ig2_Sphere_Sphere_ScGeom (avoidGranularRatcheting = true, its default) with
// ScGeom::precompute/rotate and the RVE's contact law (backends/contact_laws/: frict's
// Law2_ScGeom_FrictPhys_CundallStrack, periodic branch, or frict_visco),
// formula for formula (docs/dem_backend.md, "Same physics, to rounding"), the sphere fields
// gathered by index. It vectorises across contacts (SIMD clones, simd_clones.hpp); forces
// are not scattered here but written per contact (ContactOut), and the caller adds them to
// the spheres in contact order. A contact that opened (penetration < 0) gets its normal and
// penetration written; its other outputs are to be ignored (YADE erases it).
#pragma once

#include <cstddef>
#include <cstdint>

#include "backends/contact_laws/law_math.hpp"
#include "backends/native/rve_state.hpp"

namespace mpmdem::dem::native {

// Contacts per call of update_contacts (the outputs fit in L1).
constexpr std::size_t kContactChunk = 128;

// Per contact of a chunk: force on sphere 1 (sphere 2 gets its opposite), torques on both.
struct ContactOut {
  double f[3][kContactChunk], t1[3][kContactChunk], t2[3][kContactChunk];
};

// The indices, radii and image offsets of a chunk's contacts, widened to 64 bits, so that
// the vectorised loops over contacts have no narrower type (GCC would otherwise size their
// vectors by the 16-bit offsets, 32 contacts per iteration, and spill registers).
struct StagedContacts {
  std::int64_t a[kContactChunk], b[kContactChunk];  // sphere indices
  double c[3][kContactChunk];
};
// Contacts [k0, k0 + m), m <= kContactChunk.
void stage_contacts(const RveState& s, std::size_t k0, std::size_t m, StagedContacts& st);

// What every contact of a step shares: the law's parameters (young, ks_kn, tan2, beta_n) and
// the step's.
struct LawConstants : laws::LawParams {
  double dt, half_dt;
  double h[3][3];   // cell hsize (image shift H c)
  double lh[3][3];  // velGrad * hsize before the step (image velocity)
};

LawConstants law_constants(const RveState& s);

// The law is the RVE's (s.law, contact_law.hpp); frict_visco also writes normal_viscous.
// Updates contacts [k0, k0 + m), m <= kContactChunk: normal, penetration and shear force in
// place; out[j] for contact k0 + j. A new contact is one with zero normal and shear force
// (then the rotation terms vanish, as ScGeom's isNew branch). rec: the spheres' records of
// pack_sphere_records (nullptr: the fields are gathered from the arrays); the same bits.
void update_contacts(RveState& s, const LawConstants& k, std::size_t k0, std::size_t m,
                     ContactOut& out, const double* rec = nullptr);

// The spheres' position, radius, velocity and angular velocity packed into one record per
// sphere, for the AVX-512 contact update (contact_kernel_avx512.cpp); valid until a sphere
// moves (per thread: the next call overwrites it). nullptr without AVX-512 (the CPU's or the
// build's, simd_clones.hpp).
const double* pack_sphere_records(const RveState& s);
// The Love-Weber and stiffness terms of all contacts added to lanes (measures.cpp's
// contributions and add_to_lanes, the same bits) through freshly packed records; false
// (lanes untouched) without AVX-512.
bool stress_terms_records(const RveState& s, const double (&h)[3][3], double (&lanes)[15][8]);
// update_contacts through these records (AVX-512 only).
void update_contacts_records(RveState& s, const LawConstants& k, std::size_t k0, std::size_t m,
                             const double* rec, ContactOut& out);

}  // namespace mpmdem::dem::native
