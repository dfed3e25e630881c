#include "output/vtk_writer.hpp"

#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "output/run_directory.hpp"

namespace mpmdem::mpm {

#if !defined(__BYTE_ORDER__) || __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "vtk_writer writes LittleEndian files; add byte swapping for this platform"
#endif

namespace {

// One DataArray of the appended section: its XML declaration and its bytes.
struct Array {
  std::string name;
  std::string type;  // Float64, Int64, Int32, UInt8
  int components = 1;
  std::vector<char> bytes;
};

template <typename T>
void append_bytes(std::vector<char>& bytes, const T& value) {
  const char* raw = reinterpret_cast<const char*>(&value);
  bytes.insert(bytes.end(), raw, raw + sizeof(T));
}

Array vec3_array(const std::string& name, const std::vector<Vec3>& v) {
  Array a{name, "Float64", 3, {}};
  a.bytes.reserve(v.size() * 3 * sizeof(double));
  for (const Vec3& e : v)
    for (int k = 0; k < 3; ++k) append_bytes(a.bytes, e[k]);
  return a;
}

template <typename T>
Array scalar_array(const std::string& name, const std::string& type, const std::vector<T>& s) {
  Array a{name, type, 1, {}};
  a.bytes.resize(s.size() * sizeof(T));
  if (!s.empty()) std::memcpy(a.bytes.data(), s.data(), a.bytes.size());
  return a;
}

}  // namespace

void write_vtu(const std::string& path, const Particles& p) {
  const std::size_t n = p.size();

  std::vector<Array> point_data;
  point_data.push_back(vec3_array("position", p.x));
  point_data.push_back(vec3_array("velocity", p.v));
  {
    std::vector<Vec3> u(n);
    for (std::size_t i = 0; i < n; ++i) u[i] = p.x[i] - p.x0[i];
    point_data.push_back(vec3_array("displacement", u));
  }
  {
    Array s{"stress", "Float64", 9, {}};
    s.bytes.reserve(n * 9 * sizeof(double));
    for (const Mat3& sigma : p.sigma)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) append_bytes(s.bytes, sigma(i, j));  // row-major
    point_data.push_back(std::move(s));
  }
  point_data.push_back(scalar_array("mass", "Float64", p.m));
  point_data.push_back(scalar_array("volume", "Float64", p.V));
  point_data.push_back(scalar_array("id", "Int64", p.id));
  if (p.region.size() == n) point_data.push_back(scalar_array("region", "Int32", p.region));
  // RVE outputs: present only when the provider filled them.
  if (n > 0 && p.rotation.size() == n) point_data.push_back(vec3_array("rotation", p.rotation));
  if (n > 0 && p.porosity.size() == n)
    point_data.push_back(scalar_array("porosity", "Float64", p.porosity));
  if (n > 0 && p.coordination.size() == n)
    point_data.push_back(scalar_array("coordination", "Float64", p.coordination));
  if (n > 0 && p.unbalanced_force.size() == n)
    point_data.push_back(scalar_array("unbalanced_force", "Float64", p.unbalanced_force));
  if (n > 0 && p.state.size() == n)
    point_data.push_back(scalar_array("status", "Int32", state_codes(p.state)));

  Array points = vec3_array("Points", p.x);
  Array connectivity{"connectivity", "Int64", 1, {}};
  Array offsets{"offsets", "Int64", 1, {}};
  Array types{"types", "UInt8", 1, {}};
  connectivity.bytes.reserve(n * 8);
  offsets.bytes.reserve(n * 8);
  for (std::size_t i = 0; i < n; ++i) {
    append_bytes(connectivity.bytes, static_cast<std::int64_t>(i));
    append_bytes(offsets.bytes, static_cast<std::int64_t>(i + 1));
    types.bytes.push_back(static_cast<char>(1));  // VTK_VERTEX
  }

  // XML header with the offset of each array inside the appended section.
  std::uint64_t offset = 0;
  auto declare = [&offset](std::ostringstream& xml, const Array& a) {
    xml << "        <DataArray type=\"" << a.type << "\" Name=\"" << a.name << "\"";
    if (a.components > 1) xml << " NumberOfComponents=\"" << a.components << "\"";
    xml << " format=\"appended\" offset=\"" << offset << "\"/>\n";
    offset += sizeof(std::uint64_t) + a.bytes.size();
  };
  std::ostringstream xml;
  xml << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\""
      << " header_type=\"UInt64\">\n"
      << "  <UnstructuredGrid>\n"
      << "    <Piece NumberOfPoints=\"" << n << "\" NumberOfCells=\"" << n << "\">\n"
      << "      <PointData Vectors=\"velocity\" Tensors=\"stress\" Scalars=\"mass\">\n";
  for (const Array& a : point_data) declare(xml, a);
  xml << "      </PointData>\n      <Points>\n";
  declare(xml, points);
  xml << "      </Points>\n      <Cells>\n";
  declare(xml, connectivity);
  declare(xml, offsets);
  declare(xml, types);
  xml << "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n"
      << "  <AppendedData encoding=\"raw\">\n   _";

  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot write '" + tmp + "'");
    const std::string head = xml.str();
    out.write(head.data(), static_cast<std::streamsize>(head.size()));
    auto write_block = [&out](const Array& a) {
      const std::uint64_t nbytes = a.bytes.size();
      out.write(reinterpret_cast<const char*>(&nbytes), sizeof nbytes);
      out.write(a.bytes.data(), static_cast<std::streamsize>(a.bytes.size()));
    };
    for (const Array& a : point_data) write_block(a);
    write_block(points);
    write_block(connectivity);
    write_block(offsets);
    write_block(types);
    out << "\n  </AppendedData>\n</VTKFile>\n";
    out.flush();
    if (!out) throw std::runtime_error("write to '" + tmp + "' failed (disk full?)");
  }
  commit_file(tmp, path);
}

VtkSeries::VtkSeries(std::string dir, std::string prefix)
    : dir_(std::move(dir)), prefix_(std::move(prefix)) {}

VtkSeries::VtkSeries(std::string dir, const std::vector<double>& times, std::string prefix)
    : dir_(std::move(dir)), prefix_(std::move(prefix)) {
  for (double t : times) {
    char name[64];
    std::snprintf(name, sizeof name, "%s_%05zu.vtu", prefix_.c_str(), frames_.size());
    frames_.emplace_back(t, name);
  }
}

std::vector<double> VtkSeries::frame_times() const {
  std::vector<double> t;
  for (const auto& f : frames_) t.push_back(f.first);
  return t;
}

std::string VtkSeries::pvd_path() const {
  return dir_ + "/" + prefix_ + "s.pvd";
}

std::string VtkSeries::write_frame(const Particles& p, double time) {
  char name[64];
  std::snprintf(name, sizeof name, "%s_%05zu.vtu", prefix_.c_str(), frames_.size());
  write_vtu(dir_ + "/" + name, p);
  frames_.emplace_back(time, name);

  std::ostringstream pvd;
  pvd.precision(17);
  pvd << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      << "  <Collection>\n";
  for (const auto& [t, file] : frames_) {
    pvd << "    <DataSet timestep=\"" << t << "\" group=\"\" part=\"0\" file=\"" << file
        << "\"/>\n";
  }
  pvd << "  </Collection>\n</VTKFile>\n";
  write_file_atomic(pvd_path(), pvd.str());
  return name;
}

}  // namespace mpmdem::mpm
