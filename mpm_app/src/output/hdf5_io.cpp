#include "output/hdf5_io.hpp"

#include <stdexcept>
#include <utility>

namespace mpmdem::mpm::h5 {

namespace {

void check(herr_t status, const std::string& what) {
  if (status < 0) throw std::runtime_error("HDF5: cannot " + what);
}

// Closes an HDF5 object at scope exit.
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

void write_raw(hid_t file, const std::string& name, hid_t type, const std::vector<hsize_t>& dims,
               const void* data) {
  Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose,
               "create dataspace for " + name);
  Handle set(
      H5Dcreate2(file, name.c_str(), type, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
      H5Dclose, "create dataset " + name);
  check(H5Dwrite(set.get(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), "write dataset " + name);
}

template <class T>
std::vector<T> read_raw(hid_t file, const std::string& path, const std::string& name, hid_t type) {
  Handle set(H5Dopen2(file, name.c_str(), H5P_DEFAULT), H5Dclose,
             "open dataset " + name + " in " + path);
  Handle space(H5Dget_space(set.get()), H5Sclose, "get the dataspace of " + name);
  const hssize_t n = H5Sget_simple_extent_npoints(space.get());
  if (n < 0) throw std::runtime_error("HDF5: cannot size dataset " + name + " in " + path);
  std::vector<T> out(static_cast<std::size_t>(n));
  if (n > 0) {
    check(H5Dread(set.get(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()),
          "read dataset " + name + " in " + path);
  }
  return out;
}

void write_attr(hid_t file, const std::string& name, hid_t type, const void* value) {
  Handle root(H5Gopen2(file, "/", H5P_DEFAULT), H5Gclose, "open root group");
  Handle space(H5Screate(H5S_SCALAR), H5Sclose, "create attribute space");
  Handle attr(H5Acreate2(root.get(), name.c_str(), type, space.get(), H5P_DEFAULT, H5P_DEFAULT),
              H5Aclose, "create attribute " + name);
  check(H5Awrite(attr.get(), type, value), "write attribute " + name);
}

void read_attr(hid_t file, const std::string& path, const std::string& name, hid_t type,
               void* value) {
  Handle root(H5Gopen2(file, "/", H5P_DEFAULT), H5Gclose, "open root group");
  Handle attr(H5Aopen(root.get(), name.c_str(), H5P_DEFAULT), H5Aclose,
              "open attribute " + name + " in " + path);
  check(H5Aread(attr.get(), type, value), "read attribute " + name + " in " + path);
}

}  // namespace

File File::create(const std::string& path) {
  const hid_t id = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (id < 0) throw std::runtime_error("HDF5: cannot create file " + path);
  return File(id, path);
}

File File::open(const std::string& path) {
  const hid_t id = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (id < 0) throw std::runtime_error("HDF5: cannot open file " + path);
  return File(id, path);
}

File::~File() {
  if (id_ >= 0) H5Fclose(id_);
}

void File::write(const std::string& name, const std::vector<double>& data,
                 const std::vector<hsize_t>& dims) {
  write_raw(id_, name, H5T_NATIVE_DOUBLE, dims, data.data());
}
void File::write(const std::string& name, const std::vector<std::int64_t>& data) {
  write_raw(id_, name, H5T_NATIVE_INT64, {data.size()}, data.data());
}
void File::write(const std::string& name, const std::vector<std::int32_t>& data) {
  write_raw(id_, name, H5T_NATIVE_INT32, {data.size()}, data.data());
}

bool File::has(const std::string& name) const {
  return H5Lexists(id_, name.c_str(), H5P_DEFAULT) > 0;
}

std::vector<double> File::read_doubles(const std::string& name, std::size_t expected) const {
  auto v = read_raw<double>(id_, path_, name, H5T_NATIVE_DOUBLE);
  if (v.size() != expected) {
    throw std::runtime_error("HDF5: dataset " + name + " in " + path_ + " has " +
                             std::to_string(v.size()) + " values, expected " +
                             std::to_string(expected));
  }
  return v;
}
std::vector<double> File::read_doubles(const std::string& name) const {
  return read_raw<double>(id_, path_, name, H5T_NATIVE_DOUBLE);
}
std::vector<std::int64_t> File::read_int64(const std::string& name) const {
  return read_raw<std::int64_t>(id_, path_, name, H5T_NATIVE_INT64);
}
std::vector<std::int32_t> File::read_int32(const std::string& name) const {
  return read_raw<std::int32_t>(id_, path_, name, H5T_NATIVE_INT32);
}

void File::attribute(const std::string& name, double value) {
  write_attr(id_, name, H5T_NATIVE_DOUBLE, &value);
}
void File::attribute(const std::string& name, std::int64_t value) {
  write_attr(id_, name, H5T_NATIVE_INT64, &value);
}
void File::attribute(const std::string& name, const std::string& value) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose, "copy string type");
  check(H5Tset_size(type.get(), H5T_VARIABLE), "size string type");
  check(H5Tset_cset(type.get(), H5T_CSET_UTF8), "set string charset");
  const char* text = value.c_str();
  write_attr(id_, name, type.get(), &text);
}
bool File::has_attribute(const std::string& name) const {
  return H5Aexists(id_, name.c_str()) > 0;
}
double File::attribute_double(const std::string& name) const {
  double v = 0.0;
  read_attr(id_, path_, name, H5T_NATIVE_DOUBLE, &v);
  return v;
}
std::int64_t File::attribute_int64(const std::string& name) const {
  std::int64_t v = 0;
  read_attr(id_, path_, name, H5T_NATIVE_INT64, &v);
  return v;
}

void File::flush() {
  check(H5Fflush(id_, H5F_SCOPE_GLOBAL), "flush " + path_);
}

}  // namespace mpmdem::mpm::h5
