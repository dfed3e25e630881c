// Progress lines on stdout during a run, at most one per `interval_s` of wall time:
//   step 1200  t=0.0600/0.5000 s (12.0%)  dt=5.0e-05 s  ETA 0:00:42  E_k/E_p0=1.2e-03
// (E_k in J instead of the ratio when the scene has no potential energy). scripts/run
// shows these lines as they come.
#pragma once

#include <chrono>
#include <cstdint>
#include <ostream>
#include <string>

namespace mpmdem::mpm {

struct ProgressState {
  std::int64_t step = 0;
  double time = 0.0;
  double end_time = 0.0;
  double dt = 0.0;
  double E_k = 0.0;
  double E_p0 = 0.0;
};

// "H:MM:SS" (hours grow past 9 as needed); "?" for a negative or non-finite duration.
std::string format_duration(double seconds);
// The progress line for `s`, with the given remaining wall time estimate.
std::string format_progress(const ProgressState& s, double eta_s);

class Progress {
 public:
  using Clock = std::chrono::steady_clock;

  // interval_s <= 0 disables the periodic lines.
  Progress(std::ostream& out, double interval_s);
  // True if interval_s of wall time passed since the last line (cheap: call every step).
  bool due() const;
  // Prints a line if due(). Returns true if it printed.
  bool update(const ProgressState& s);
  // Marks the start of stepping (for the ETA): simulated time at which stepping began.
  void start(double sim_time);
  // Prints a line now (end of the run).
  void print(const ProgressState& s);
  double elapsed_s() const;

 private:
  double eta(const ProgressState& s) const;

  std::ostream& out_;
  double interval_s_;
  Clock::time_point start_;
  Clock::time_point last_;
  double start_sim_time_ = -1.0;
};

// "time step: dt = ..." lines: at the first step and whenever the step changed by more than
// 10 % since the last line.
class TimeStepLog {
 public:
  // The line for a step of dt ending at step `step`, time `time`; "" if none is due.
  std::string line(double dt, std::int64_t step, double time);

 private:
  double logged_ = 0.0;
};

}  // namespace mpmdem::mpm
