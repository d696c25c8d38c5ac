// History and interpolation of delay(); see delay_lines.hpp.
#include "mo/runtime/delay_lines.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mo::runtime {

namespace {

/// Two times closer than this are one instant (t_e + T − T is t_e only up to rounding).
double instant(double t) { return 64 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(t)); }

/// Breaks of a higher level are not scheduled: each level smooths the
/// signal by one derivative, and every level multiplies the events.
constexpr int kLastLevel = 2;

}  // namespace

void DelayLines::reset(std::size_t n) {
  lines_.assign(n, Line{});
  breaks_.clear();
  last_event_ = -std::numeric_limits<double>::max();
}

void DelayLines::schedule(double time, int level) {
  if (level > kLastLevel || !std::isfinite(time)) return;
  const auto at = std::lower_bound(breaks_.begin(), breaks_.end(), time,
                                   [](const Break& b, double t) { return b.time < t; });
  for (auto it = at == breaks_.begin() ? at : at - 1; it != breaks_.end() && it->time <= time + instant(time); ++it)
    if (std::abs(it->time - time) <= instant(time)) {  // one event: the lower level counts
      it->level = std::min(it->level, level);
      return;
    }
  breaks_.insert(at, Break{time, level});
}

void DelayLines::at_event(double t) {
  last_event_ = t;
  while (!breaks_.empty() && breaks_.front().time <= t + instant(t)) {
    const Break b = breaks_.front();
    breaks_.erase(breaks_.begin());
    if (std::abs(b.time - t) > instant(t)) continue;  // passed without its event (a failed run)
    for (const Line& line : lines_)
      if (line.delay > 0.0 && !line.varying) schedule(t + line.delay, b.level + 1);
  }
}

void DelayLines::set_times(std::size_t k, double delay_time, double delay_max) {
  lines_[k].delay = delay_time;
  lines_[k].keep = std::max(delay_time, delay_max);
  if (!(delay_time <= delay_max)) lines_[k].delay = std::numeric_limits<double>::quiet_NaN();
}

void DelayLines::set_varying(std::size_t k, double at_start, double delay_max) {
  set_times(k, at_start, delay_max);
  lines_[k].varying = true;
}

void DelayLines::set_start(std::size_t k, double value) { lines_[k].start = value; }

bool DelayLines::record(std::size_t k, double t, double value) {
  Line& line = lines_[k];
  bool jump = false;
  if (line.t.empty()) {
    if (line.delay > 0.0 && !line.varying) schedule(t + line.delay, 1);  // t − T leaves the start
  } else {
    const double last = line.t.back();
    if (t < last) return false;
    if (t == last) {
      jump = value != line.v.back();
      // A third record at an instant: the event iteration moved on; the
      // value after is the latest.
      if (line.t.size() >= 2 && line.t[line.t.size() - 2] == t) {
        line.v.back() = value;
        jump = value != line.v[line.v.size() - 2];
        if (jump && line.delay > 0.0 && !line.varying) schedule(t + line.delay, 1);  // once: schedule() merges
        return jump;
      }
      if (jump && line.delay > 0.0 && !line.varying) schedule(t + line.delay, 1);
    }
  }
  line.t.push_back(t);
  line.v.push_back(value);
  forget(line, t);
  return jump;
}

// Drops what t − Tmax can no longer read, keeping three points before it for
// the interpolation stencil; compacts once the dead part is the larger.
void DelayLines::forget(Line& line, double now) {
  const double oldest = now - line.keep - instant(now);
  while (line.first + 4 < line.t.size() && line.t[line.first + 3] < oldest) ++line.first;
  if (line.first > 64 && line.first * 2 > line.t.size()) {
    line.t.erase(line.t.begin(), line.t.begin() + static_cast<std::ptrdiff_t>(line.first));
    line.v.erase(line.v.begin(), line.v.begin() + static_cast<std::ptrdiff_t>(line.first));
    line.first = 0;
  }
}

