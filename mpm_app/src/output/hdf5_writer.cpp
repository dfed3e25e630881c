#include "output/hdf5_writer.hpp"

#include <stdexcept>
#include <vector>

#include "output/hdf5_io.hpp"
#include "output/run_directory.hpp"

namespace mpmdem::mpm {

namespace {

template <typename V>
std::vector<double> flatten(const std::vector<V>& values, int comps) {
  std::vector<double> flat;
  flat.reserve(values.size() * static_cast<std::size_t>(comps));
  for (const V& e : values) {
    if constexpr (V::ColsAtCompileTime == 1) {
      for (int k = 0; k < comps; ++k) flat.push_back(e[k]);
    } else {
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) flat.push_back(e(i, j));  // row-major
    }
  }
  return flat;
}

}  // namespace

void write_final_state(const std::string& path, const Particles& p, const StateInfo& info) {
  const std::string tmp = path + ".tmp";
  const hsize_t n = p.size();
  {
    h5::File f = h5::File::create(tmp);
    f.write("id", p.id);
    if (p.region.size() == p.size())
      f.write("region", std::vector<std::int32_t>(p.region.begin(), p.region.end()));
    f.write("x", flatten(p.x, 3), {n, 3});
    f.write("x0", flatten(p.x0, 3), {n, 3});
    f.write("v", flatten(p.v, 3), {n, 3});
    f.write("stress", flatten(p.sigma, 9), {n, 3, 3});
    f.write("F", flatten(p.F, 9), {n, 3, 3});
    f.write("volume", p.V, {n});
    f.write("mass", p.m, {n});
    if (p.rotation.size() == p.size()) f.write("rotation", flatten(p.rotation, 3), {n, 3});
    if (p.porosity.size() == p.size()) f.write("porosity", p.porosity, {n});
    if (p.coordination.size() == p.size()) f.write("coordination", p.coordination, {n});
    if (p.status.size() == p.size()) f.write("status", p.status);
    f.attribute("time", info.time);
    f.attribute("step", info.step);
    f.attribute("scene", info.scene);
    f.attribute("config_file", info.config_file);
    f.flush();
  }
  commit_file(tmp, path);
}

}  // namespace mpmdem::mpm
