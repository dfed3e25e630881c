// Lazy RVE evaluation: checkpoint state (see lazy_evaluation.hpp).
#include "constitutive/lazy_evaluation.hpp"

#include <stdexcept>
#include <string>

namespace mpmdem::mpm {

std::vector<double> LazyEvaluation::save() const {
  std::vector<double> s{static_cast<double>(pending_.size()), static_cast<double>(evaluations_),
                        static_cast<double>(skipped_)};
  for (std::size_t p = 0; p < pending_.size(); ++p) {
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) s.push_back(pending_[p](i, j));
    }
    s.push_back(pending_dt_[p]);
  }
  return s;
}

void LazyEvaluation::load(const std::vector<double>& s) {
  if (s.size() < 3 || s.size() != 3 + 10 * static_cast<std::size_t>(s[0])) {
    throw std::runtime_error("checkpoint: the lazy-evaluation state holds " +
                             std::to_string(s.size()) + " values, not 3 + 10 per point");
  }
  const auto n = static_cast<std::size_t>(s[0]);
  evaluations_ = static_cast<std::int64_t>(s[1]);
  skipped_ = static_cast<std::int64_t>(s[2]);
  pending_.assign(n, Mat3::Identity());
  pending_dt_.assign(n, 0.0);
  for (std::size_t p = 0; p < n; ++p) {
    const double* v = &s[3 + 10 * p];
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) pending_[p](i, j) = v[3 * i + j];
    }
    pending_dt_[p] = v[9];
  }
}

}  // namespace mpmdem::mpm
