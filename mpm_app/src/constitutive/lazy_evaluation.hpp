// Lazy RVE evaluation (issue 6: leave out what a scene does not need).
//
// Per material point, the increments dF since its RVE last ran are accumulated,
// dF_acc = dF_n ... dF_k (newest on the left), with the time they span. While
// max_ij |dF_acc - I|_ij <= tolerance the RVE is not run (its stress is held, the request
// carries RequestFlags::kFlagSkip); when the gap exceeds the tolerance the RVE runs once
// with dF_acc over the accumulated time, and the accumulation restarts. No increment is
// lost: the product of everything sent and everything pending is the product of all
// increments. A rigid rotation accumulates in dF_acc too, so a rotating point is
// re-evaluated after a rotation of about the tolerance (radians): the held stress is not
// rotated in between (an error of the order of the tolerance). Tolerance 0: always run.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace mpmdem::mpm {

class LazyEvaluation {
 public:
  using Mat3 = Eigen::Matrix3d;
  explicit LazyEvaluation(double tolerance) : tol_(tolerance) {}

  bool enabled() const { return tol_ > 0.0; }
  // Point p's increment of this step. true: run the RVE with (dF_run, dt_run); false: skip.
  bool next(std::size_t p, const Mat3& dF, double dt, Mat3& dF_run, double& dt_run) {
    prepare(p + 1);
    const bool run = decide(p, dF, dt, dF_run, dt_run);
    count(run ? 1 : 0, run ? 0 : 1);
    return run;
  }

  // The same decision for many points at once, from several threads: prepare(n) once, then
  // decide(p, ...) for each point p < n (points are independent: decide touches only point
  // p's pending increment), then count() the runs and skips. Same state and counts as next().
  void prepare(std::size_t n) {
    if (enabled() && pending_.size() < n) {
      pending_.resize(n, Mat3::Identity());
      pending_dt_.resize(n, 0.0);
    }
  }
  bool decide(std::size_t p, const Mat3& dF, double dt, Mat3& dF_run, double& dt_run) {
    if (!enabled()) {
      dF_run = dF;
      dt_run = dt;
      return true;
    }
    const Mat3 acc = dF * pending_[p];
    if ((acc - Mat3::Identity()).cwiseAbs().maxCoeff() <= tol_) {
      pending_[p] = acc;
      pending_dt_[p] += dt;
      return false;
    }
    dF_run = acc;
    dt_run = pending_dt_[p] + dt;
    pending_[p] = Mat3::Identity();
    pending_dt_[p] = 0.0;
    return true;
  }
  void count(std::int64_t runs, std::int64_t skips) {
    evaluations_ += runs;
    skipped_ += skips;
  }

  std::int64_t evaluations() const { return evaluations_; }
  std::int64_t skipped() const { return skipped_; }
  const std::vector<Mat3>& pending() const { return pending_; }

  // For checkpoints: [n, evaluations, skipped, then per point dF_acc (row-major 9), dt_acc].
  std::vector<double> save() const;
  // Throws std::runtime_error if `s` is not a saved state.
  void load(const std::vector<double>& s);

 private:
  double tol_;
  std::vector<Mat3> pending_;
  std::vector<double> pending_dt_;
  std::int64_t evaluations_ = 0, skipped_ = 0;
};

}  // namespace mpmdem::mpm
