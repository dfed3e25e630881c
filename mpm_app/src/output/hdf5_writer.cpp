#include "output/hdf5_writer.hpp"

#include <stdexcept>
#include <vector>

#include "output/hdf5_io.hpp"
#include "output/run_directory.hpp"

namespace mpmdem::mpm {

void write_final_state(const std::string& path, const Particles& p, const StateInfo& info) {
  const std::string tmp = path + ".tmp";
  const hsize_t n = p.size();
  {
    h5::File f = h5::File::create(tmp);
    f.write("id", p.id);
    if (p.region.size() == p.size())
      f.write("region", std::vector<std::int32_t>(p.region.begin(), p.region.end()));
    f.write("x", h5::flatten(p.x), {n, 3});
    f.write("x0", h5::flatten(p.x0), {n, 3});
    f.write("v", h5::flatten(p.v), {n, 3});
    f.write("stress", h5::flatten(p.sigma), {n, 3, 3});
    f.write("F", h5::flatten(p.F), {n, 3, 3});
    f.write("volume", p.V, {n});
    f.write("mass", p.m, {n});
    if (p.rotation.size() == p.size()) f.write("rotation", h5::flatten(p.rotation), {n, 3});
    if (p.porosity.size() == p.size()) f.write("porosity", p.porosity, {n});
    if (p.coordination.size() == p.size()) f.write("coordination", p.coordination, {n});
    if (p.state.size() == p.size()) f.write("status", state_codes(p.state));
    f.attribute("time", info.time);
    f.attribute("step", info.step);
    f.attribute("scene", info.scene);
    f.attribute("config_file", info.config_file);
    f.flush();
  }
  commit_file(tmp, path);
}

}  // namespace mpmdem::mpm
