#include "yade_schema.hpp"

namespace mpmdem {

// PLACEHOLDER (issue 3 fills this in).
void add_yade_keys(config::Schema& schema) { (void)schema; }

}  // namespace mpmdem
