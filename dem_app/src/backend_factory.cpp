// Creating a backend by name: see backend_factory.hpp.
#include "backend_factory.hpp"

#include <stdexcept>

#include "backend_catalog.hpp"

#include "backends/batch/cuda_backend.hpp"
#include "backends/elastic_backend.hpp"
#include "backends/native/native_backend.hpp"
#ifdef MPMDEM_HAVE_YADE
#include "backends/yade_backend.hpp"
#endif

namespace mpmdem::dem {

namespace {

using Maker = std::unique_ptr<RveBackend> (*)(const config::Config&, const BackendContext&);

std::unique_ptr<RveBackend> make_elastic(const config::Config& cfg, const BackendContext&) {
  return make_elastic_backend(cfg);
}
std::unique_ptr<RveBackend> make_native(const config::Config& cfg, const BackendContext&) {
  return make_native_backend(cfg);
}
std::unique_ptr<RveBackend> make_cuda(const config::Config& cfg, const BackendContext&) {
  return make_cuda_backend(cfg);
}
#ifdef MPMDEM_HAVE_YADE
std::unique_ptr<RveBackend> make_yade(const config::Config& cfg, const BackendContext& ctx) {
  return make_yade_backend(cfg, ctx);
}
#endif

// The maker of each backend of the catalog (backend_catalog.hpp) built into this dem_app.
Maker maker(const std::string& name) {
  if (name == "elastic") return make_elastic;
  if (name == "native") return make_native;
  if (name == "cuda") return make_cuda;
#ifdef MPMDEM_HAVE_YADE
  if (name == "yade") return make_yade;
#endif
  return nullptr;
}

std::string available_text() {
  std::string names;
  for (const auto& n : available_backends()) names += (names.empty() ? "" : ", ") + n;
  return names;
}

}  // namespace

std::vector<std::string> available_backends() {
  std::vector<std::string> names;
  for (const BackendSpec& b : backend_catalog()) {
    if (maker(b.name)) names.push_back(b.name);
  }
  return names;
}

void check_backend_available(const config::Config& cfg) {
  const std::string name = cfg.string("coupling.backend");
  if (maker(name)) return;
  cfg.fail("coupling.backend",
           name + " is not built into this dem_app (available: " + available_text() +
               "); configure with -DMPMDEM_WITH_YADE=ON, or choose one of them");
}

std::unique_ptr<RveBackend> make_backend(const std::string& name, const config::Config& cfg,
                                         const BackendContext& ctx) {
  if (const Maker make = maker(name)) return make(cfg, ctx);
  const std::string names = available_text();
  if (find_backend(name)) {
    throw std::invalid_argument("backend '" + name +
                                "' is not built into this dem_app (configure with "
                                "-DMPMDEM_WITH_YADE=ON); available: " +
                                names);
  }
  throw std::invalid_argument("unknown backend '" + name + "'; available: " + names);
}

}  // namespace mpmdem::dem
