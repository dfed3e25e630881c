// energies.csv: the energy time series of a run, one row per logged step, first row at t=0.
// Columns: time [s], step, dt [s] (the step that led to this row; 0 on the first row),
// E_p = -sum m g.x (sum m g z for gravity along -z), E_k = sum 1/2 m v^2, E_d = E_p0 - E_p - E_k
// (energy dissipated, plus elastic energy stored), E_strain (elastic strain energy where the model
// defines it, else 0), E_p0 (potential energy at t=0), then the energy budget
// (energy_budget.hpp): E_k0 (kinetic energy at t=0), W_int (stress work), W_damp (local
// damping), W_bc (walls and velocity constraints) and
// E_err = E_p0 + E_k0 - E_p - E_k - W_int - W_damp - W_bc, W_transfer (the part of E_err
// the particle-grid transfers remove) and W_transfer_walls (the part of W_transfer at the
// walls) — all in J.
// Rows are appended and flushed as the run goes, so a long run can be watched.
#pragma once

#include <cstdint>
#include <fstream>
#include <string>

namespace mpmdem::mpm {

struct EnergyRow {
  double time = 0.0;
  std::int64_t step = 0;
  double dt = 0.0;
  double E_p = 0.0;
  double E_k = 0.0;
  double E_strain = 0.0;
  double E_p0 = 0.0;
  double E_k0 = 0.0;
  double W_int = 0.0;
  double W_damp = 0.0;
  double W_bc = 0.0;
  double W_transfer = 0.0;
  double W_transfer_walls = 0.0;
};

class EnergyLog {
 public:
  static constexpr const char* kHeader =
      "time,step,dt,E_p,E_k,E_d,E_strain,E_p0,E_k0,W_int,W_damp,W_bc,E_err,W_transfer,"
      "W_transfer_walls";

  // A new log (last_step < 0), or the log of a resumed run: keeps the header and the rows up
  // to `last_step` (rows the interrupted run wrote after its checkpoint are dropped), then
  // appends.
  explicit EnergyLog(const std::string& path, std::int64_t last_step = -1);
  // Appends one row. Throws std::runtime_error if a value is not finite (nothing written).
  void append(const EnergyRow& row);
  std::size_t rows() const { return rows_; }

 private:
  std::string path_;
  std::size_t rows_ = 0;  // before out_: opening a resumed log sets it
  std::ofstream out_;
};

}  // namespace mpmdem::mpm
