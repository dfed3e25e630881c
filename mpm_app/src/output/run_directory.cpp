#include "output/run_directory.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>

namespace mpmdem::mpm {

namespace fs = std::filesystem;

std::string default_run_directory(const std::string& scene_name) {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", &utc);
  const std::string name = scene_name.empty() ? std::string("scene") : scene_name;
  return (fs::path("runs") / (name + "-" + stamp)).string();
}

void check_run_directory(const std::string& dir, bool force) {
  std::error_code ec;
  const fs::path p(dir);
  if (!fs::exists(p, ec)) return;
  if (!fs::is_directory(p, ec)) {
    throw RunDirectoryError("output path '" + dir +
                            "' exists and is not a directory; choose another --out");
  }
  if (!force && fs::exists(p / "summary.json", ec)) {
    throw RunDirectoryError("output directory '" + dir +
                            "' already holds a run (summary.json exists); choose another "
                            "--out or pass --force to overwrite it");
  }
}

void create_run_directory(const std::string& dir, bool force) {
  check_run_directory(dir, force);
  const fs::path p(dir);
  std::error_code ec;
  fs::create_directories(p, ec);
  if (ec) {
    throw RunDirectoryError("cannot create output directory '" + dir + "': " + ec.message());
  }
  if (force) {
    // Remove an earlier run's outputs so that stale frames do not mix with the new ones.
    for (const auto& entry : fs::directory_iterator(p, ec)) {
      const std::string name = entry.path().filename().string();
      const bool old_output = name == "summary.json" || name == "energies.csv" ||
                              name == "final_state.h5" || name == "frames.pvd" ||
                              (name.rfind("frame_", 0) == 0 && entry.path().extension() == ".vtu");
      if (old_output) fs::remove(entry.path(), ec);
    }
  }
  // Probe that the directory is writable now rather than at the first output frame.
  const fs::path probe = p / ".mpm_app_write_probe";
  {
    std::ofstream out(probe);
    if (!out) {
      throw RunDirectoryError("output directory '" + dir + "' is not writable");
    }
  }
  fs::remove(probe, ec);
}

void commit_file(const std::string& tmp_path, const std::string& path) {
  if (std::rename(tmp_path.c_str(), path.c_str()) != 0) {
    throw std::runtime_error("cannot rename '" + tmp_path + "' to '" + path +
                             "': " + std::strerror(errno));
  }
}

void write_file_atomic(const std::string& path, const std::string& content) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot write '" + tmp + "'");
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.flush();
    if (!out) throw std::runtime_error("write to '" + tmp + "' failed (disk full?)");
  }
  commit_file(tmp, path);
}

std::size_t keep_rows_up_to_step(const std::string& path, const std::string& header,
                                 std::int64_t last_step, int step_column) {
  std::string kept = header + "\n";
  std::size_t rows = 0;
  {
    std::ifstream in(path);
    std::string line;
    std::getline(in, line);  // header
    // A log written by a version with fewer columns (`header` adds columns at its end): the
    // kept rows get "nan" in the columns they do not have, so no value sits under the wrong
    // name.
    std::string pad;
    if (line != header && header.compare(0, line.size() + 1, line + ",") == 0) {
      const auto commas = [](const std::string& s) { return std::count(s.begin(), s.end(), ','); };
      for (auto n = commas(header) - commas(line); n > 0; --n) pad += ",nan";
    }
    while (std::getline(in, line)) {
      std::size_t start = 0;
      for (int c = 0; c < step_column && start != std::string::npos; ++c) {
        start = line.find(',', start);
        if (start != std::string::npos) ++start;
      }
      if (start == std::string::npos) break;
      if (std::atoll(line.c_str() + start) > last_step) break;
      kept += line + pad + "\n";
      ++rows;
    }
  }
  write_file_atomic(path, kept);
  return rows;
}

std::ofstream open_step_log(const std::string& path, const std::string& header,
                            std::int64_t last_step, int step_column, std::size_t* kept_rows) {
  if (last_step < 0) {
    std::ofstream out(path, std::ios::trunc);
    if (!out) throw std::runtime_error("cannot write '" + path + "'");
    out << header << '\n';
    out.flush();
    if (kept_rows) *kept_rows = 0;
    return out;
  }
  const std::size_t kept = keep_rows_up_to_step(path, header, last_step, step_column);
  if (kept_rows) *kept_rows = kept;
  std::ofstream out(path, std::ios::app);
  if (!out) throw std::runtime_error("cannot append to '" + path + "'");
  return out;
}

void write_buffer(std::ofstream& out, std::string& buffer, const std::string& path) {
  if (buffer.empty()) return;
  out << buffer;
  out.flush();
  if (!out) throw std::runtime_error("write to '" + path + "' failed (disk full?)");
  buffer.clear();
}

}  // namespace mpmdem::mpm