double DelayLines::value(std::size_t k, double t, double delay_time) const {
  const Line& line = lines_[k];
  if (line.t.empty()) return line.start;
  const double q = t - delay_time;
  const auto begin = line.t.begin() + static_cast<std::ptrdiff_t>(line.first);
  if (q <= *begin) return line.v[line.first];
  if (q >= line.t.back()) {
    // At the last instant's jump before its event: the value before.
    const std::size_t n = line.t.size();
    if (n >= 2 && line.t[n - 2] == line.t[n - 1] && q - line.t[n - 1] <= instant(q) && last_event_ < t - instant(t))
      return line.v[n - 2];
    return line.v.back();
  }
  // Segment [i, i + 1) with t_i <= q < t_{i+1}.
  std::size_t i = static_cast<std::size_t>(std::upper_bound(begin, line.t.end(), q) - line.t.begin()) - 1;
  const bool after = last_event_ >= t - instant(t);  // the event at t_e + T has been handled
  // A jump at t_i (q just after it) or at t_{i+1} (q just before it) within
  // rounding of q: the side the event says.
  if (i > line.first && line.t[i - 1] == line.t[i] && q - line.t[i] <= instant(q) && !after) return line.v[i - 1];
  if (i + 2 < line.t.size() && line.t[i + 1] == line.t[i + 2] && line.t[i + 1] - q <= instant(q) && after)
    return line.v[i + 2];
  // Four points around [t_i, t_{i+1}) within the piece between the breaks
  // before and after it (fewer where the piece has fewer).
  std::size_t first = i, last = i + 1;
  while (first > line.first && first + 3 > i && line.t[first - 1] != line.t[first]) --first;
  while (last + 1 < line.t.size() && last < i + 4 && line.t[last + 1] != line.t[last]) ++last;
  std::size_t lo = std::max(first, i > 0 ? i - 1 : 0);
  const std::size_t hi = std::min(last, lo + 3);
  lo = std::max(first, hi >= 3 ? hi - 3 : 0);
  const double cubic = interpolate(line, lo, hi, q);
  // Far outside the values around it, the points are not smooth (a steep
  // change no event separated): the chord between the two neighbours.
  const auto [low, high] = std::minmax_element(line.v.begin() + static_cast<std::ptrdiff_t>(lo),
                                               line.v.begin() + static_cast<std::ptrdiff_t>(hi) + 1);
  if (cubic >= *low - (*high - *low) && cubic <= *high + (*high - *low)) return cubic;
  return interpolate(line, i, i + 1, q);
}

// Lagrange through the points lo..hi (at most four, distinct times), as
// v_lo + Σ w_j (v_j − v_lo): constant data gives its value exactly (a
// delayed Integer read through integer() must not come back as 2.9999…).
double DelayLines::interpolate(const Line& line, std::size_t lo, std::size_t hi, double q) const {
  const double base = line.v[lo];
  double sum = 0.0;
  for (std::size_t j = lo + 1; j <= hi; ++j) {
    double w = 1.0;
    for (std::size_t m = lo; m <= hi; ++m)
      if (m != j) w *= (q - line.t[m]) / (line.t[j] - line.t[m]);
    sum += w * (line.v[j] - base);
  }
  return base + sum;
}

double DelayLines::next_event(double t) const {
  for (const Break& b : breaks_)
    if (b.time > t + instant(t)) return b.time;
  return std::numeric_limits<double>::infinity();
}

double DelayLines::shortest() const {
  double shortest = std::numeric_limits<double>::infinity();
  for (const Line& line : lines_) {
    // A varying delay time of 0 at the start (allowed: e itself) is bounded by Tmax.
    const double delay = line.varying && line.delay == 0.0 ? line.keep : line.delay;
    if (!(delay > 0.0)) return std::numeric_limits<double>::quiet_NaN();
    shortest = std::min(shortest, delay);
  }
  return shortest;
}

}  // namespace mo::runtime
