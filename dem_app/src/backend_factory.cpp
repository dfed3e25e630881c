// Creating a backend by name: see backend_factory.hpp.
#include "backend_factory.hpp"

#include <stdexcept>

#include "backends/batch/cuda_backend.hpp"
#include "backends/elastic_backend.hpp"
#include "backends/native/native_backend.hpp"
#ifdef MPMDEM_HAVE_YADE
#include "backends/yade_backend.hpp"
#endif

namespace mpmdem::dem {

std::vector<std::string> available_backends() {
#ifdef MPMDEM_HAVE_YADE
  return {"elastic", "native", "cuda", "yade"};
#else
  return {"elastic", "native", "cuda"};
#endif
}

namespace {
std::string available_text() {
  std::string names;
  for (const auto& n : available_backends()) names += (names.empty() ? "" : ", ") + n;
  return names;
}
}  // namespace

void check_backend_available(const config::Config& cfg) {
  const std::string name = cfg.string("coupling.backend");
  for (const auto& n : available_backends()) {
    if (n == name) return;
  }
  cfg.fail("coupling.backend",
           name + " is not built into this dem_app (available: " + available_text() +
               "); configure with -DMPMDEM_WITH_YADE=ON, or choose one of them");
}

std::unique_ptr<RveBackend> make_backend(const std::string& name, const config::Config& cfg,
                                         const BackendContext& ctx) {
  (void)ctx;
  if (name == "elastic") return make_elastic_backend(cfg);
  if (name == "native") return make_native_backend(cfg);
  if (name == "cuda") return make_cuda_backend(cfg);
#ifdef MPMDEM_HAVE_YADE
  if (name == "yade") return make_yade_backend(cfg, ctx);
#endif
  const std::string names = available_text();
  if (name == "yade") {
    throw std::invalid_argument(
        "backend 'yade' is not built into this dem_app (configure with -DMPMDEM_WITH_YADE=ON); "
        "available: " +
        names);
  }
  throw std::invalid_argument("unknown backend '" + name + "'; available: " + names);
}

}  // namespace mpmdem::dem
