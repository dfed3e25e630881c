#include "run/observer.hpp"

#include <ostream>

namespace mpmdem::mpm {

std::ostream& RunContext::event() const {
  return out << "[step " << solver.step_count() << ", t=" << solver.time() << " s] ";
}

}  // namespace mpmdem::mpm
