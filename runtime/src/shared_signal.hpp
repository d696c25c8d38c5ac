// Small InputSignal adaptors used by the optimisation code.
#pragma once

#include "mo/runtime/input.hpp"

#include <memory>
#include <vector>

namespace mo::runtime::detail {

/// Forwards to a shared signal, so one signal can drive several Inputs objects.
class SharedSignal final : public InputSignal {
public:
  explicit SharedSignal(std::shared_ptr<const InputSignal> signal) : signal_(std::move(signal)) {}
  [[nodiscard]] double value(double t) const override { return signal_->value(t); }
  [[nodiscard]] double value_before(double t) const override { return signal_->value_before(t); }
  [[nodiscard]] std::vector<double> breakpoints(double t0, double t1) const override {
    return signal_->breakpoints(t0, t1);
  }

private:
  std::shared_ptr<const InputSignal> signal_;
};

/// A unique_ptr signal for Inputs that shares `signal`.
inline std::unique_ptr<InputSignal> share(std::shared_ptr<const InputSignal> signal) {
  return std::make_unique<SharedSignal>(std::move(signal));
}

}  // namespace mo::runtime::detail
