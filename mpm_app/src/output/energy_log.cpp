#include "output/energy_log.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "output/run_directory.hpp"

namespace mpmdem::mpm {

EnergyLog::EnergyLog(const std::string& path, std::int64_t last_step)
    : path_(path), out_(open_step_log(path, kHeader, last_step, 1, &rows_)) {}

void EnergyLog::append(const EnergyRow& r) {
  const double E_d = r.E_p0 - r.E_p - r.E_k;
  const double E_err = r.E_p0 + r.E_k0 - r.E_p - r.E_k - r.W_int - r.W_damp - r.W_bc;
  for (double value : {r.time, r.dt, r.E_p, r.E_k, E_d, r.E_strain, r.E_p0, r.E_k0, r.W_int,
                       r.W_damp, r.W_bc, E_err, r.W_transfer, r.W_transfer_walls}) {
    if (!std::isfinite(value)) {
      throw std::runtime_error("non-finite energy at step " + std::to_string(r.step) +
                               "; not written to " + path_);
    }
  }
  char line[640];
  std::snprintf(
      line, sizeof line,
      "%.10e,%lld,%.6e,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e\n",
      r.time, static_cast<long long>(r.step), r.dt, r.E_p, r.E_k, E_d, r.E_strain, r.E_p0, r.E_k0,
      r.W_int, r.W_damp, r.W_bc, E_err, r.W_transfer, r.W_transfer_walls);
  out_ << line;
  out_.flush();
  if (!out_) throw std::runtime_error("write to '" + path_ + "' failed (disk full?)");
  ++rows_;
}

}  // namespace mpmdem::mpm
