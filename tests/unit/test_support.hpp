// Helpers shared by the unit tests that write files: a temporary directory removed at the
// end of the test, and reading a whole file.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>

namespace test_support {

// <temp>/mpmdem_<tag>_<pid>_<n>, empty at the start (created only with kCreate: the run
// driver creates its own run directory), removed with everything in it at the end.
class TempDir {
 public:
  enum Mode { kNameOnly, kCreate };
  explicit TempDir(const std::string& tag, Mode mode = kNameOnly) {
    path_ = std::filesystem::temp_directory_path() /
            ("mpmdem_" + tag + "_" + std::to_string(::getpid()) + "_" + std::to_string(count_++));
    std::filesystem::remove_all(path_);
    if (mode == kCreate) std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string str() const { return path_.string(); }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  static inline int count_ = 0;
};

// The whole file as bytes; empty if it cannot be read.
inline std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace test_support
