// Test-only process `test_free_block`: a free cube of n^3 particles (no tools) whose velocity is
// set at the first step to v_z = -v0 sin(pi z/L), v_x = v0 sin(pi y/L) (compression plus shear).
// With zero initial stress all energy starts kinetic, so in a conservative discretisation the
// kinetic energy can never exceed its initial value (tests/unit/test_energy_free_block.cpp).
#include <cmath>
#include <numbers>

#include "sphforge/plugin.hpp"

namespace {
using namespace sphforge;

class FreeBlock final : public Process {
 public:
  explicit FreeBlock(const ParamValues& p)
      : n_(static_cast<int>(p.integer("n"))), dx_(p.number("spacing")), v0_(p.number("v0")) {}
  void build(SceneBuilder& scene) override {
    std::vector<Eigen::Vector3d> points;
    for (int k = 0; k < n_; ++k)
      for (int j = 0; j < n_; ++j)
        for (int i = 0; i < n_; ++i) points.emplace_back((i + 0.5) * dx_, (j + 0.5) * dx_, (k + 0.5) * dx_);
    scene.add_body("block", points, dx_);
  }
  void bind_signals(SignalBus&) override {}
  void before_step(ProcessContext& ctx) override {
    if (initialised_) return;
    initialised_ = true;
    const double L = n_ * dx_;
    double* v = ctx.fields->f64(field::velocity);
    const double* x = ctx.fields->f64(field::position);
    for (std::size_t i = 0; i < ctx.fields->size(); ++i) {
      v[3 * i + 0] = v0_ * std::sin(std::numbers::pi * x[3 * i + 1] / L);
      v[3 * i + 2] = -v0_ * std::sin(std::numbers::pi * x[3 * i + 2] / L);
    }
  }
  void measure(ProcessContext&) override {}
  std::vector<HistoryColumn> history_columns() const override { return {}; }

 private:
  int n_;
  double dx_, v0_;
  bool initialised_ = false;
};

const PluginDescriptor& descriptor() {
  static const PluginDescriptor d = make_plugin_descriptor<FreeBlock>(
      "test_free_block", "0.1.0", "free cube with an initial velocity field (tests only)",
      {ParamSpec::integer("n", 12, "particles per edge", 2, 200),
       ParamSpec::number("spacing", "m", 1e-3, "particle spacing", 1e-9),
       ParamSpec::number("v0", "m/s", 0.02, "velocity amplitude", 0.0)});
  return d;
}
}  // namespace

SPHFORGE_PLUGIN(descriptor)
