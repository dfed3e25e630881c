#include "constitutive/model_registry.hpp"

#include <map>
#include <stdexcept>

namespace mpmdem::mpm {

namespace {

// Constructed on first use, so that registrations from any file's static initialisation
// find it ready.
std::map<std::string, LocalModel>& registry() {
  static std::map<std::string, LocalModel> models;
  return models;
}

}  // namespace

bool register_local_model(LocalModel model) {
  if (model.name.empty() || model.name == kRemoteModel) {
    throw std::logic_error("register_local_model: the name '" + model.name +
                           "' cannot name a local model");
  }
  if (!model.add_keys || !model.load || !model.make) {
    throw std::logic_error("register_local_model: " + model.name + " lacks add_keys, load or make");
  }
  const std::string name = model.name;
  if (!registry().emplace(name, std::move(model)).second) {
    throw std::logic_error("register_local_model: " + name + " is registered twice");
  }
  return true;
}

std::vector<const LocalModel*> local_models() {
  std::vector<const LocalModel*> v;
  for (const auto& [name, model] : registry()) v.push_back(&model);
  return v;
}

const LocalModel* find_local_model(const std::string& name) {
  const auto it = registry().find(name);
  return it == registry().end() ? nullptr : &it->second;
}

const LocalModel& local_model(const std::string& name) {
  if (const LocalModel* m = find_local_model(name)) return *m;
  throw std::invalid_argument("unknown local constitutive model '" + name + "'; registered: " +
                              local_model_names() + " (and " + kRemoteModel + ", the RVE model)");
}

std::string local_model_names() {
  std::string s;
  for (const auto& [name, model] : registry()) s += (s.empty() ? "" : ", ") + name;
  return s;
}

const char* remote_model_summary() {
  return "the RVE model: each point's stress from a DEM RVE on dem_app (needs coupling:)";
}

void add_elastic_moduli_keys(config::Schema& s, const std::string& section) {
  using config::key;
  using config::Type;
  s.add(key(section + ".youngs_modulus", Type::kDouble, "Pa", "Young's modulus E").req().gt(0));
  s.add(key(section + ".poisson_ratio", Type::kDouble, "-", "Poisson's ratio nu")
            .req()
            .ge(0)
            .lt(0.5));
}

void load_elastic_moduli(const config::Config& cfg, const std::string& section,
                         ConstitutiveParams& params) {
  params.youngs_modulus = cfg.number(section + ".youngs_modulus");
  params.poisson_ratio = cfg.number(section + ".poisson_ratio");
}

void add_constitutive_model_keys(config::Schema& s) {
  using config::key;
  using config::Type;
  std::vector<std::string> choices;
  for (const auto& [name, model] : registry()) choices.push_back(name);
  choices.emplace_back(kRemoteModel);
  s.add(key("constitutive.model", Type::kEnum, "",
            "a local model, computed in-process (mpm_app --list-models), or remote (RVEs on "
            "dem_app; needs coupling:)")
            .def("linear_elastic")
            .one_of(choices));
  for (const auto& [name, model] : registry()) {
    const std::string section = "constitutive." + name;
    s.add(key(section, Type::kMap, "", model.summary + " (model " + name + ")"));
    model.add_keys(s, section);
  }
}

}  // namespace mpmdem::mpm
