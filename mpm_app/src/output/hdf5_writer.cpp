#include "output/hdf5_writer.hpp"

#include <hdf5.h>

#include <stdexcept>
#include <vector>

#include "output/run_directory.hpp"

namespace mpmdem::mpm {

namespace {

// Closes an HDF5 handle at scope exit.
class Handle {
 public:
  Handle(hid_t id, herr_t (*close)(hid_t), const std::string& what) : id_(id), close_(close) {
    if (id_ < 0) throw std::runtime_error("HDF5: cannot " + what);
  }
  ~Handle() {
    if (id_ >= 0) close_(id_);
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  hid_t get() const { return id_; }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

void check(herr_t status, const std::string& what) {
  if (status < 0) throw std::runtime_error("HDF5: cannot " + what);
}

void write_dataset(hid_t file, const std::string& name, hid_t type,
                   const std::vector<hsize_t>& dims, const void* data) {
  Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose,
               "create dataspace for " + name);
  Handle set(
      H5Dcreate2(file, name.c_str(), type, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
      H5Dclose, "create dataset " + name);
  check(H5Dwrite(set.get(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), "write dataset " + name);
}

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

void write_attribute(hid_t loc, const std::string& name, hid_t type, const void* value) {
  Handle space(H5Screate(H5S_SCALAR), H5Sclose, "create attribute space");
  Handle attr(H5Acreate2(loc, name.c_str(), type, space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
              "create attribute " + name);
  check(H5Awrite(attr.get(), type, value), "write attribute " + name);
}

// Variable-length UTF-8 string: h5py reads it as str.
void write_string_attribute(hid_t loc, const std::string& name, const std::string& value) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose, "copy string type");
  check(H5Tset_size(type.get(), H5T_VARIABLE), "size string type");
  check(H5Tset_cset(type.get(), H5T_CSET_UTF8), "set string charset");
  const char* text = value.c_str();
  write_attribute(loc, name, type.get(), &text);
}

}  // namespace

void write_final_state(const std::string& path, const Particles& p, const StateInfo& info) {
  const std::string tmp = path + ".tmp";
  const hsize_t n = p.size();
  {
    Handle file(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose,
                "create file " + tmp);
    const hid_t f = file.get();
    write_dataset(f, "id", H5T_NATIVE_INT64, {n}, p.id.data());
    if (p.region.size() == p.size())
      write_dataset(f, "region", H5T_NATIVE_INT32, {n}, p.region.data());
    write_dataset(f, "x", H5T_NATIVE_DOUBLE, {n, 3}, flatten(p.x, 3).data());
    write_dataset(f, "x0", H5T_NATIVE_DOUBLE, {n, 3}, flatten(p.x0, 3).data());
    write_dataset(f, "v", H5T_NATIVE_DOUBLE, {n, 3}, flatten(p.v, 3).data());
    write_dataset(f, "stress", H5T_NATIVE_DOUBLE, {n, 3, 3}, flatten(p.sigma, 9).data());
    write_dataset(f, "F", H5T_NATIVE_DOUBLE, {n, 3, 3}, flatten(p.F, 9).data());
    write_dataset(f, "volume", H5T_NATIVE_DOUBLE, {n}, p.V.data());
    write_dataset(f, "mass", H5T_NATIVE_DOUBLE, {n}, p.m.data());

    Handle root(H5Gopen2(f, "/", H5P_DEFAULT), H5Gclose, "open root group");
    write_attribute(root.get(), "time", H5T_NATIVE_DOUBLE, &info.time);
    write_attribute(root.get(), "step", H5T_NATIVE_INT64, &info.step);
    write_string_attribute(root.get(), "scene", info.scene);
    write_string_attribute(root.get(), "config_file", info.config_file);
    check(H5Fflush(f, H5F_SCOPE_GLOBAL), "flush " + tmp);
  }
  commit_file(tmp, path);
}

}  // namespace mpmdem::mpm
