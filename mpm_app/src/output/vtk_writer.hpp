// ParaView output: one XML UnstructuredGrid file (.vtu) per frame with the material points
// as VTK_VERTEX cells, and a .pvd collection that lists the frames with their times.
//
// Arrays are stored as raw binary in an appended section (header_type UInt64, little
// endian), which ParaView, VisIt and meshio read; this is ~3x smaller than ASCII.
// Point data: position, velocity, displacement (x - x0), stress (9 components, row-major,
// tension positive), mass, volume, id, region, and the RVE outputs the scene asked for
// (rotation, porosity, coordination, unbalanced_force, status) when the provider filled them.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "particles.hpp"

namespace mpmdem::mpm {

// Writes one .vtu file (through a temporary name and a rename).
void write_vtu(const std::string& path, const Particles& p);

class VtkSeries {
 public:
  // Frames go to dir/<prefix>_NNNNN.vtu, the collection to dir/<prefix>s.pvd.
  explicit VtkSeries(std::string dir, std::string prefix = "frame");
  // Continues a series whose first frames (prefix_00000.vtu, ...) were written at `times`
  // (a resumed run: frames written after its checkpoint are overwritten).
  VtkSeries(std::string dir, const std::vector<double>& times, std::string prefix = "frame");
  std::vector<double> frame_times() const;
  // Writes the next frame and rewrites the collection. Returns the frame's file name.
  std::string write_frame(const Particles& p, double time);
  std::size_t frames() const { return frames_.size(); }
  std::string pvd_path() const;

 private:
  std::string dir_;
  std::string prefix_;
  std::vector<std::pair<double, std::string>> frames_;  // (time, file name)
};

}  // namespace mpmdem::mpm
