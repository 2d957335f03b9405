// The pipeline assembled from a case allocates exactly the fields its passes declare: an
// isothermal elastoplastic ram-extrusion case has plastic_strain but no temperature, and the
// particle count is the lattice the process promises.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "engine/simulation.hpp"
#include "sphforge/case_file.hpp"
#include "sphforge/errors.hpp"
#include "sphforge/fields.hpp"
#include "sphforge/plugin_loader.hpp"

using namespace sphforge;
namespace fs = std::filesystem;

namespace {

const std::string kQuickCase = std::string(SPHFORGE_SOURCE_DIR) + "/cases/ram_extrusion/paste_orifice_quick.json";

// The shrunk case: billet 4 mm high on a 1 mm lattice. (3 mm is too coarse for ram_extrusion,
// which wants at least 4 particles over the billet height; see BilletBelowFourLayersIsRejected.)
constexpr double kBilletHeight_mm = 4.0;
constexpr double kSpacing_mm = 1.0;
constexpr double kBarrelDiameter_mm = 25.0;  // from the quick case

CaseDocument shrunk_case() {
  // The density is pinned too, so that the checks below do not depend on how the bundled case is tuned.
  return load_case(kQuickCase, {"process.billet_height=4 mm", "process.particle_spacing=1 mm",
                                "material.density=1e7 kg/m^3"});
}

/// Particles of a cubic lattice at cell centres (i + 1/2, j + 1/2, k + 1/2) dx that stay at
/// least dx/2 inside the barrel wall, counted in integer arithmetic in units of dx/2:
/// (2i+1)^2 + (2j+1)^2 <= (2 R/dx - 1)^2, k < H/dx.
long long lattice_count(double barrel_diameter_mm, double height_mm, double dx_mm) {
  const long long two_r = std::llround(barrel_diameter_mm / dx_mm);  // 2R/dx
  const long long limit = (two_r - 1) * (two_r - 1);
  const long long layers = std::llround(std::floor(height_mm / dx_mm + 1e-9));
  long long per_layer = 0;
  for (long long i = -two_r; i <= two_r; ++i)
    for (long long j = -two_r; j <= two_r; ++j)
      if ((2 * i + 1) * (2 * i + 1) + (2 * j + 1) * (2 * j + 1) <= limit) ++per_layer;
  return per_layer * layers;
}

bool has_pass(const Simulation& sim, const std::string& name) {
  return std::any_of(sim.passes().begin(), sim.passes().end(), [&](const PassInfo& p) { return p.name == name; });
}

}  // namespace

TEST(PipelineFields, LatticeCountHelperIsRight) {
  // 25 mm barrel, 1 mm lattice: 448 columns inside r <= 12 mm (checked by hand: 4 x 112 per quadrant).
  EXPECT_EQ(lattice_count(25.0, 1.0, 1.0), 448);
  EXPECT_EQ(lattice_count(25.0, 4.0, 1.0), 4 * 448);
}

