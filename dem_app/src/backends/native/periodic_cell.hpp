// The periodic cell of one native RVE: YADE's Cell (core/Cell.cpp) with the state the
// NewtonIntegrator keeps about it. Columns of `hsize` are the lattice vectors; `trsf` is the
// transformation integrated since the packing was made; velocity gradients follow YADE's
// sequence exactly (docs/dem_backend.md, "native backend"):
//   * set_vel_grad(L) stores L as the next one (YADE's Cell.velGrad setter -> nextVelGrad);
//   * integrate_and_update(dt), first thing in a DEM step, applies the *active* vel_grad:
//     trsf += dt L trsf, hsize += dt L hsize, and keeps L * hsize_before for the velocity
//     of periodic images (Cell::intrShiftVel);
//   * activate_next() (NewtonIntegrator, after the contacts) makes the stored one active.
// So a gradient set before step k first moves the cell in step k + 1 (the velGrad lag).
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>

namespace mpmdem::dem::native {

struct PeriodicCell {
  Eigen::Matrix3d hsize = Eigen::Matrix3d::Identity();  // lattice vectors as columns [m]
  Eigen::Matrix3d trsf = Eigen::Matrix3d::Identity();   // integrated transformation [-]
  Eigen::Matrix3d vel_grad = Eigen::Matrix3d::Zero();   // active velocity gradient [1/s]
  Eigen::Matrix3d next_vel_grad = Eigen::Matrix3d::Zero();
  bool vel_grad_changed = false;
  Eigen::Matrix3d prev_vel_grad = Eigen::Matrix3d::Zero();       // NewtonIntegrator::prevVelGrad
  Eigen::Matrix3d vgrad_times_prev_h = Eigen::Matrix3d::Zero();  // velGrad * hSize(before)

  void set_vel_grad(const Eigen::Matrix3d& l) {
    next_vel_grad = l;
    vel_grad_changed = true;
  }
  // YADE Cell::integrateAndUpdate.
  void integrate_and_update(double dt) {
    const Eigen::Matrix3d inc = dt * vel_grad;
    trsf += inc * trsf;
    vgrad_times_prev_h = vel_grad * hsize;
    hsize += inc * hsize;
  }
  // The head of NewtonIntegrator::action: the requested gradient becomes the active one.
  void activate_next() {
    if (vel_grad_changed || next_vel_grad != Eigen::Matrix3d::Zero()) {
      vel_grad = next_vel_grad;
      vel_grad_changed = false;
      next_vel_grad.setZero();
    }
  }
  // The gradient that the next integrate_and_update() will apply.
  const Eigen::Matrix3d& pending_vel_grad() const {
    return vel_grad_changed ? next_vel_grad : vel_grad;
  }
  double volume() const { return hsize.determinant(); }
  // Offset and extra velocity of the periodic image c (any integer type).
  template <typename Int>
  Eigen::Vector3d shift(const Eigen::Matrix<Int, 3, 1>& c) const {
    return hsize * c.template cast<double>();
  }
  template <typename Int>
  Eigen::Vector3d shift_vel(const Eigen::Matrix<Int, 3, 1>& c) const {
    return vgrad_times_prev_h * c.template cast<double>();
  }
  // Distance between the two faces spanned by the other lattice vectors, for each vector.
  Eigen::Vector3d heights() const;
  // YADE Cell::flipCell: an equivalent, less skewed lattice (hsize += hsize * flip), trsf
  // unchanged. Returns the integer matrix M with hsize_new = hsize_old * M (identity when
  // nothing changed); an image offset c becomes M^-1 c.
  Eigen::Matrix3i flip();
};

}  // namespace mpmdem::dem::native
