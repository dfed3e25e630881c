// The batch of RVEs one dem_app rank steps at once (coupling.backend: cuda): every RVE of the
// rank in one structure of arrays, spheres, contacts and Verlet pairs of all RVEs each in one
// array, RVE r owning [sph0[r], sph0[r+1]) of the spheres and fixed-capacity slices of the
// contacts and pairs. BatchView is the set of raw pointers the physics (rve_step.hpp) reads:
// host vectors (BatchState, the host batch path) or their device copies (batch_device.cu).
#pragma once

#include <cstdint>

namespace mpmdem::dem::batch {

// Per-RVE cell block (doubles): row-major 3x3 matrices of native::PeriodicCell and the list.
enum CellSlot : int {
  kHsize = 0,     // lattice vectors as columns
  kTrsf = 9,      // integrated transformation
  kVelGrad = 18,  // active velocity gradient
  kNextVelGrad = 27,
  kPrevVelGrad = 36,  // NewtonIntegrator::prevVelGrad
  kLh = 45,           // velGrad * hsize before the step (image velocity)
  kHrefInv = 54,      // the Verlet list's hsize at its build, inverted
  kFlipInv = 63,      // scratch: the inverse of the last flip's integer matrix
  kCellDoubles = 72
};
// Per-RVE flags (ints).
// kScratch: a word the group's first thread hands to the others (after a sync).
enum RveFlag : int {
  kVelGradChanged = 0,
  kListValid = 1,
  kScratch = 2,
  kScratch2 = 3,
  kRveFlags = 4
};
// protocol::RveStatus and OutputBits values (the layout has no protocol dependency).
enum : std::int32_t {
  kStatusOk = 0,
  kStatusNoContacts = 1,
  kStatusNonFinite = 2,
  kStatusExploding = 3
};
enum : std::uint32_t {
  kOutRotation = 1,
  kOutPorosity = 2,
  kOutCoordination = 4,
  kOutUnbalanced = 8
};

// Per-RVE input of one coupling step.
enum StepFlag : int {
  kStepActive = 1,    // the RVE is stepped (not served from the kFlagSkip cache)
  kStepTileCheck = 2  // the coupling step checks whether the cell must be tiled (every 10th)
};
struct StepIn {
  double dF[9];        // row-major
  std::int32_t ns;     // DEM substeps (0: query only)
  std::int32_t flags;  // StepFlag
};
// Errors of the batch (StepOut::error): the RVE outgrew a fixed capacity; its state is not
// usable (the backend stops with a message naming the key to raise).
enum BatchError : std::int32_t { kErrNone = 0, kErrContacts = 1, kErrPairs = 2 };
struct StepOut {
  double stress[9];  // symmetrised Love-Weber stress (row-major)
  double rotation[3];
  double porosity, coordination, unbalanced, stiffness, kinetic;
  std::int32_t status;    // protocol::RveStatus
  std::int32_t error;     // BatchError
  std::int32_t tile;      // the cell is thinner than the tiling height: the host tiles it
  std::int32_t rebuilds;  // Verlet rebuilds in this step
};

// What all RVEs of a step share.
struct BatchParams {
  double damping;
  double ke_threshold;
  double skin_factor;      // Verlet skin in smallest radii
  std::int32_t stiffness;  // compute the stiffness bound
  std::uint32_t outputs;   // protocol::OutputBits
};

struct BatchView {
  std::int32_t n_rve = 0;
  // per RVE
  const std::int64_t* sph0 = nullptr;   // n_rve + 1 sphere offsets
  const std::int64_t* con0 = nullptr;   // n_rve + 1 contact-slot offsets (capacity)
  const std::int64_t* pair0 = nullptr;  // n_rve + 1 pair-slot offsets (capacity)
  std::int32_t* n_con = nullptr;
  std::int32_t* n_pair = nullptr;
  double* cell = nullptr;         // kCellDoubles per RVE
  std::int32_t* flags = nullptr;  // kRveFlags per RVE
  const double* dt = nullptr;
  const double* young = nullptr;
  const double* ks_kn = nullptr;
  const double* tan2 = nullptr;  // tan(friction angle)^2, computed on the host (libm)
  const double* p0 = nullptr;
  double* skin = nullptr;  // the list's skin and largest cutoff, set at its build
  double* max_cut = nullptr;
  double* unbalanced = nullptr;  // unbalanced force after the last burst (when requested)
  std::int64_t* iter = nullptr;
  const StepIn* in = nullptr;
  StepOut* out = nullptr;
  // per sphere (index sph0[r] + i)
  const double* radius = nullptr;
  const double* mass = nullptr;
  const double* inertia = nullptr;
  const double* inv_mass = nullptr;
  const double* inv_inertia = nullptr;
  double* pos[3] = {};
  double* vel[3] = {};
  double* ang[3] = {};
  double* ori = nullptr;      // 4 per sphere, Eigen's order x y z w
  double* ref_ori = nullptr;  // idem
  double* force[3] = {};
  double* torque[3] = {};
  double* x_ref[3] = {};              // the list's reference positions
  std::int32_t* inc_start = nullptr;  // per RVE (n + 1 entries at sph0[r] + r): incidence rows
  std::int32_t* inc_fill = nullptr;   // per sphere: fill cursor
  // per contact slot (index con0[r] + k)
  std::uint32_t* id1 = nullptr;
  std::uint32_t* id2 = nullptr;
  std::int16_t* ccell[3] = {};
  double* normal[3] = {};
  double* shear[3] = {};
  double* pen = nullptr;
  double* of[3] = {};               // force on sphere 1 of the step
  double* ot1[3] = {};              // torque on sphere 1
  double* ot2[3] = {};              // torque on sphere 2
  std::int32_t* pair_of = nullptr;  // the contact's Verlet pair (-1: none)
  std::int32_t* inc = nullptr;      // 2 per contact slot: incidences 2 k + role
  // per pair slot (index pair0[r] + p): rows i < j, j ascending, images lexicographic
  std::uint32_t* pi = nullptr;
  std::uint32_t* pj = nullptr;
  std::int16_t* pc[3] = {};
  std::uint8_t* in_contact = nullptr;
};

}  // namespace mpmdem::dem::batch
