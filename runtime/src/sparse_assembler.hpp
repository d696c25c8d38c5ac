// Triplet assembly of a sparse matrix whose pattern is found by running the
// evaluation code once: a recording pass collects the (row, col) of every
// add() call; later passes replay the same calls in the same order and
// accumulate values into the merged pattern (duplicates are summed).
#pragma once

#include <algorithm>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace mo::runtime::detail {

/// Records a sparsity pattern from add() calls, then accumulates values in that order.
class SparseAssembler {
public:
  /// Starts a recording pass: add() collects positions, values are ignored.
  void begin_record() {
    recording_ = true;
    calls_.clear();
  }
  /// Ends the recording pass: merges duplicate positions into the pattern.
  void finish_record() {
    recording_ = false;
    std::vector<std::pair<int, int>> unique = calls_;
    std::sort(unique.begin(), unique.end());
    unique.erase(std::unique(unique.begin(), unique.end()), unique.end());
    rows_.clear(), cols_.clear();
    for (auto [r, c] : unique) rows_.push_back(r), cols_.push_back(c);
    slot_.resize(calls_.size());
    for (std::size_t k = 0; k < calls_.size(); ++k)
      slot_[k] = static_cast<int>(std::lower_bound(unique.begin(), unique.end(), calls_[k]) -
                                  unique.begin());
    calls_.clear();
    calls_.shrink_to_fit();
  }
  /// Starts a value pass writing into `values` (size nnz(), zeroed here).
  void begin_values(std::span<double> values) {
    values_ = values;
    std::fill(values.begin(), values.end(), 0.0);
    next_ = 0;
  }
  /// Ends a value pass; throws std::logic_error if the calls differ from the recording.
  void finish_values() const {
    if (next_ != slot_.size())
      throw std::logic_error("internal error: sparse assembly replayed " + std::to_string(next_) +
                             " of " + std::to_string(slot_.size()) + " recorded entries");
  }
  /// Adds `value` at (row, col): recorded or accumulated depending on the pass.
  void add(int row, int col, double value) {
    if (recording_) {
      calls_.emplace_back(row, col);
      return;
    }
    if (next_ >= slot_.size())
      throw std::logic_error("internal error: sparse assembly beyond the recorded pattern");
    values_[static_cast<std::size_t>(slot_[next_++])] += value;
  }
  /// Number of distinct positions.
  [[nodiscard]] int nnz() const { return static_cast<int>(rows_.size()); }
  /// Row of each distinct position.
  [[nodiscard]] const std::vector<int>& rows() const { return rows_; }
  /// Column of each distinct position.
  [[nodiscard]] const std::vector<int>& cols() const { return cols_; }

private:
  bool recording_ = false;
  std::vector<std::pair<int, int>> calls_;
  std::vector<int> slot_, rows_, cols_;
  std::span<double> values_;
  std::size_t next_ = 0;
};

}  // namespace mo::runtime::detail
