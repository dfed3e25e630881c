// Small HDF5 (C API) helpers shared by the final-state writer and the checkpoints: a file
// handle that closes itself, datasets of doubles / int64 / int32 with any shape, scalar
// attributes. Every failure throws std::runtime_error naming the object.
#pragma once

#include <hdf5.h>
#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace mpmdem::mpm::h5 {

// Fixed-size Eigen vectors/matrices to one flat row-major array of doubles, and back.
template <int R, int C>
std::vector<double> flatten(const std::vector<Eigen::Matrix<double, R, C>>& v) {
  std::vector<double> out;
  out.reserve(v.size() * R * C);
  for (const auto& e : v)
    for (int i = 0; i < R; ++i)
      for (int j = 0; j < C; ++j) out.push_back(e(i, j));
  return out;
}
template <int R, int C>
std::vector<Eigen::Matrix<double, R, C>> unflatten(const std::vector<double>& flat, std::size_t n) {
  std::vector<Eigen::Matrix<double, R, C>> out(n);
  std::size_t k = 0;
  for (auto& e : out)
    for (int i = 0; i < R; ++i)
      for (int j = 0; j < C; ++j) e(i, j) = flat[k++];
  return out;
}

class File {
 public:
  // Create (truncate) or open read-only.
  static File create(const std::string& path);
  static File open(const std::string& path);
  ~File();
  File(File&& o) noexcept : id_(o.id_), path_(std::move(o.path_)) { o.id_ = -1; }
  File(const File&) = delete;
  File& operator=(const File&) = delete;
  hid_t id() const { return id_; }
  const std::string& path() const { return path_; }

  void write(const std::string& name, const std::vector<double>& data,
             const std::vector<hsize_t>& dims);
  void write(const std::string& name, const std::vector<std::int64_t>& data);
  void write(const std::string& name, const std::vector<std::int32_t>& data);
  bool has(const std::string& name) const;
  std::vector<double> read_doubles(const std::string& name, std::size_t expected) const;
  std::vector<double> read_doubles(const std::string& name) const;  // any size
  std::vector<std::int64_t> read_int64(const std::string& name) const;
  std::vector<std::int32_t> read_int32(const std::string& name) const;

  void attribute(const std::string& name, double value);
  void attribute(const std::string& name, std::int64_t value);
  void attribute(const std::string& name, const std::string& value);
  bool has_attribute(const std::string& name) const;
  double attribute_double(const std::string& name) const;
  std::int64_t attribute_int64(const std::string& name) const;
  void flush();

 private:
  File(hid_t id, std::string path) : id_(id), path_(std::move(path)) {}
  hid_t id_;
  std::string path_;
};

}  // namespace mpmdem::mpm::h5
