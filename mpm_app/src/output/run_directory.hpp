// The run directory: where one run's outputs go, and how files in it are written.
// Final files are written to a temporary name and renamed, so a reader never sees half a
// file and an interrupted run never leaves a truncated summary or state.
#pragma once

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <stdexcept>
#include <string>

namespace mpmdem::mpm {

// The run directory cannot be used (exists with a finished run, not writable, ...).
// A user fault: exit code 2, like a config error.
class RunDirectoryError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// runs/<scene_name>-<UTC yyyymmdd-HHMMSS>, relative to the working directory.
std::string default_run_directory(const std::string& scene_name);

// Checks, without creating or touching anything, that `dir` may receive this run:
// refused if it holds a finished or failed run (summary.json exists) unless `force`,
// or if it exists and is not a directory. A directory that holds only what the pair
// launcher put there (dem_port.txt, Open MPI files) is accepted.
void check_run_directory(const std::string& dir, bool force);

// Creates `dir` (and parents). With `force`, removes the outputs of an earlier run in it
// (summary.json, energies.csv, final_state.h5, frames.pvd, frame_*.vtu) first.
void create_run_directory(const std::string& dir, bool force);

// Writes `content` to `path` through `path + ".tmp"` and a rename.
void write_file_atomic(const std::string& path, const std::string& content);

// A resumed run's CSV log: rewrites `path` (atomically) with `header` and the rows whose
// integer in column `step_column` is <= last_step, stopping at the first later row (rows
// the interrupted run wrote after its checkpoint). Returns the rows kept. If the file's header
// is `header` less some columns at its end (a log written before those columns existed), the
// kept rows get "nan" in them.
std::size_t keep_rows_up_to_step(const std::string& path, const std::string& header,
                                 std::int64_t last_step, int step_column);
// A step-indexed CSV log opened for appending: a new file holding `header` (last_step < 0),
// or, for a resumed run, the file cut by keep_rows_up_to_step (rows kept in *kept_rows).
// Throws naming the path if it cannot be written.
std::ofstream open_step_log(const std::string& path, const std::string& header,
                            std::int64_t last_step, int step_column,
                            std::size_t* kept_rows = nullptr);
// Appends `buffer` to `out` and clears it; throws naming `path` if the write failed.
void write_buffer(std::ofstream& out, std::string& buffer, const std::string& path);
// Renames `tmp_path` to `path` (same directory), throwing with both names on failure.
void commit_file(const std::string& tmp_path, const std::string& path);

}  // namespace mpmdem::mpm
