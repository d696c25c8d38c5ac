// The history behind Modelica's delay(e, T, Tmax): per call ("line") the
// values e took at the times the simulator recorded, read back at t − T.
//
//   - Recorded: the start (after initialisation), every accepted integrator
//     step, and each event twice (before and after the handler): two records
//     at one time are a break of the history (a jump if the values differ).
//   - Events: the delayed signal is not smooth where e jumps, nor where t − T
//     leaves the start (e(t0) before, e's history after). These breaks are
//     time events (next_event): t0 + T, and t_e + T after a jump of e at t_e
//     (level 1); and since a break of one delayed signal bends what the
//     model computes from it, each level-1 break at t_b schedules t_b + T
//     of every line (level 2). The integrator then never steps over them,
//     and the history has a break there too.
//   - Read: e(t0) for t − T <= t0 (MLS 3.7.2.4); within the history, cubic
//     interpolation through the recorded points around t − T between the
//     same two breaks; at a jump, the value before it until the event at
//     t_e + T has been handled (at_event), the value after it from then on.
//   - Kept: what t − Tmax may still read (Tmax >= T, the call's delayMax).
//
// A delay time must be positive: the simulator limits its step to the
// shortest one, so that every point read lies in the recorded past.
//
// A line may have a delay time that varies (delay(e, T, Tmax), T computed
// with the model's steps): it is read at t − T(t) with T given at each read,
// keeps Tmax of history, and schedules no breaks of its own (t_e + T(t) = t
// has no closed form); its delay time at the start counts for the step. A
// T outside [0, Tmax] is an error the caller reports; t − T after the last
// record (a T shorter than the step) reads the last value.
#pragma once

#include <cstddef>
#include <vector>

namespace mo::runtime {

class DelayLines {
public:
  /// `n` lines with no history, delay times 0 and starts 0.
  void reset(std::size_t n);
  /// Line k delays by `delay_time` and keeps `delay_max` (>= delay_time) of history.
  void set_times(std::size_t k, double delay_time, double delay_max);
  /// Line k's delay time varies, at most `delay_max`; `at_start` is its value at t0.
  void set_varying(std::size_t k, double at_start, double delay_max);
  /// The value line k gives before its first record (while the start is settled).
  void set_start(std::size_t k, double value);
  /// e_k(t) = value. A record at the time of the line's last one is the value
  /// after an event there: a jump if it differs. Records earlier than the
  /// last one are ignored (the integrator never goes back). True if this
  /// record is a jump (a new value at the last record's time).
  bool record(std::size_t k, double t, double value);
  /// An event is being handled at t: jumps that reach the present at t are
  /// read with their value after; a break due at t schedules the next level.
  void at_event(double t);
  /// e_k(t − T_k), the line's delayed value at time t.
  [[nodiscard]] double value(std::size_t k, double t) const { return value(k, t, lines_[k].delay); }
  /// e_k(t − delay_time): a varying line's value for its delay time now.
  [[nodiscard]] double value(std::size_t k, double t, double delay_time) const;
  /// Tmax of line k.
  [[nodiscard]] double delay_max(std::size_t k) const { return lines_[k].keep; }
  /// The first t_e + T_k of a recorded jump strictly after t (+infinity if none).
  [[nodiscard]] double next_event(double t) const;
  /// The shortest delay time over all lines; NaN if a line has T <= 0 or
  /// T > Tmax, +infinity without lines.
  [[nodiscard]] double shortest() const;
  [[nodiscard]] std::size_t size() const { return lines_.size(); }
  [[nodiscard]] bool has_history(std::size_t k) const { return !lines_[k].t.empty(); }

private:
  struct Line {
    double delay = 0.0, keep = 0.0, start = 0.0;
    bool varying = false;      ///< delay is the value at the start; reads give their own
    std::vector<double> t, v;  ///< ascending t; a break is two entries at one t
    std::size_t first = 0;     ///< entries before it are no longer read
  };
  struct Break {
    double time;
    int level;
  };
  [[nodiscard]] double interpolate(const Line& line, std::size_t lo, std::size_t hi, double q) const;
  void forget(Line& line, double now);
  void schedule(double time, int level);

  std::vector<Line> lines_;
  std::vector<Break> breaks_;  ///< time events still to come, ascending
  double last_event_ = -1e300;
};

}  // namespace mo::runtime
