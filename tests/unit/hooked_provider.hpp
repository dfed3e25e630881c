// A constitutive provider for fault injection and instrumentation in the unit tests: it runs
// another provider and hands the responses of every update to a hook, which may change them
// (a NaN, a status) or record what the solver sent (the dF batch). Used with
// SceneBuilder::solver(provider) (scene_builder.hpp) or RunOptions::provider_factory.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "constitutive/provider.hpp"

namespace mpmdem::mpm::test_fixture {

// What the hook is told of an update: its count (1 for the first update of this provider),
// the solver's step number and the batch of dF.
struct Update {
  std::int64_t call = 0;
  std::int64_t step = 0;
  const std::vector<Mat3>& dF;
};

class HookedProvider : public ConstitutiveProvider {
 public:
  using Hook = std::function<void(const Update&, std::vector<PointResponse>&)>;
  HookedProvider(std::unique_ptr<ConstitutiveProvider> inner, Hook hook)
      : inner_(std::move(inner)), hook_(std::move(hook)) {}
  std::string name() const override { return "hooked_" + inner_->name(); }
  void initialise(const std::vector<Mat3>& s0, std::vector<PointResponse>& out) override {
    inner_->initialise(s0, out);
  }
  void update(const std::vector<Mat3>& dF, double dt, std::int64_t step, double time,
              std::vector<PointResponse>& out) override {
    inner_->update(dF, dt, step, time, out);
    hook_(Update{++calls_, step, dF}, out);
  }

 private:
  std::unique_ptr<ConstitutiveProvider> inner_;
  Hook hook_;
  std::int64_t calls_ = 0;
};

}  // namespace mpmdem::mpm::test_fixture