TEST(PipelineFields, IsothermalElastoplasticCaseAllocatesWhatItsPassesDeclare) {
  PluginLoader loader({SPHFORGE_PLUGIN_BUILD_DIR});
  const CaseDocument doc = shrunk_case();
  EXPECT_EQ(doc.file, kQuickCase);
  Simulation sim(doc, loader);
  const FieldRegistry& fields = sim.fields();

  // Particle count: the lattice, computed independently.
  const long long expected = lattice_count(kBarrelDiameter_mm, kBilletHeight_mm, kSpacing_mm);
  EXPECT_EQ(expected, 1792);
  EXPECT_EQ(static_cast<long long>(sim.particle_count()), expected);
  EXPECT_EQ(fields.size(), sim.particle_count());

  // Isothermal: no pass reads or writes temperature, so it does not exist at all.
  EXPECT_FALSE(fields.allocated(field::temperature));
  EXPECT_FALSE(fields.declared(field::temperature));
  const auto names = fields.names();
  EXPECT_EQ(std::count(names.begin(), names.end(), std::string(field::temperature)), 0);

  // The elastoplastic material declares plastic_strain (diagnostics such as von Mises stress only when
  // listed in its output_fields; the quick case lists none).
  ASSERT_TRUE(fields.allocated(field::plastic_strain));
  EXPECT_FALSE(fields.declared(field::von_mises_stress));
  EXPECT_FALSE(fields.declared("plastic_strain_rate"));
  EXPECT_FALSE(fields.declared("yield_stress"));
  EXPECT_EQ(fields.info(field::plastic_strain).components, 1);
  const auto& ps_users = fields.declared_by(field::plastic_strain);
  EXPECT_NE(std::find(ps_users.begin(), ps_users.end(), "material:elastoplastic"), ps_users.end());
  EXPECT_TRUE(has_pass(sim, "material:elastoplastic"));

  // The core fields the engine needs are there, with their shapes.
  struct Shape {
    const char* name;
    int components;
    FieldType type;
  };
  for (const Shape& s : {Shape{field::position, 3, FieldType::Float64}, Shape{field::velocity, 3, FieldType::Float64},
                         Shape{field::mass, 1, FieldType::Float64}, Shape{field::density, 1, FieldType::Float64},
                         Shape{field::pressure, 1, FieldType::Float64},
                         Shape{field::deviatoric_stress, 6, FieldType::Float64},
                         Shape{field::velocity_gradient, 9, FieldType::Float64},
                         Shape{field::id, 1, FieldType::Int64}}) {
    ASSERT_TRUE(fields.allocated(s.name)) << s.name;
    EXPECT_EQ(fields.info(s.name).components, s.components) << s.name;
    EXPECT_EQ(fields.info(s.name).type, s.type) << s.name;
  }

  // Every allocated field is declared by at least one pass of the pipeline, and by nothing that
  // is not a pass; conversely, everything a pass declares is allocated.
  std::set<std::string> pass_names, pass_fields;
  for (const PassInfo& p : sim.passes()) {
    EXPECT_TRUE(pass_names.insert(p.name).second) << "pass listed twice: " << p.name;
    for (const FieldInfo& f : p.reads) pass_fields.insert(f.name);
    for (const FieldInfo& f : p.writes) pass_fields.insert(f.name);
  }
  ASSERT_FALSE(names.empty());
  for (const std::string& name : names) {
    EXPECT_TRUE(fields.allocated(name)) << name << " declared but not allocated";
    const auto& users = fields.declared_by(name);
    EXPECT_FALSE(users.empty()) << name << " allocated without a declaring pass";
    for (const std::string& who : users) EXPECT_EQ(pass_names.count(who), 1u) << name << " declared by '" << who << "'";
    EXPECT_EQ(pass_fields.count(name), 1u) << name;
  }
  EXPECT_EQ(pass_fields, std::set<std::string>(names.begin(), names.end()));

  // The particles were initialised: mass rho0 dx^3 = 1e7 kg/m^3 * (1 mm)^3 = 0.01 kg, density rho0,
  // ids 0..n-1, everything inside the barrel and the billet height, half a spacing from the walls.
  const double* m = fields.f64(field::mass);
  const double* rho = fields.f64(field::density);
  const double* x = fields.f64(field::position);
  const std::int64_t* id = fields.i64(field::id);
  for (std::size_t i = 0; i < sim.particle_count(); ++i) {
    ASSERT_NEAR(m[i], 0.01, 1e-15) << i;
    ASSERT_DOUBLE_EQ(rho[i], 1e7) << i;
    ASSERT_EQ(id[i], static_cast<std::int64_t>(i));
    ASSERT_LE(std::hypot(x[3 * i], x[3 * i + 1]), 12.0e-3 + 1e-12) << i;
    ASSERT_GE(x[3 * i + 2], 0.5e-3 - 1e-12) << i;
    ASSERT_LE(x[3 * i + 2], 3.5e-3 + 1e-12) << i;
  }

  // Three tools: barrel, die and ram.
  ASSERT_EQ(sim.tools().size(), 3u);
  EXPECT_EQ(sim.tools()[0].name(), "barrel");
  EXPECT_EQ(sim.tools()[1].name(), "die");
  EXPECT_EQ(sim.tools()[2].name(), "ram");

  EXPECT_EQ(sim.settings().case_name, "paste_orifice_quick");
  EXPECT_DOUBLE_EQ(sim.settings().cfl, 0.3);
  EXPECT_DOUBLE_EQ(sim.settings().h_over_dx, 1.3);
}

TEST(PipelineFields, ParticleCountFollowsTheLattice) {
  // A second lattice, so the count is not a coincidence of one geometry: 5 mm billet, 1.25 mm spacing.
  PluginLoader loader({SPHFORGE_PLUGIN_BUILD_DIR});
  const CaseDocument doc =
      load_case(kQuickCase, {"process.billet_height=5 mm", "process.particle_spacing=1.25 mm"});
  Simulation sim(doc, loader);
  EXPECT_EQ(static_cast<long long>(sim.particle_count()), lattice_count(25.0, 5.0, 1.25));
  EXPECT_FALSE(sim.fields().allocated(field::temperature));
}

TEST(PipelineFields, BilletBelowFourLayersIsRejected) {
  PluginLoader loader({SPHFORGE_PLUGIN_BUILD_DIR});
  const CaseDocument doc = load_case(kQuickCase, {"process.billet_height=3 mm", "process.particle_spacing=1 mm"});
  try {
    Simulation sim(doc, loader);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), kQuickCase);
    EXPECT_EQ(e.pointer(), "/process/particle_spacing");
    EXPECT_NE(e.message().find("too coarse"), std::string::npos) << e.what();
  }
}
