#include "engine/simulation.hpp"

#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <numbers>

#include "backend.hpp"
#include "engine/attached_bodies.hpp"
#include "engine/body_force.hpp"
#include "engine/energy.hpp"
#include "engine/heat_conduction.hpp"
#include "engine/reorder.hpp"
#include "engine/second_order_gradient.hpp"
#include "engine/tool_heat.hpp"
#include "engine/density_diffusion.hpp"
#include "engine/xsph.hpp"
#include "io/output_writers.hpp"
#include "io/particle_dump.hpp"
#include "sphforge/errors.hpp"
#include "sphforge/version.hpp"

namespace sphforge {

namespace fs = std::filesystem;

namespace {

const ParamSpecs& top_level_specs() {
  static const ParamSpecs specs = {
      ParamSpec::object("case", "name and description of the case", true),
      ParamSpec::object("process", "the process plugin and its parameters", true),
      ParamSpec::object("material", "the material plugin of the workpiece and its parameters", true),
      ParamSpec::object("materials", "further materials by name, for bodies that name one (e.g. a tool's)"),
      ParamSpec::object("thermal", "heat conduction and convection; absent: isothermal (no thermal fields)"),
      ParamSpec::object("contact", "penalty contact settings and the friction law plugin", true),
      ParamSpec::object("body_force", "uniform body force on every mechanical particle, e.g. gravity (theory eq. 47)"),
      ParamSpec::array("controllers", "controller plugins driving the process's commands"),
      ParamSpec::array("phases", "process phases, each with its controllers and end condition (docs/controllers.md)"),
      ParamSpec::object("numerics", "SPH discretisation settings"),
      ParamSpec::object("run", "duration and output intervals", true),
  };
  return specs;
}

const ParamSpecs& case_specs() {
  static const ParamSpecs specs = {
      ParamSpec::string("name", std::nullopt, "case name, used for the default output folder"),
      ParamSpec::string("description", std::string(), "free text"),
  };
  return specs;
}

const ParamSpecs& numerics_specs() {
  static const ParamSpecs specs = {
      ParamSpec::string("kernel", std::string("cubic_spline"), "smoothing kernel (support 2h)",
                        {"cubic_spline", "wendland_c2"}),
      ParamSpec::number("h_over_dx", "1", 1.3, "smoothing length over particle spacing", 0.8, 3.0),
      ParamSpec::number("cfl", "1", 0.3, "Courant number of the time step dt = cfl h / (c + |v|max)", 1e-3, 2.0),
      ParamSpec::object("artificial_viscosity", "Monaghan artificial viscosity coefficients"),
      ParamSpec::boolean("gradient_correction", true,
                         "first-order (Randles-Libersky) correction of the velocity gradient (theory eq. 3b)"),
      ParamSpec::string("momentum_correction", std::string("full"),
                        "which part of the stress the correction C multiplies in the momentum equation, while the "
                        "velocity gradient stays corrected (eq. 3b). full: A = sigma C (eq. 7, the dual of the "
                        "corrected gradient); none: A = sigma (eq. 7a); deviatoric: A = S C - p I (eq. 7b). The "
                        "plain pressure term resists crowding under pressure (paste lands, docs/validation/"
                        "ram_extrusion.md 2g-2i). Costs (docs/verification.md 5b): none makes free faces soft (a "
                        "bar's wave -12 % at 4 particles across) and angular momentum inexact; deviatoric keeps "
                        "angular momentum exact and halves the softness",
                        {"full", "deviatoric", "none"}),
      ParamSpec::string("gradient_correction_order", std::string("first"),
                        "first: linear-consistent correction (eq. 3b); second: quadratic-consistent where the "
                        "neighbourhood allows, with its energy-consistent momentum term (theory section 18)",
                        {"first", "second"}),
      ParamSpec::object("artificial_stress", "Gray-Monaghan-Swift artificial stress against tensile instability"),
      ParamSpec::number("neighbour_skin", "1", 0.1,
                        "Verlet skin as a fraction of h: lists are rebuilt when a particle moved skin/2", 0.0, 2.0),
      ParamSpec::number("thermal_neighbour_skin", "1", -1.0,
                        "Verlet skin of the thermal lists (scenes with thermal-only bodies), fraction of h; -1: "
                        "neighbour_skin. Thicker when attached bodies turn fast (theory section 7)", -1.0, 2.0),
      ParamSpec::number("mass_scaling", "1", 1.0,
                        "factor on every particle's inertia (theory eq. 24); check kinetic_to_internal_ratio_1", 1.0,
                        1e12),
      ParamSpec::number("time_scaling", "1", 1.0,
                        "processes run f times faster; rate laws and heat flow are corrected (theory eq. 25)", 1.0,
                        1e6),
      ParamSpec::number("domain_margin", "m", -1.0,
                        "how far a particle may go beyond the initial scene's bounding box before the run stops "
                        "as unstable (-1: the box's own size, at least 100 spacings); raise it for long extrudates",
                        -1.0),
      ParamSpec::number("xsph", "1", 0.0, "XSPH velocity smoothing epsilon (theory eq. 19; 0: off)", 0.0, 1.0),
      ParamSpec::number("density_diffusion", "1", 0.0,
                        "delta-SPH density diffusion delta (theory eq. 4a; 0: off; 0.1 is the usual value): "
                        "damps the density noise the continuity equation accumulates in long, nearly "
                        "incompressible flows",
                        0.0, 1.0),
      ParamSpec::object("symmetry",
                        "mirror planes and/or a rotationally periodic sector about z: only the particles inside "
                        "are simulated, their images across the cuts are ghosts (theory section 11)"),
  };
  return specs;
}

const ParamSpecs& symmetry_specs() {
  static const ParamSpecs specs = {
      ParamSpec::array("mirror_planes",
                       "mirror planes {point, normal}, pairwise orthogonal; the normal points into the simulated side"),
      ParamSpec::object("sector", "rotationally periodic sector about the z axis: {angle, axis}"),
  };
  return specs;
}

const ParamSpecs& mirror_plane_specs() {
  static const ParamSpecs specs = {
      ParamSpec::array("point", "a point of the plane [x, y, z] (m; default the origin)"),
      ParamSpec::array("normal", "normal [nx, ny, nz] pointing into the simulated half-space", true),
  };
  return specs;
}

const ParamSpecs& sector_specs() {
  static const ParamSpecs specs = {
      ParamSpec::number("angle", "rad", std::nullopt,
                        "sector angle 360 deg / N (N >= 2 integer), from the +x axis counter-clockwise", 0.0),
      ParamSpec::string("axis", std::string("z"), "axis of the sector (through the origin)", {"z"}),
  };
  return specs;
}

/// Three numbers (SI) or quantity strings in `unit`.
Eigen::Vector3d vector3(const ParamValues& p, const std::string& name, const std::string& unit) {
  const std::vector<double> v = p.quantities(name, 3, unit);
  return {v[0], v[1], v[2]};
}

const ParamSpecs& viscosity_specs() {
  static const ParamSpecs specs = {
      ParamSpec::number("alpha", "1", 1.0, "linear coefficient", 0.0, 10.0),
      ParamSpec::number("beta", "1", 1.0, "quadratic coefficient", 0.0, 10.0),
      ParamSpec::number("eta", "1", 0.1, "singularity guard as a fraction of h", 1e-6, 1.0),
  };
  return specs;
}

const ParamSpecs& artificial_stress_specs() {
  static const ParamSpecs specs = {
      ParamSpec::number("epsilon", "1", 0.3, "strength (0 disables the term)", 0.0, 1.0),
      ParamSpec::number("exponent", "1", 4.0, "n in (W(r)/W(dx))^n", 1.0, 12.0),
  };
  return specs;
}

const ParamSpecs& contact_specs() {
  static const ParamSpecs specs = {
      ParamSpec::number("stiffness_factor", "1", 1.0,
                        "kappa: penalty stiffness k = kappa M dx, M = rho0 c^2 (theory eq. 10)", 1e-3, 10.0),
      ParamSpec::number("damping_ratio", "1", 0.2, "fraction of critical damping of the contact spring", 0.0, 1.0),
      ParamSpec::object("law", "friction law plugin used on every tool", true),
      ParamSpec::object("tool_laws", "per-tool friction laws overriding 'law', keyed by tool name"),
      ParamSpec::number("friction_heat_to_workpiece", "1", 0.5,
                        "fraction of the friction heat |f_t||v_t| that enters the workpiece; the rest goes to the "
                        "tool: into its attached thermal body if it has one (eq. 91), else it leaves the model "
                        "(theory eq. 18f)",
                        0.0, 1.0),
  };
  return specs;
}

const ParamSpecs& body_force_specs() {
  static const ParamSpecs specs = {
      ParamSpec::array("acceleration", "[gx, gy, gz] (m/s^2), e.g. [0, 0, \"-9.81 m/s^2\"]", true),
      ParamSpec::array("oscillation", "[ax, ay, az] (m/s^2): adds a cos(omega t) (a shaking table; theory eq. 47a)"),
      ParamSpec::number("angular_frequency", "rad/s", 0.0, "omega of the oscillating part", 0.0),
  };
  return specs;
}

const ParamSpecs& thermal_specs() {
  static const ParamSpecs specs = {
      ParamSpec::number("initial_temperature", "K", 293.15, "temperature of every particle at t = 0", 0.0),
      ParamSpec::number("ambient_temperature", "K", 293.15, "temperature of the surroundings (convection)", 0.0),
      ParamSpec::number("convection_coefficient", "W/(m^2*K)", 0.0,
                        "heat transfer coefficient on free surfaces; processes may set it per surface region", 0.0),
      ParamSpec::number("time_step_factor", "1", 0.1,
                        "dt <= factor rho c h^2 / k (theory eq. 26)", 1e-3, 1.0),
      ParamSpec::boolean("subcycling", false,
                         "conduction, convection and the tools' share of the friction heat on a step of their "
                         "own, as long as eq. 26 allows, while the heat sources act every step (theory eq. 26b); "
                         "false: every step conducts"),
  };
  return specs;
}

const ParamSpecs& run_specs() {
  static const ParamSpecs specs = {
      ParamSpec::number("end_time", "s", std::nullopt, "simulated time to run", 0.0),
      ParamSpec::number("output_interval", "s", 0.0, "time between particle frames (0: end_time/20)", 0.0),
      ParamSpec::number("history_interval", "s", 0.0, "time between history rows (0: output_interval/10)", 0.0),
      ParamSpec::integer("max_steps", 0, "stop after this many steps (0: no limit)", 0),
      ParamSpec::integer("threads", 0, "OpenMP threads (0: OpenMP default)", 0, 1024),
      ParamSpec::number("checkpoint_interval", "s", 0.0,
                        "time between restart checkpoints checkpoint_NNNNNN.h5, plus one at the end "
                        "(0: none; docs/checkpoints.md)", 0.0),
  };
  return specs;
}

/// Loads the plugin named in section["plugin"] and validates the rest of the section against it.
std::pair<const PluginDescriptor*, ParamValues> load_plugin(PluginLoader& loader, PluginKind kind,
                                                            const ParamValues& parent, const json& section,
                                                            const std::string& pointer) {
  const std::string& file = parent.file();
  if (!section.is_object()) throw InputError(file, pointer, "expected an object with a \"plugin\" name");
  if (!section.contains("plugin"))
    throw InputError(file, pointer + "/plugin", std::string("missing required value 'plugin' (name of a ") +
                                                    to_string(kind) + " plugin; see `sphforge plugins`)");
  if (!section["plugin"].is_string())
    throw InputError(file, pointer + "/plugin", "expected a plugin name (string)");
  const LoadedPlugin& plugin = loader.load(kind, section["plugin"].get<std::string>(), file, pointer + "/plugin");
  ParamValues values = validate_parameters(section, plugin.descriptor->parameters, file, pointer, {"plugin"});
  return {plugin.descriptor, std::move(values)};
}

std::string format_g(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", value);
  return buffer;
}

// Index of kinetic_to_work_ratio_1 in history_header().
constexpr std::size_t kRatioColumn = 8;

/// Index and speed of the fastest particle (for instability diagnoses).
std::pair<std::size_t, double> fastest_particle(const double* v, std::size_t n) {
  std::size_t fastest = 0;
  double vmax2 = -1.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double s2 = v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] + v[3 * i + 2] * v[3 * i + 2];
    if (s2 > vmax2) {
      vmax2 = s2;
      fastest = i;
    }
  }
  return {fastest, std::sqrt(std::max(vmax2, 0.0))};
}

bool finite3(const double* p) { return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]); }

/// " at (x, y, z) m" for a diagnosis.
std::string at_position(const double* x, std::size_t i) {
  char text[96];
  std::snprintf(text, sizeof text, " at (%.6g, %.6g, %.6g) m", x[3 * i], x[3 * i + 1], x[3 * i + 2]);
  return text;
}

// --- progress -------------------------------------------------------------------------------------
class Progress {
 public:
  /// start_time and start_steps: where this invocation starts (a restart at its checkpoint). The rate
  /// and the ETA count only the steps and the simulated time done since then, the percentage the whole run.
  Progress(ProgressMode mode, double start_time, long long start_steps, double end_time)
      : end_time_(end_time), start_time_(start_time), start_steps_(start_steps) {
    if (mode == ProgressMode::Auto) mode = isatty(STDERR_FILENO) ? ProgressMode::Bar : ProgressMode::Lines;
    mode_ = mode;
    start_ = last_ = std::chrono::steady_clock::now();
  }
  void update(double time, long long steps, bool force = false) {
    if (mode_ == ProgressMode::Quiet) return;
    const auto now = std::chrono::steady_clock::now();
    const double since_last = std::chrono::duration<double>(now - last_).count();
    const double interval = mode_ == ProgressMode::Bar ? 0.2 : 10.0;
    if (!force && since_last < interval) return;
    last_ = now;
    const double wall = std::chrono::duration<double>(now - start_).count();
    const double frac = std::clamp(time / end_time_, 0.0, 1.0);
    const double steps_per_s = wall > 0 ? (steps - start_steps_) / wall : 0.0;
    const double done = time - start_time_, left = end_time_ - time;
    const double eta = done > 0 && left > 0 ? wall * left / done : 0.0;
    char line[200];
    if (mode_ == ProgressMode::Bar) {
      const int width = 30, filled = static_cast<int>(frac * width);
      std::string bar(filled, '#');
      bar.resize(width, '.');
      std::snprintf(line, sizeof line, "\r[%s] %5.1f%%  t = %.4g s  %.0f steps/s  ETA %.0f s   ", bar.c_str(),
                    100 * frac, time, steps_per_s, eta);
      std::cerr << line << std::flush;
    } else {
      std::snprintf(line, sizeof line, "progress %5.1f%%  t = %.6g s  step %lld  %.0f steps/s  ETA %.0f s",
                    100 * frac, time, steps, steps_per_s, eta);
      std::cerr << line << std::endl;
    }
  }
  void finish() {
    if (mode_ == ProgressMode::Bar) std::cerr << std::endl;
  }

 private:
  ProgressMode mode_;
  double end_time_;
  double start_time_;
  long long start_steps_;
  std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace

// --- scene building -------------------------------------------------------------------------------
class Simulation::Builder : public SceneBuilder {
 public:
  std::vector<BodySpec> bodies;
  std::vector<RigidTool> tools;
  const Symmetry* symmetry = nullptr;  ///< active: bodies are clipped to the symmetry region

  std::size_t add_body(BodySpec body) override {
    if (!(body.spacing_m > 0.0)) throw std::invalid_argument("body '" + body.name + "': spacing must be positive");
    if (!body.velocities.empty() && body.velocities.size() != body.positions.size())
      throw std::invalid_argument("body '" + body.name + "': one initial velocity per particle expected");
    if (!body.particle_spacings_m.empty() && body.particle_spacings_m.size() != body.positions.size())
      throw std::invalid_argument("body '" + body.name + "': one particle spacing per particle expected");
    if (symmetry && symmetry->active()) {
      // The core keeps only the particles inside the symmetry region (eq. 30): processes build
      // their whole bodies and need not know about symmetry.
      std::size_t kept = 0;
      for (std::size_t k = 0; k < body.positions.size(); ++k) {
        if (!symmetry->inside(body.positions[k])) continue;
        body.positions[kept] = body.positions[k];
        if (!body.velocities.empty()) body.velocities[kept] = body.velocities[k];
        if (!body.particle_spacings_m.empty()) body.particle_spacings_m[kept] = body.particle_spacings_m[k];
        ++kept;
      }
      body.positions.resize(kept);
      if (!body.velocities.empty()) body.velocities.resize(kept);
      if (!body.particle_spacings_m.empty()) body.particle_spacings_m.resize(kept);
      if (kept == 0)
        throw std::invalid_argument("body '" + body.name + "' has no particle inside the symmetry region "
                                    "(numerics.symmetry)");
    }
    reject_coincident_particles(body);
    bodies.push_back(std::move(body));
    return bodies.size() - 1;
  }
  /// Two particles of one body on one spot, directly or through the symmetry (eq. 30a), would stay
  /// together for the whole run: refused, naming where (a process's lattice must keep its sites off
  /// the cuts; the ram_extrusion die fill once did not, docs/validation/dry_ice.md).
  void reject_coincident_particles(const BodySpec& body) const {
    double finest = body.spacing_m;
    for (double s : body.particle_spacings_m) finest = std::min(finest, s);
    const Symmetry none;
    const auto [i, j] = (symmetry ? *symmetry : none).find_coincident(body.positions, 0.5 * finest, 1e-6 * finest);
    if (i == body.positions.size()) return;
    const Eigen::Vector3d& x = body.positions[i];
    throw std::invalid_argument("body '" + body.name + "': particles " + std::to_string(i) + " and " +
                                std::to_string(j) + " lie on one spot (" + std::to_string(x[0]) + ", " +
                                std::to_string(x[1]) + ", " + std::to_string(x[2]) +
                                ") m, directly or through numerics.symmetry (a lattice site on a symmetry "
                                "cut is kept twice); shift the lattice off the cuts");
  }

  std::size_t add_tool(RigidTool tool) override {
    tools.push_back(std::move(tool));
    return tools.size() - 1;
  }
};

Simulation::Simulation(const CaseDocument& doc, PluginLoader& loader) : case_file_(doc.file), loader_(loader) {
  const std::string& file = doc.file;
  if (!doc.root.is_object()) throw InputError(file, "", "expected a JSON object at the top level");
  const ParamValues root = validate_parameters(doc.root, top_level_specs(), file, "");

  const ParamValues case_section = root.sub("case", case_specs());
  settings_.case_name = case_section.string("name");

  const ParamValues numerics =
      root.sub("numerics", numerics_specs());  // absent: validated as {} with defaults
  settings_.kernel = numerics.string("kernel") == "wendland_c2" ? KernelKind::WendlandC2 : KernelKind::CubicSpline;
  settings_.h_over_dx = numerics.number("h_over_dx");
  settings_.cfl = numerics.number("cfl");
  settings_.neighbour_skin = numerics.number("neighbour_skin");
  settings_.thermal_neighbour_skin = numerics.number("thermal_neighbour_skin") >= 0.0
                                        ? numerics.number("thermal_neighbour_skin")
                                        : settings_.neighbour_skin;
  settings_.domain_margin_m = numerics.number("domain_margin");
  settings_.gradient_correction = numerics.boolean("gradient_correction");
  const std::string momentum = numerics.string("momentum_correction");
  settings_.momentum_correction = momentum == "none"         ? MomentumCorrection::None
                                  : momentum == "deviatoric" ? MomentumCorrection::Deviatoric
                                                             : MomentumCorrection::Full;
  settings_.second_order_gradient = numerics.string("gradient_correction_order") == "second";
  if (settings_.second_order_gradient && !settings_.gradient_correction)
    numerics.fail("gradient_correction_order", "\"second\" needs numerics.gradient_correction = true");
  if (settings_.second_order_gradient && settings_.momentum_correction != MomentumCorrection::Full)
    numerics.fail("momentum_correction", "\"" + momentum + "\" needs numerics.gradient_correction_order = \"first\" "
                                         "(the second order has its own momentum term, eq. 136)");
  if (settings_.second_order_gradient && numerics.has("symmetry") && numerics.raw("symmetry").is_object() &&
      !numerics.raw("symmetry").empty())
    numerics.fail("gradient_correction_order", "\"second\" is not implemented with numerics.symmetry (ghost "
                                               "particles would need B transformed as a third-order tensor)");
  const ParamValues av = numerics.sub("artificial_viscosity", viscosity_specs());
  settings_.viscosity = {av.number("alpha"), av.number("beta"), av.number("eta")};
  const ParamValues as = numerics.sub("artificial_stress", artificial_stress_specs());
  settings_.artificial_stress.epsilon = as.number("epsilon");
  settings_.artificial_stress.exponent = as.number("exponent");

  const ParamValues run = root.sub("run", run_specs());
  settings_.end_time_s = run.number("end_time");
  if (!(settings_.end_time_s > 0.0)) run.fail("end_time", "expected a positive duration");
  settings_.output_interval_s = run.number("output_interval");
  if (settings_.output_interval_s <= 0.0) settings_.output_interval_s = settings_.end_time_s / 20.0;
  settings_.history_interval_s = run.number("history_interval");
  if (settings_.history_interval_s <= 0.0) settings_.history_interval_s = settings_.output_interval_s / 10.0;
  settings_.max_steps = run.integer("max_steps");
  settings_.threads = static_cast<int>(run.integer("threads"));
  settings_.checkpoint_interval_s = run.number("checkpoint_interval");
  case_root_ = doc.root;

  const double mass_scaling = numerics.number("mass_scaling");
  settings_.mass_scaling = mass_scaling;
  settings_.time_scaling = numerics.number("time_scaling");
  settings_.xsph = numerics.number("xsph");
  settings_.density_diffusion = numerics.number("density_diffusion");
  if (numerics.has("symmetry") && numerics.raw("symmetry").is_object()) {
    const ParamValues sym = numerics.sub("symmetry", symmetry_specs());
    if (sym.has("mirror_planes") && sym.raw("mirror_planes").is_array())
      for (std::size_t k = 0; k < sym.raw("mirror_planes").size(); ++k) {
        const ParamValues plane = sym.element("mirror_planes", k, mirror_plane_specs());
        SymmetrySettings::Plane pl;
        if (plane.has("point") && !plane.raw("point").empty()) pl.point = vector3(plane, "point", "m");
        pl.normal = vector3(plane, "normal", "1");
        settings_.symmetry.mirror_planes.push_back(pl);
      }
    if (sym.has("sector") && sym.raw("sector").is_object() && !sym.raw("sector").empty()) {
      const ParamValues sector = sym.sub("sector", sector_specs());
      settings_.symmetry.sector_angle_rad = sector.number("angle");
    }
    try {
      symmetry_ = Symmetry(settings_.symmetry);
      thermal_symmetry_ = Symmetry(settings_.symmetry);
    } catch (const std::invalid_argument& e) {
      throw InputError(file, "/numerics/symmetry", e.what());
    }
    settings_.symmetry = symmetry_.settings();
  }

  // Plugins: materials, process, contact laws, controllers.
  std::vector<std::string> material_names;  // plugin name of each material, for the pass list
  {
    auto [desc, values] = load_plugin(loader, PluginKind::Material, root, root.raw("material"), "/material");
    materials_.push_back(desc->make_material(values));
    material_keys_.push_back("");
    material_names.push_back(desc->name);
  }
  if (root.has("materials") && root.raw("materials").is_object()) {
    for (const auto& [key, section] : root.raw("materials").items()) {
      const std::string pointer = "/materials/" + json_pointer_escape(key);
      auto [desc, values] = load_plugin(loader, PluginKind::Material, root, section, pointer);
      materials_.push_back(desc->make_material(values));
      material_keys_.push_back(key);
      material_names.push_back(desc->name);
    }
  }
  for (const auto& material : materials_) material_views_.push_back(material.get());
  {
    auto [desc, values] = load_plugin(loader, PluginKind::Process, root, root.raw("process"), "/process");
    process_ = desc->make_process(values);
    process_name_ = desc->name;
  }

  // Build the scene.
  Builder builder;
  builder.symmetry = &symmetry_;
  try {
    process_->build(builder);
  } catch (const std::invalid_argument& e) {
    throw InputError(file, "/process", e.what());
  }
  if (builder.bodies.empty()) throw InputError(file, "/process", "the process created no particles");
  tools_ = std::move(builder.tools);

  // Thermal settings: a "thermal" section switches heat conduction on for the whole scene.
  settings_.thermal.enabled = doc.root.contains("thermal");
  if (settings_.thermal.enabled) {
    const ParamValues thermal = root.sub("thermal", thermal_specs());
    settings_.thermal.initial_temperature_K = thermal.number("initial_temperature");
    settings_.thermal.ambient_temperature_K = thermal.number("ambient_temperature");
    settings_.thermal.convection_coefficient = thermal.number("convection_coefficient");
    settings_.thermal.time_step_factor = thermal.number("time_step_factor");
    settings_.thermal.subcycling = thermal.boolean("subcycling");
  }

  // Bodies: resolve their materials; mechanical bodies first in the arrays (the mechanics passes
  // then run over one contiguous range [0, mechanical_count_)).
  std::vector<std::size_t> body_material(builder.bodies.size());
  std::vector<long long> body_tool(builder.bodies.size(), -1);
  for (std::size_t b = 0; b < builder.bodies.size(); ++b) {
    const BodySpec& spec = builder.bodies[b];
    auto it = std::find(material_keys_.begin(), material_keys_.end(), spec.material);
    if (it == material_keys_.end()) {
      std::string keys;
      for (std::size_t k = 1; k < material_keys_.size(); ++k) keys += (keys.empty() ? "" : ", ") + material_keys_[k];
      throw InputError(file, "/process", "body '" + spec.name + "' names material '" + spec.material +
                                             "', which is not a key of /materials" +
                                             (keys.empty() ? std::string(" (there is none)") : " (" + keys + ")"));
    }
    body_material[b] = static_cast<std::size_t>(it - material_keys_.begin());
    const std::size_t mat = body_material[b];
    if (settings_.thermal.enabled && !materials_[mat]->conducts_heat())
      throw InputError(file, mat == 0 ? "/material" : "/materials/" + json_pointer_escape(material_keys_[mat]),
                       "the case has a \"thermal\" section but this material has no thermal properties "
                       "(give its specific_heat and conductivity)");
    // A tool turning about z keeps a sector's symmetry but not a mirror plane's: a body attached to
    // a tool may only be cut by a sector (theory section 11).
    if (!spec.attached_to.empty() && symmetry_.active() && !settings_.symmetry.mirror_planes.empty())
      throw InputError(file, "/numerics/symmetry", "body '" + spec.name + "' is attached to tool '" +
                                                     spec.attached_to +
                                                     "': a turning tool breaks mirror symmetry; use a sector only");
    if (!spec.mechanics && !settings_.thermal.enabled)
      throw InputError(file, "/process", "body '" + spec.name +
                                             "' is thermal-only, which needs a \"thermal\" section in the case");
    // A body attached to a tool moves with it (eq. 90) and takes its share of the friction heat (eq. 91).
    if (!spec.attached_to.empty()) {
      auto it = std::find_if(tools_.begin(), tools_.end(), [&](const RigidTool& t) { return t.name() == spec.attached_to; });
      if (it == tools_.end()) {
        std::string names;
        for (const auto& t : tools_) names += (names.empty() ? "" : ", ") + t.name();
        throw InputError(file, "/process", "body '" + spec.name + "' is attached to tool '" + spec.attached_to +
                                               "', which does not exist (tools: " +
                                               (names.empty() ? std::string("none") : names) + ")");
      }
      if (spec.mechanics)
        throw InputError(file, "/process", "body '" + spec.name + "' is attached to tool '" + spec.attached_to +
                                               "' but is mechanical: only thermal-only bodies (mechanics false) "
                                               "can move with a tool");
      body_tool[b] = it - tools_.begin();
      any_attached_ = true;
    }
  }

  const ParamValues contact = root.sub("contact", contact_specs());
  settings_.contact.stiffness_factor = contact.number("stiffness_factor");
  settings_.contact.damping_ratio = contact.number("damping_ratio");
  settings_.contact.heat_to_workpiece = contact.number("friction_heat_to_workpiece");
  if (root.has("body_force") && root.raw("body_force").is_object() && !root.raw("body_force").empty()) {
    const ParamValues body_force = root.sub("body_force", body_force_specs());
    body_acceleration_ = vector3(body_force, "acceleration", "m/s^2");
    if (body_force.has("oscillation") && !body_force.raw("oscillation").empty())
      body_oscillation_ = vector3(body_force, "oscillation", "m/s^2");
    body_angular_frequency_ = body_force.number("angular_frequency");
  }
  {
    auto [desc, values] = load_plugin(loader, PluginKind::Contact, contact, contact.raw("law"),
                                      "/contact/law");
    contact_laws_.push_back(desc->make_contact(values));
  }
  std::vector<const ContactLaw*> tool_laws(tools_.size(), contact_laws_.front().get());
  if (contact.has("tool_laws") && contact.raw("tool_laws").is_object()) {
    for (const auto& [tool_name, section] : contact.raw("tool_laws").items()) {
      const std::string pointer = "/contact/tool_laws/" + json_pointer_escape(tool_name);
      auto it = std::find_if(tools_.begin(), tools_.end(), [&](const RigidTool& t) { return t.name() == tool_name; });
      if (it == tools_.end()) {
        std::string names;
        for (const auto& t : tools_) names += (names.empty() ? "" : ", ") + t.name();
        throw InputError(file, pointer, "no tool named '" + tool_name + "'; this process has: " + names);
      }
      auto [desc, values] = load_plugin(loader, PluginKind::Contact, contact, section, pointer);
      contact_laws_.push_back(desc->make_contact(values));
      tool_laws[static_cast<std::size_t>(it - tools_.begin())] = contact_laws_.back().get();
    }
  }
  for (const ContactLaw* law : tool_laws) need_yield_ = need_yield_ || law->needs_yield_stress();
  tool_laws_ = tool_laws;

  // Signals and controllers.
  process_->bind_signals(signals_);
  // Run-long controllers and process phases (engine/controller_phases.hpp), from the validated
  // sections ([] when absent).
  controllers_.load(
      root,
      [&](const json& section, const std::string& pointer) {
        auto [desc, values] = load_plugin(loader, PluginKind::Controller, root, section, pointer);
        return desc->make_controller(values);
      },
      signals_);
  // A checkpoint is only worth writing if the run can continue from it with every plugin's memory.
  if (settings_.checkpoint_interval_s > 0.0)
    if (const std::string missing = first_without_restart(); !missing.empty())
      throw InputError(file, "/run/checkpoint_interval",
                       "cannot write restart checkpoints: " + missing +
                           " keeps no restart state (supports_restart() is false); docs/checkpoints.md");

  // --- Pipeline: the passes this scene runs, and the fields they declare -------------------------
  const FieldInfo position{field::position, 3, "m"}, velocity{field::velocity, 3, "m/s"},
      acceleration{field::acceleration, 3, "m/s^2"}, mass{field::mass, 1, "kg"},
      density{field::density, 1, "kg/m^3"},
      pressure{field::pressure, 1, "Pa"}, stress{field::deviatoric_stress, 6, "Pa"},
      grad_v{field::velocity_gradient, 9, "1/s"}, contact_force{field::contact_force, 3, "N"},
      id{field::id, 1, "1", FieldType::Int64}, body{field::body, 1, "1", FieldType::Int64},
      temperature{field::temperature, 1, "K"}, temperature_rate{field::temperature_rate, 1, "K/s"},
      convection_coefficient{field::convection_coefficient, 1, "W/(m^2*K)"},
      heat_source{field::heat_source, 1, "W/kg"};
  bool any_mechanics = false;
  for (const BodySpec& b : builder.bodies) any_mechanics = any_mechanics || b.mechanics;
  // Optional passes and fields enter the list only when the case uses them.
  passes_ = {{"particles", {}, {id, body, mass, position}}};
  if (any_mechanics) {
    // The density rate and the gradient condition are per-step values that only the output frames
    // show: no fields; a frame computes them for the state it shows (output_velocity_gradient()).
    std::vector<FieldInfo> gradient_writes = {grad_v};
    passes_.push_back({"neighbour_search", {position}, {}});
    passes_.push_back({settings_.second_order_gradient ? "velocity_gradient_second_order" : "velocity_gradient",
                       {position, velocity, mass, density}, gradient_writes});
    // The materials of the mechanical bodies, each once.
    std::vector<std::size_t> used;
    for (std::size_t b = 0; b < builder.bodies.size(); ++b)
      if (builder.bodies[b].mechanics && std::find(used.begin(), used.end(), body_material[b]) == used.end())
        used.push_back(body_material[b]);
    if (settings_.density_diffusion > 0.0) {
      // Eq. 4a diffuses rho_j - rho_i between neighbours: meaningful within one material only.
      if (used.size() > 1)
        throw InputError(file, "/numerics/density_diffusion",
                         "density diffusion (eq. 4a) needs one material for all mechanical bodies; this case has " +
                             std::to_string(used.size()));
      passes_.push_back({"density_diffusion", {position, mass, density}, {}});
    }
    passes_.push_back({"continuity", {grad_v, density}, {density}});
    passes_.push_back({"jaumann_rotation", {grad_v}, {stress}});
    for (std::size_t mat : used) {
      std::vector<FieldInfo> material_reads = {grad_v, density}, material_writes = {stress, pressure};
      if (settings_.thermal.enabled) {
        material_reads.push_back(temperature);
        material_writes.push_back(heat_source);
      }
      for (const FieldInfo& f : materials_[mat]->fields()) material_writes.push_back(f);
      passes_.push_back({"material:" + material_names[mat], material_reads, material_writes});
    }
    // Bond failure (theory section 16): only when a material has a failure criterion (declares `failed`).
    bool any_failure = false;
    for (std::size_t mat : used)
      for (const FieldInfo& f : materials_[mat]->fields()) any_failure = any_failure || f.name == field::failed;
    if (any_failure) passes_.push_back({"bond_failure", {FieldInfo{field::failed, 1, "1"}, pressure, stress}, {}});
    if (any_failure && settings_.second_order_gradient)
      throw InputError(file, "/numerics/gradient_correction_order",
                       "\"second\" is not implemented with bond failure (a material with a failure criterion)");
    if (settings_.artificial_stress.epsilon > 0.0)
      passes_.push_back({"artificial_stress", {pressure, stress, density}, {}});
    passes_.push_back({"momentum", {position, velocity, mass, density, pressure, stress}, {acceleration}});
    // The friction laws that remember (the tangential spring of `coulomb`, eq. 18b) have it kept by
    // the contact pass for the touching particles only, keyed by the particle id (not a field: a
    // few per cent of the particles touch a tool; written to the outputs as friction_history_<tool>).
    if (!tools_.empty()) passes_.push_back({"contact", {position, velocity, mass, acceleration, id}, {contact_force}});
    if (settings_.xsph > 0.0) passes_.push_back({"xsph", {position, velocity, mass, density}, {}});
    passes_.push_back({"integrate", {acceleration, contact_force}, {position, velocity}});
  }
  if (settings_.thermal.enabled) {
    std::vector<FieldInfo> reads = {position, mass, density, temperature};
    if (any_mechanics) reads.push_back(heat_source);
    std::vector<FieldInfo> writes = {temperature_rate};
    // Sub-cycled (eq. 26b): each contact particle keeps the tools' share of its friction heat until
    // the next thermal step, a field per tool with an attached body, so that it survives reordering.
    if (settings_.thermal.subcycling && any_mechanics) {
      pending_tool_heat_field_.assign(tools_.size(), std::string());  // empty: the tool has no body
      for (std::size_t t = 0; t < tools_.size(); ++t)
        if (std::find(body_tool.begin(), body_tool.end(), static_cast<long long>(t)) != body_tool.end()) {
          pending_tool_heat_field_[t] = "pending_tool_heat_" + tools_[t].name();
          writes.push_back(FieldInfo{pending_tool_heat_field_[t], 1, "J"});
        }
    }
    passes_.push_back({"heat_conduction", reads, writes});
    passes_.push_back({"convection", {position, mass, density, temperature}, {convection_coefficient}});
    passes_.push_back({"integrate_temperature", {temperature_rate}, {temperature}});
  }
  // Variable spacing (theory section 19): particles of several spacings each get the smoothing length
  // of their own, h_i = h_over_dx s_i, and a pair uses h_ij = (h_i + h_j) / 2 (eq. 138). smin, smax:
  // over the particles created; the scene's spacing (h, the contact, eq. 10) is the largest body
  // spacing, empty bodies included, or the largest particle spacing if that is larger.
  double smin = std::numeric_limits<double>::infinity(), smax = 0.0;
  spacing_ = 0.0;  // every body spacing is > 0 (add_body)
  {
    for (const BodySpec& b : builder.bodies) {  // (add_body checked one spacing per particle)
      spacing_ = std::max(spacing_, b.spacing_m);
      if (b.particle_spacings_m.empty()) {
        if (!b.positions.empty()) smin = std::min(smin, b.spacing_m), smax = std::max(smax, b.spacing_m);
      } else {
        for (double s : b.particle_spacings_m) {
          if (!(s > 0.0)) throw std::logic_error("process: body '" + b.name + "' has a particle spacing <= 0");
          smin = std::min(smin, s), smax = std::max(smax, s);
        }
      }
    }
    spacing_ = std::max(spacing_, smax);
    variable_spacing_ = smax > smin * (1.0 + 1e-9);
    if (variable_spacing_) {
      const std::string why = " is not implemented for particles of several spacings (this case has " +
                              std::to_string(smin * 1e3) + " to " + std::to_string(smax * 1e3) +
                              " mm; docs/theory.md section 19)";
      if (symmetry_.active()) throw InputError(file, "/numerics/symmetry", "a symmetry sector" + why);
      if (settings_.second_order_gradient)
        throw InputError(file, "/numerics/gradient_correction_order", "\"second\"" + why);
      if (settings_.density_diffusion > 0.0)
        throw InputError(file, "/numerics/density_diffusion", "density diffusion" + why);
      if (settings_.xsph > 0.0) throw InputError(file, "/numerics/xsph", "XSPH" + why);
      passes_.push_back({"variable_spacing", {}, {FieldInfo{field::smoothing_length, 1, "m"}}});
    }
  }
  // Tool-attached thermal bodies keep their tool-frame positions, moved with them by reordering (eq. 90).
  if (any_attached_)
    passes_.push_back({"attached_bodies", {}, {position, FieldInfo{kToolReferencePosition, 3, "m"}}});
  std::vector<FieldInfo> process_fields = process_->fields();
  if (!process_fields.empty()) passes_.push_back({"process:" + process_name_, {}, process_fields});
  for (const PassInfo& pass : passes_) {
    for (const FieldInfo& f : pass.reads) fields_.declare(f, pass.name, Access::Read);
    for (const FieldInfo& f : pass.writes) fields_.declare(f, pass.name, Access::Write);
  }

  // --- Particles ----------------------------------------------------------------------------------
  for (const auto& b : builder.bodies) count_ += b.positions.size();
  if (count_ == 0) throw InputError(file, "/process", "the process created no particles");
  fields_.allocate(count_);
  h_ = settings_.h_over_dx * spacing_;
  h_min_ = variable_spacing_ ? settings_.h_over_dx * smin : h_;
  settings_.artificial_stress.w_dx = kernel_value(settings_.kernel, spacing_, h_);
  settings_.artificial_stress.w_dx_unit = kernel_value(settings_.kernel, 1.0 / settings_.h_over_dx, 1.0);  // eq. 139
  double* smoothing_length = variable_spacing_ ? fields_.f64(field::smoothing_length) : nullptr;
  double* x = fields_.f64(field::position);
  double* v = fields_.f64_if(field::velocity);
  double* m = fields_.f64(field::mass);
  double* rho = fields_.f64(field::density);
  std::int64_t* ids = fields_.i64(field::id);
  std::int64_t* body_of = fields_.i64(field::body);
  // Particle ranges: mechanical bodies first, thermal-only after, each in the order added; the
  // body index (field `body`, ProcessContext::bodies) is the order the process added them.
  bodies_.resize(builder.bodies.size());
  std::size_t next = 0;
  for (const bool mechanics : {true, false}) {
    for (std::size_t b = 0; b < builder.bodies.size(); ++b) {
      const BodySpec& src = builder.bodies[b];
      if (src.mechanics != mechanics) continue;
      bodies_[b] = {src.name, next, src.positions.size(), src.spacing_m, body_material[b], src.mechanics, body_tool[b]};
      const Material& material = *materials_[body_material[b]];
      // Mass scaling multiplies mass and (inertial) density alike (eq. 24).
      const double rho0 = material.reference_density() * mass_scaling;
      for (std::size_t k = 0; k < src.positions.size(); ++k, ++next) {
        for (int d = 0; d < 3; ++d) x[3 * next + d] = src.positions[k][d];
        if (v && !src.velocities.empty())
          for (int d = 0; d < 3; ++d) v[3 * next + d] = src.velocities[k][d];
        const double s = src.particle_spacings_m.empty() ? src.spacing_m : src.particle_spacings_m[k];
        m[next] = rho0 * s * s * s;
        if (smoothing_length) smoothing_length[next] = settings_.h_over_dx * s;
        rho[next] = rho0;
        ids[next] = static_cast<std::int64_t>(next);
        body_of[next] = static_cast<std::int64_t>(b);
      }
    }
    if (mechanics) mechanical_count_ = next;
  }
  for (const auto& b : bodies_)
    if (b.mechanics) materials_[b.material]->initialize(fields_, b.first, b.count);
  // Attached bodies: tool-frame positions from the tool's initial pose, then placed by eq. 90
  // (the same positions up to round-off), so that every step places them the same way.
  tool_takes_heat_.assign(tools_.size(), 0);
  for (const auto& b : bodies_) {
    if (b.attached_tool < 0) continue;
    const RigidTool& tool = tools_[static_cast<std::size_t>(b.attached_tool)];
    double* ref = fields_.f64(kToolReferencePosition);
    attach_to_tool(tool, x + 3 * b.first, ref + 3 * b.first, b.count);
    place_on_tool(tool, ref + 3 * b.first, x + 3 * b.first, b.count);
    tool_takes_heat_[static_cast<std::size_t>(b.attached_tool)] = 1;
  }
  tool_friction_heat_J_.assign(tools_.size(), 0.0);
  tool_heat_to_tool_J_.assign(tools_.size(), 0.0);
  if (settings_.thermal.enabled) {
    double* T = fields_.f64(field::temperature);
    std::fill(T, T + count_, settings_.thermal.initial_temperature_K);
    double* hc = fields_.f64(field::convection_coefficient);
    std::fill(hc, hc + count_, settings_.thermal.convection_coefficient);
    conductivity_.resize(count_);
    specific_heat_.resize(count_);
    heat_W_.resize(count_);
    area_.resize(count_);
    thermal_volume_.resize(count_);
  }

  // Wave speed of the mechanical materials, slowed by mass scaling (eq. 24).
  double c_max = 0.0;
  for (const auto& b : bodies_)
    if (b.mechanics) c_max = std::max(c_max, materials_[b.material]->wave_speed());
  wave_speed_ = c_max / std::sqrt(mass_scaling);
  if (mechanical_count_ > 0) {
    min_mass_ = *std::min_element(m, m + mechanical_count_);  // masses never change: the contact limit is fixed
    // Contact stiffness from the P-wave modulus M = rho0 c^2 of the workpiece material, which
    // mass scaling leaves unchanged (rho0 s c^2 / s).
    const auto first_mechanical = std::find_if(bodies_.begin(), bodies_.end(), [](const BodyRange& b) { return b.mechanics; });
    const Material& work = *materials_[first_mechanical->material];
    const double c0 = work.wave_speed();
    contact_.configure(settings_.contact, tool_laws, spacing_, work.reference_density() * c0 * c0,
                       variable_spacing_ ? smin : 0.0);
  }
  if (need_yield_) yield_scratch_.resize(count_);
  process_columns_ = process_->history_columns();
  controller_columns_ = controllers_.history_columns();
}

Simulation::~Simulation() = default;

const double* Simulation::smoothing_lengths() const {
  return variable_spacing_ ? fields_.f64(field::smoothing_length) : nullptr;
}

const double* Simulation::point_supports(std::size_t count) {
  if (!variable_spacing_) return nullptr;
  const double* hl = fields_.f64(field::smoothing_length);
  point_support_.resize(count);
  for (std::size_t i = 0; i < count; ++i) point_support_[i] = kernel_support_radius(hl[i]);
  return point_support_.data();
}

// --- time step ------------------------------------------------------------------------------------
double Simulation::thermal_time_step() const {
  // Explicit conduction is stable for dt < factor rho c h^2 / k (eq. 26), with time scaling f
  // speeding the conduction up f times. Uses the properties of the last thermal pass.
  if (!settings_.thermal.enabled) return std::numeric_limits<double>::infinity();
  const double* rho = fields_.f64(field::density);
  double limit = std::numeric_limits<double>::infinity();
  const double s = settings_.mass_scaling;
#pragma omp parallel for reduction(min : limit) schedule(static)
  for (std::size_t i = 0; i < count_; ++i) {
    if (!(conductivity_[i] > 0.0)) continue;
    // Thermal inertia uses the physical density: mass scaling is a mechanical device only.
    limit = std::min(limit, rho[i] / s * specific_heat_[i] / conductivity_[i]);
  }
  // The smallest smoothing length sets it (with variable spacing, eq. 138).
  return settings_.thermal.time_step_factor * h_min_ * h_min_ * limit / settings_.time_scaling;
}

double Simulation::stable_time_step() {
  const std::size_t nm = mechanical_count_;
  dt_cfl_ = dt_contact_ = std::numeric_limits<double>::infinity();
  if (nm > 0) {
    const double* v = fields_.f64(field::velocity);
    double vmax2 = 0.0;
#pragma omp parallel for reduction(max : vmax2) schedule(static)
    for (std::size_t i = 0; i < nm; ++i)
      vmax2 = std::max(vmax2, v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] + v[3 * i + 2] * v[3 * i + 2]);
    // NaN in a velocity is lost by max(); the stability check finds it.
    dt_cfl_ = settings_.cfl * h_min_ / (wave_speed_ + std::sqrt(vmax2));  // eq. 13 (h_min_: eq. 138)
    // Half the contact spring's stability limit: a safety margin for the damping's velocity lag.
    if (!tools_.empty()) dt_contact_ = 0.5 * contact_.stable_time_step(min_mass_);
  }
  dt_thermal_ = thermal_time_step();
  return std::min({dt_cfl_, dt_contact_, dt_thermal_});
}

void Simulation::check_stability() const {
  const std::int64_t* ids = fields_.i64(field::id);
  const std::size_t nm = mechanical_count_;
  std::size_t bad = count_;
  if (nm > 0) {
    // Cheap every step: all positions, velocities and the time step. Stress every 10 steps.
    const double* x = fields_.f64(field::position);
    const double* v = fields_.f64(field::velocity);
#pragma omp parallel for reduction(min : bad) schedule(static)
    for (std::size_t i = 0; i < nm; ++i)
      if (!finite3(x + 3 * i) || !finite3(v + 3 * i)) bad = std::min(bad, i);
    if (bad < count_)
      throw InstabilityError(step_, time_, ids[bad], finite3(x + 3 * bad) ? field::velocity : field::position,
                             "value is not finite (NaN or Inf)" + at_position(x, bad));
    if (step_ % 10 == 0) {
      const double* s = fields_.f64(field::deviatoric_stress);
      const double* p = fields_.f64(field::pressure);
#pragma omp parallel for reduction(min : bad) schedule(static)
      for (std::size_t i = 0; i < nm; ++i) {
        bool ok = std::isfinite(p[i]);
        for (int c = 0; c < 6; ++c) ok = ok && std::isfinite(s[6 * i + c]);
        if (!ok) bad = std::min(bad, i);
      }
      if (bad < count_)
        throw InstabilityError(step_, time_, ids[bad], field::deviatoric_stress,
                               "stress is not finite (NaN or Inf)" + at_position(x, bad));
      // Particles leaving the domain: farther from the initial bounding box than its own size
      // (or than 100 spacings for a thin scene) means a particle was ejected.
#pragma omp parallel for reduction(min : bad) schedule(static)
      for (std::size_t i = 0; i < nm; ++i)
        for (int d = 0; d < 3; ++d)
          if (x[3 * i + d] < domain_min_[d] || x[3 * i + d] > domain_max_[d]) bad = std::min(bad, i);
      if (bad < count_)
        throw InstabilityError(step_, time_, ids[bad], field::position,
                               "particle left the domain at (" + format_g(x[3 * bad]) + ", " +
                                   format_g(x[3 * bad + 1]) + ", " + format_g(x[3 * bad + 2]) +
                                   ") m: the domain is the initial scene enlarged by " +
                                   format_g(domain_margin_used_m_) +
                                   " m on every side (numerics.domain_margin; raise it if the particle "
                                   "is a legitimate extrudate)");
      // Energy ledger: without body forces, the kinetic energy can never exceed what the tools
      // put in plus what the particles started with; twice that means energy is being created.
      double work = 0.0;
      for (const auto& t : tools_) work += t.work_J;
      const double ke = kinetic_energy();
      const double budget = initial_kinetic_energy_ + std::max(work + constraint_work_J_ + body_force_work_J_, 0.0);
      // Motion at round-off speed is not a blow-up: a particle set exactly at the contact's reach
      // (a ring of sites dx/2 from a cylindrical wall, eq. 99a) sees a gap of 1e-18 m and a force of
      // that size before any tool has done work (7e-15 m/s in the FSBE quick case), against a budget
      // of 0 J. The ledger therefore speaks only once some particle moves faster than 1e-9 of the
      // (scaled) wave speed; energy created by an unstable scheme grows step by step past that.
      const auto [fastest, speed] =
          ke > 2.0 * budget && ke > 0.0 ? fastest_particle(v, nm) : std::pair<std::size_t, double>{0, 0.0};
      if (speed > 1e-9 * wave_speed_) {
        throw InstabilityError(step_, time_, ids[fastest], field::velocity,
                               "kinetic energy " + format_g(ke) + " J exceeds twice the energy put in (" +
                                   format_g(budget) + " J: initial kinetic energy plus the work of tools and "
                                   "prescribed velocities): energy is being "
                                   "created numerically; fastest particle at " + format_g(speed) + " m/s" +
                                   at_position(x, fastest));
      }
    }
    if (dt_ < 1e-3 * dt_initial_) {
      // The fastest particle is what collapsed the step.
      const auto [fastest, vmax] = fastest_particle(v, nm);
      throw InstabilityError(step_, time_, ids[fastest], field::velocity,
                             "time step collapsed to " + format_g(dt_) + " s (< 1e-3 of the initial " +
                                 format_g(dt_initial_) + " s); speed " + format_g(vmax) + " m/s" +
                                 at_position(x, fastest));
    }
  }
  if (settings_.thermal.enabled && step_ % 10 == 0) {
    const double* T = fields_.f64(field::temperature);
#pragma omp parallel for reduction(min : bad) schedule(static)
    for (std::size_t i = 0; i < count_; ++i)
      if (!std::isfinite(T[i]) || T[i] < 0.0) bad = std::min(bad, i);
    if (bad < count_)
      throw InstabilityError(step_, time_, ids[bad], field::temperature,
                             "temperature " + format_g(fields_.f64(field::temperature)[bad]) +
                                 " K is not finite or negative" + at_position(fields_.f64(field::position), bad) +
                                 " (conduction unstable? lower thermal.time_step_factor)");
  }
}

ProcessContext Simulation::context() {
  ProcessContext ctx{time_, dt_, step_, &fields_, &tools_, &bodies_};
  ctx.mechanical_count = mechanical_count_;
  ctx.time_scaling = settings_.time_scaling;
  ctx.materials = &material_views_;
  return ctx;
}

// --- one step ---------------------------------------------------------------------------------------
// Bond failure (eqs. 110-114), only where a material declared `failed`: both pair passes judge the
// bonds from the flags and the stresses of the step's start, copied here, so that they leave out the
// same pairs (the material sets new flags between the two passes).
BondFailure Simulation::bond_failure_inputs(std::size_t n) {
  BondFailure failure;
  if (const double* failed = fields_.f64_if(field::failed)) {
    const bool sym = symmetry_.active();
    const std::size_t nt = sym ? n + symmetry_.ghost_count() : n;
    bond_stress_.resize(6 * nt);
    cauchy_stress(fields_.f64(field::pressure), fields_.f64(field::deviatoric_stress), bond_stress_.data(), n);
    if (sym) {
      symmetry_.fill_symmetric(bond_stress_.data(), n);
      extend(ext_failed_, failed, 1);
    } else {
      ext_failed_.assign(failed, failed + n);
    }
    failure = {ext_failed_.data(), bond_stress_.data()};
  }
  return failure;
}

// The velocity gradient L (eqs. 3-3b, or eqs. 130-134 with the second-order correction) at x, v
// (extended with the ghosts) into L, and the gradient condition into `condition` unless null.
void Simulation::velocity_gradient_pass(const double* xe, const double* ve, const double* volume, double* correction,
                                        double* second_b, double* L, double* condition, std::size_t n,
                                        const BondFailure& failure) {
  if (settings_.second_order_gradient) {
    // Quadratic-consistent gradient (eqs. 130-134); symmetry and bond failure are refused at setup.
    second_order_correction(neighbours_, settings_.kernel, h_, xe, volume, second_b, correction, condition, n);
    second_order_velocity_gradient(neighbours_, settings_.kernel, h_, xe, ve, volume, second_b, correction, L, n);
  } else {
    velocity_gradient(neighbours_, settings_.kernel, h_, xe, ve, volume, settings_.gradient_correction, L, condition,
                      correction, n, failure, smoothing_lengths());
  }
}

// Doubles per particle (and ghost) of the pass scratch: volume (1), C or R (6, one array), A = sigma C
// (9, unless it is kept in the velocity gradient's storage), and B, A2 = sigma B (54) with the
// second-order gradient. At least 3, so that the neighbour build (2.5 doubles per point) and the
// contact pass (1.5) can still borrow it (theory section 7).
std::size_t Simulation::pass_scratch_per_particle(bool stress_c_in_l) const {
  const bool c_or_r = settings_.gradient_correction || settings_.artificial_stress.epsilon > 0.0;
  const std::size_t doubles =
      1 + (c_or_r ? 6 : 0) + (stress_c_in_l ? 0 : 9) + (settings_.second_order_gradient ? 54 : 0);
  return std::max<std::size_t>(doubles, 3);
}

// The mechanical neighbour lists at x. With symmetry the ghosts are selected first: the images within
// support + skin of the region (eq. 31), lists for the real particles only, over real and ghost
// particles alike. The pass scratch is idle during a build (it is filled after it): sized here for
// `per_particle` doubles per particle and ghost, it lends the build its 20 bytes per point (theory
// section 7), so that the scene does not hold both (the build needs 2.5 doubles per point, the
// scratch has >= 3). `transient`: a build for one evaluation outside the step, which leaves the step's
// rebuild schedule as it was (NeighbourList::build_transient).
void Simulation::build_mechanical_lists(const double* x, std::size_t n, std::size_t per_particle, bool transient) {
  const double search = kernel_support_radius(h_), skin = settings_.neighbour_skin * h_;
  const bool sym = symmetry_.active();
  if (sym) symmetry_.select(x, n, search + skin);
  const std::size_t points = sym ? n + symmetry_.ghost_count() : n;
  scratch_.resize(per_particle * points);
  const double* xe = sym ? extend(ext_x_, x, 3, true) : x;
  const std::size_t query = sym ? n : SIZE_MAX;
  if (transient) neighbours_.build_transient(xe, points, search, skin, query, scratch_, point_supports(points));
  else neighbours_.rebuild(xe, points, search, skin, query, scratch_, point_supports(points));
}

// The velocity gradient of an output frame. The step overwrites L with A = sigma C once L is dead for
// the arithmetic (mechanics_rates), so a frame recomputes L from the positions, velocities, masses and
// densities the frame shows, with the same passes the step uses, and with it the two per-step values
// that are no fields: the density rate (eq. 4) and the gradient condition (eq. 3b), which the frame
// writes like the friction memory. The lists are the step's when still valid for these positions
// (Verlet skin); otherwise a transient build for this evaluation leaves them stale, so that the next
// step rebuilds where it would have anyway: the dynamics do not see this evaluation.
void Simulation::output_velocity_gradient(std::vector<double>& density_rate, std::vector<double>& condition) {
  const std::size_t n = mechanical_count_;
  // Thermal-only particles have neither (0, as the fields that held these values had).
  density_rate.assign(count_, 0.0);
  condition.assign(settings_.gradient_correction ? count_ : 0, 0.0);
  if (n == 0) return;
  const double* x = fields_.f64(field::position);
  const double* v = fields_.f64(field::velocity);
  const double* m = fields_.f64(field::mass);
  const double* rho = fields_.f64(field::density);
  double* L = fields_.f64(field::velocity_gradient);
  double* drho = density_rate.data();
  // A state that blew up (the instability frame) has no gradient; a build from non-finite positions
  // would not end well.
  bool finite = true;
  for (std::size_t i = 0; i < n && finite; ++i) finite = finite3(x + 3 * i);
  if (!finite) {
    std::fill(L, L + 9 * n, std::numeric_limits<double>::quiet_NaN());
    std::fill(drho, drho + n, std::numeric_limits<double>::quiet_NaN());
    std::fill(condition.begin(), condition.end(), std::numeric_limits<double>::quiet_NaN());
    return;
  }
  const bool sym = symmetry_.active();
  const double search = kernel_support_radius(h_), skin = settings_.neighbour_skin * h_;
  const std::size_t per = pass_scratch_per_particle(!sym);
  if (neighbours_.needs_rebuild(x, n, search, skin)) build_mechanical_lists(x, n, per, /*transient=*/true);
  const std::size_t nt = sym ? n + symmetry_.ghost_count() : n;
  const double* xe = sym ? extend(ext_x_, x, 3, true) : x;
  const double* ve = sym ? extend(ext_v_, v, 3) : v;
  const double* me = sym ? extend(ext_m_, m, 1) : m;
  scratch_.resize(per * nt);
  double* volume = scratch_.data();
  double* correction = settings_.gradient_correction ? volume + nt : nullptr;
  double* second_b = settings_.second_order_gradient ? volume + (per - 54) * nt : nullptr;
  const double* rho_e = sym ? extend(ext_rho_, rho, 1) : rho;
  particle_volume(me, rho_e, volume, nt);
  const BondFailure failure = bond_failure_inputs(n);
  velocity_gradient_pass(xe, ve, volume, correction, second_b, L, condition.empty() ? nullptr : condition.data(), n,
                         failure);
  continuity_density_rate(L, rho, drho, n);
  if (settings_.density_diffusion > 0.0) density_diffusion_pass(xe, rho_e, volume, correction, drho, n, failure);
}

// Eqs. 4a-4b: the corrected density gradient of the real particles, the ghosts' by symmetry (a
// gradient transforms as a vector, eq. 31), then the diffusive rate added to drho.
void Simulation::density_diffusion_pass(const double* xe, const double* rho_e, const double* volume,
                                        const double* correction, double* drho, std::size_t n,
                                        const BondFailure& failure) {
  const bool sym = symmetry_.active();
  const std::size_t nt = sym ? n + symmetry_.ghost_count() : n;
  density_gradient_.resize(3 * nt);
  density_gradient(neighbours_, settings_.kernel, h_, xe, rho_e, volume, correction, density_gradient_.data(), n,
                   failure);
  if (sym) symmetry_.fill_vectors(density_gradient_.data(), n);
  add_density_diffusion(neighbours_, settings_.kernel, h_, settings_.density_diffusion, wave_speed_, xe, rho_e, volume,
                        density_gradient_.data(), drho, n, failure);
}

void Simulation::mechanics_rates() {
  const std::size_t n = mechanical_count_;
  double* x = fields_.f64(field::position);
  double* v = fields_.f64(field::velocity);
  double* a = fields_.f64(field::acceleration);
  double* m = fields_.f64(field::mass);
  double* rho = fields_.f64(field::density);
  double* p = fields_.f64(field::pressure);
  double* S = fields_.f64(field::deviatoric_stress);
  double* L = fields_.f64(field::velocity_gradient);
  double* fc = fields_.f64(field::contact_force);
  double* T = fields_.f64_if(field::temperature);
  double* heat_source = fields_.f64_if(field::heat_source);

  const double search = kernel_support_radius(h_), skin = settings_.neighbour_skin * h_;
  const bool sym = symmetry_.active();
  // Per-step scratch: volume (1), correction C (6), A = sigma C (9, see below), and for the artificial stress
  // R (6) per particle (nt: ghosts included). R is computed in place from sigma/rho^2 (eq. 9 reads
  // a particle's six values before it writes them), so that input needs no array of its own.
  // C and R share one array: C is last read when A = sigma C is formed (eq. 3b), before R is first
  // written (eq. 9), and neither is read by the other's passes.
  const bool with_artificial_stress = settings_.artificial_stress.epsilon > 0.0;
  const bool corrected = settings_.gradient_correction;
  // The second-order correction (theory section 18) adds B and A2 = sigma B, 27 each per particle.
  const bool second = settings_.second_order_gradient;
  const std::size_t shared_c_r = corrected || with_artificial_stress ? 6 : 0;
  // A = sigma C (9 per particle) goes into the velocity gradient's storage: L is last read by the
  // material update (eq. 15) and the Jaumann rotation (eq. 6), before A is formed (eq. 3b), and
  // nothing in the step reads L after that; an output frame recomputes L from the state it shows
  // (output_velocity_gradient()). With symmetry A is needed for the ghosts too (n + g particles),
  // more than the field holds, so it stays in the pass scratch.
  const bool stress_c_in_l = !sym;
  const std::size_t scratch_per_particle = pass_scratch_per_particle(stress_c_in_l);
  if (neighbours_.needs_rebuild(x, n, search, skin)) {
    // Symmetry: particles that crossed a cut re-enter through its image (eq. 32).
    if (sym && symmetry_.wrap(fields_, n, wrap_moves_) > 0) {
      // The friction memory is a vector, like the fields the wrap transformed (Q v, eq. 32); it is
      // kept by the contact pass by particle id (eq. 18b), so it is transformed here, the same way.
      const std::int64_t* ids = fields_.i64(field::id);
      for (std::size_t t = 0; t < contact_.history_tools(); ++t)
        for (const auto& [i, k] : wrap_moves_)
          if (FrictionHistoryEntry* e = contact_.friction_history_entry(t, ids[i])) {
            double rotated[3];
            Symmetry::transform_vector(symmetry_.images()[k].Q, e->value, rotated);
            for (int d = 0; d < 3; ++d) e->value[d] = rotated[d];
          }
    }
    // Memory locality: every few rebuilds, first sort the particles by cell (Morton order within
    // each body; every registered field moves, and nothing else indexed by particle outlives a step).
    if (neighbours_.builds() % kReorderEveryBuilds == 0 && reorder_by_cell(fields_, bodies_, search + skin))
      thermal_lists_stale_ = true;  // thermal-only particles moved in the arrays too
    build_mechanical_lists(x, n, scratch_per_particle, /*transient=*/false);
  }
  // With symmetry the pair passes read extended arrays [real | ghosts] of size nt = n + g; the
  // ghosts' values are refreshed from their sources right before the pass that reads them.
  const std::size_t nt = sym ? n + symmetry_.ghost_count() : n;
  const double* xe = sym ? extend(ext_x_, x, 3, true) : x;
  const double* ve = sym ? extend(ext_v_, v, 3) : v;
  const double* me = sym ? extend(ext_m_, m, 1) : m;
  scratch_.resize(scratch_per_particle * nt);
  double* volume = scratch_.data();
  double* correction = corrected ? volume + nt : nullptr;
  double* artificial = with_artificial_stress ? volume + nt : nullptr;  // C's storage, once C is dead
  double* stress_c = stress_c_in_l ? L : volume + (1 + shared_c_r) * nt;
  double* second_b = second ? volume + (1 + shared_c_r + (stress_c_in_l ? 0 : 9)) * nt : nullptr;
  double* stress_b = second ? second_b + 27 * nt : nullptr;
  // V = m / rho of the step's start; a ghost's volume is its source's (eq. 31).
  const double* rho_start = sym ? extend(ext_rho_, rho, 1) : rho;
  particle_volume(me, rho_start, volume, nt);
  const BondFailure failure = bond_failure_inputs(n);
  velocity_gradient_pass(xe, ve, volume, correction, second_b, L, nullptr, n, failure);
  const bool diffusion = settings_.density_diffusion > 0.0;
  if (diffusion) {
    diffusion_rate_.assign(n, 0.0);
    density_diffusion_pass(xe, rho_start, volume, correction, diffusion_rate_.data(), n, failure);
  }
  // The density advances here, before the material's equation of state, so that the pressure and
  // the deviatoric stress both belong to the new configuration x^n (eq. 14). Updating it after
  // the momentum pass lagged the pressure one step behind: a delayed restoring force that pumps
  // energy into nearly incompressible bodies (a free elastic block with nu = 0.47 gained 25x its
  // kinetic energy at cfl 0.3).
  // The rate (eq. 4) serves only this update, so it goes through a small buffer per block of
  // particles instead of an array per particle; the arithmetic is that of a whole-array rate.
  constexpr std::size_t kRateBlock = 1024;
  const std::size_t rate_blocks = (n + kRateBlock - 1) / kRateBlock;
#pragma omp parallel for schedule(static)
  for (std::size_t blk = 0; blk < rate_blocks; ++blk) {
    double drho[kRateBlock];
    const std::size_t first = blk * kRateBlock, len = std::min(kRateBlock, n - first);
    continuity_density_rate(L + 9 * first, rho + first, drho, len);  // (nested: serial in this thread)
    if (diffusion)
      for (std::size_t k = 0; k < len; ++k) drho[k] += diffusion_rate_[first + k];  // eq. 4a
    for (std::size_t k = 0; k < len; ++k) rho[first + k] += dt_ * drho[k];
  }
  jaumann_rotation(L, dt_, S, n);
  // Materials see the physical density: mass scaling multiplied the inertial one (eq. 24).
  const double* material_density = rho;
  if (settings_.mass_scaling != 1.0) {
    physical_density_.resize(n);
    const double inv_s = 1.0 / settings_.mass_scaling;
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) physical_density_[i] = rho[i] * inv_s;
    material_density = physical_density_.data();
  }
  // Every particle's source is rebuilt each step: the materials and the contact fill the mechanical
  // ones, the tools' share of the friction heat the attached thermal-only ones (eq. 91).
  if (heat_source) std::fill(heat_source, heat_source + count_, 0.0);
  for (const BodyRange& b : bodies_) {
    if (!b.mechanics) continue;
    MaterialBatch batch;
    batch.count = b.count;
    batch.dt = dt_;
    batch.velocity_gradient = L + 9 * b.first;
    batch.density = material_density + b.first;
    batch.deviatoric_stress = S + 6 * b.first;
    batch.pressure = p + b.first;
    batch.fields = &fields_;
    batch.first = b.first;
    batch.temperature = T ? T + b.first : nullptr;
    batch.heat_source = heat_source ? heat_source + b.first : nullptr;
    batch.time_scaling = settings_.time_scaling;
    materials_[b.material]->update_stress(batch);
    if (need_yield_) materials_[b.material]->yield_stress(batch, yield_scratch_.data() + b.first);
  }
  corrected_stress(p, S, settings_.momentum_correction == MomentumCorrection::None ? nullptr : correction,
                   settings_.momentum_correction == MomentumCorrection::Full, stress_c, n);
  if (second) second_order_stress(p, S, second_b, stress_b, n);
  if (artificial) {
    stress_over_density_squared(p, S, rho, artificial, n);
    artificial_stress(artificial, settings_.artificial_stress.epsilon, artificial, n);  // in place
  }
  const double* rho_e = rho;
  if (sym) {
    // The ghosts' A = sigma C and R transform as tensors, A' = Q A Q^T (eq. 31), and their
    // density is the source's new one, as for the real particles.
    symmetry_.fill_tensors(stress_c, n);
    if (artificial) symmetry_.fill_symmetric(artificial, n);
    rho_e = extend(ext_rho_, rho, 1);
  }
  if (artificial) {
    tension_bits_.resize((nt + 63) / 64);
    mark_tension(artificial, nt, tension_bits_.data());
  }
  // The volumes are those of the step's start (before the density update): the same V_j the
  // corrected gradient used, as the energy consistency of eq. 7 requires.
  momentum_rate(neighbours_, settings_.kernel, h_, settings_.viscosity, wave_speed_, xe, ve, me, rho_e, volume, stress_c,
                settings_.artificial_stress, artificial, artificial ? tension_bits_.data() : nullptr, a, n, failure,
                smoothing_lengths());
  // Its quadratic part, the dual of the second-order gradient (eq. 136).
  if (second) second_order_momentum_term(neighbours_, settings_.kernel, h_, xe, me, volume, stress_b, a, n);
  // Body force (gravity): the internal-work ledger below takes it out again so that it is not
  // booked as internal (eq. 47); added before the contact pass so that a sticking force can cancel it (eq. 18a).
  // g + A cos(omega t) at the step's time t^n, where the leapfrog evaluates every force (eq. 47a).
  body_now_ = body_acceleration_ + body_oscillation_ * std::cos(body_angular_frequency_ * time_);
  if (body_now_.squaredNorm() > 0.0) add_body_force(body_now_.data(), settings_.mass_scaling, a, n);
  std::fill(fc, fc + 3 * n, 0.0);
  if (!tools_.empty()) {
    const auto contact_start = std::chrono::steady_clock::now();
    ContactArrays ca;
    ca.x = x;
    ca.v = v;
    ca.mass = m;
    ca.acceleration = a;
    ca.yield = need_yield_ ? yield_scratch_.data() : nullptr;
    ca.n = n;
    ca.dt = dt_;
    ca.force = fc;
    ca.heat_source = heat_source;
    ca.mass_scaling = settings_.mass_scaling;
    ca.tool_takes_heat = any_attached_ ? tool_takes_heat_.data() : nullptr;
    ca.id = fields_.i64(field::id);
    // The pass scratch is dead after the momentum pass (until the next step's build): it lends the
    // contact pass the room for its 12 bytes of indices per particle.
    ca.borrow = scratch_;
    ca.smoothing_length = smoothing_lengths();  // each particle's own spacing (eq. 141)
    ca.spacing_per_h = 1.0 / settings_.h_over_dx;
    contacts_ = contact_.apply(tools_, ca);
    contact_time_s_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - contact_start).count();
  }
  // Internal energy: the work done against the internal forces (elastic storage, plastic and
  // viscous dissipation) with the step-centred velocity of the total acceleration, so that the
  // energy balance closes to round-off for a free body and stays unbiased against walls (eq. 27).
  const Eigen::Vector3d body_scaled = body_now_ / settings_.mass_scaling;
  internal_energy_ += internal_work(m, v, a, body_scaled.data(), tools_.empty() ? nullptr : fc, dt_, n);
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const double inv_m = 1.0 / m[i];
    for (int d = 0; d < 3; ++d) a[3 * i + d] += fc[3 * i + d] * inv_m;
  }
}

void Simulation::thermal_heat_flows(const std::vector<ToolHeatRecord>& tool_heat) {
  const std::size_t n = count_;
  const double* x = fields_.f64(field::position);
  const double* m = fields_.f64(field::mass);
  const double* rho = fields_.f64(field::density);
  const double* T = fields_.f64(field::temperature);
  const double* hc = fields_.f64(field::convection_coefficient);
  const double* heat_source = fields_.f64_if(field::heat_source);
  // Neighbours of every particle: the mechanics lists serve when all particles are mechanical
  // (they were just updated); thermal-only bodies need lists of their own.
  const NeighbourList* nl = &neighbours_;
  const bool sym = symmetry_.active();
  // With symmetry the thermal lists hold ghosts. Mechanical bodies only: the mechanics' ghosts
  // and lists serve. With thermal-only bodies: ghosts of every particle (thermal_symmetry_),
  // their positions refreshed every step since attached bodies move with their tool (eq. 31).
  const Symmetry& ghosts = sym && mechanical_count_ < n ? thermal_symmetry_ : symmetry_;
  const double* xe = x;
  if (mechanical_count_ < n) {
    // Own skin (theory section 7): a tool's attached body can move more per step than the workpiece.
    const double search = kernel_support_radius(h_), skin = settings_.thermal_neighbour_skin * h_;
    const bool rebuild = thermal_lists_stale_ || thermal_neighbours_.needs_rebuild(x, n, search, skin);
    if (sym) {
      if (rebuild) thermal_symmetry_.select(x, n, search + skin);
      xe = extend(ext_thermal_x_, x, 3, true, thermal_symmetry_, n);
      if (rebuild) thermal_neighbours_.rebuild(xe, n + thermal_symmetry_.ghost_count(), search, skin, n);
    } else if (rebuild) {
      thermal_neighbours_.rebuild(x, n, search, skin, SIZE_MAX, {}, point_supports(n));
    }
    thermal_lists_stale_ = false;
    nl = &thermal_neighbours_;
  } else if (sym) {
    xe = ext_x_.data();  // filled by mechanics_rates() this step; positions have not moved since
  }
  // With symmetry x, V, T and k are read from extended arrays (eq. 31), which also keeps the cuts
  // from counting as free surface in the convection area.
  const std::size_t nt = sym ? n + ghosts.ghost_count() : n;
  thermal_volume_.resize(nt);
  conductivity_.resize(nt);
  double* volume = thermal_volume_.data();
  particle_volume(m, rho, volume, n);
  evaluate_thermal_properties();
  const double* Te = T;
  if (sym) {
    ghosts.fill_scalars(volume, n);
    ghosts.fill_scalars(conductivity_.data(), n);
    Te = extend(ext_T_, T, 1, false, ghosts, n);
  }
  // The tools' share of the friction heat into their attached particles near each contact (eq. 91),
  // over the thermal lists (every particle's neighbours, just refreshed above); heat meant for a
  // ghost goes to its source, the particle whose image it is.
  if (any_attached_ && heat_source)
    deposit_tool_heat(tool_heat, *nl, settings_.kernel, h_, xe, m, settings_.mass_scaling,
                      fields_.i64(field::body), bodies_, fields_.f64(field::heat_source), n,
                      sym ? ghosts.sources().data() : nullptr, smoothing_lengths());
  std::fill(heat_W_.begin(), heat_W_.end(), 0.0);
  heat_conduction(*nl, settings_.kernel, h_, xe, volume, Te, conductivity_.data(), heat_W_.data(), n,
                  smoothing_lengths());  // eq. 20
  if (any_convection_) {
    surface_area(*nl, settings_.kernel, h_, xe, volume, area_.data(), n, smoothing_lengths());  // eq. 22
    convection(hc, area_.data(), T, settings_.thermal.ambient_temperature_K, heat_W_.data(), n);  // eq. 23
  }
}

void Simulation::thermal_rates() {
  if (settings_.thermal.subcycling) {
    thermal_rates_subcycled();
    return;
  }
  thermal_heat_flows(contact_.tool_heat());
  const double* m = fields_.f64(field::mass);
  const double* heat_source = fields_.f64_if(field::heat_source);
  double* dT = fields_.f64(field::temperature_rate);
  // m c dT/dt = f (Q_conduction + Q_convection) + m q_plastic with physical masses; time scaling f
  // speeds up the heat flow to keep pace with the f-times faster deformation (eq. 25).
  const double f = settings_.time_scaling, inv_s = 1.0 / settings_.mass_scaling;
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < count_; ++i) {
    const double physical_mass = m[i] * inv_s;
    const double source = heat_source ? physical_mass * heat_source[i] : 0.0;
    dT[i] = (f * heat_W_[i] + source) / (physical_mass * specific_heat_[i]);
  }
}

void Simulation::thermal_rates_subcycled() {
  // Eq. 26b. The heat sources of the workpiece (plastic work, its share of the friction heat) act
  // every step through dT, at the properties of the current temperatures, so that softening follows
  // the heating without delay. The tools' share of the friction heat waits, per contact particle,
  // in the pending fields. Conduction, convection and that share act together on a thermal step of
  // length tau, the time since the last one, taken before the next mechanical step would carry tau
  // past the conduction limit dt_thermal (eq. 26): explicit conduction with tau <= dt_thermal is as
  // stable as with dt. Energy is conserved: every source term enters once, with its own duration.
  const std::size_t n = count_, nm = mechanical_count_;
  const double* m = fields_.f64(field::mass);
  const double* heat_source = fields_.f64_if(field::heat_source);
  double* dT = fields_.f64(field::temperature_rate);
  double* T = fields_.f64(field::temperature);
  const double f = settings_.time_scaling, inv_s = 1.0 / settings_.mass_scaling;
  pending_fields_.assign(pending_tool_heat_field_.size(), nullptr);  // looked up once per step, not per contact
  for (std::size_t t = 0; t < pending_tool_heat_field_.size(); ++t)
    if (!pending_tool_heat_field_[t].empty()) pending_fields_[t] = fields_.f64(pending_tool_heat_field_[t]);
  for (const ToolHeatRecord& r : contact_.tool_heat()) pending_fields_[r.tool][r.particle] += r.heat_W * dt_;
  thermal_pending_s_ += dt_;
  // No conducting particle (dt_thermal infinite): the tools' heat still goes in, every step.
  if (thermal_pending_s_ + dt_ > dt_thermal_ || !std::isfinite(dt_thermal_)) {
    const double tau = thermal_pending_s_;
    // The pending heat as records of mean power over tau, for the deposit of eq. 91.
    pending_tool_heat_.clear();
    for (std::size_t t = 0; t < pending_fields_.size(); ++t) {
      double* pending = pending_fields_[t];
      if (!pending) continue;
      for (std::size_t i = 0; i < nm; ++i)
        if (pending[i] != 0.0) {
          pending_tool_heat_.push_back({t, i, pending[i] / tau});
          pending[i] = 0.0;
        }
    }
    thermal_heat_flows(pending_tool_heat_);
    // Workpiece sources are in dT below; the attached bodies' source is the deposit just made.
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      const double physical_mass = m[i] * inv_s;
      const double source = heat_source && i >= nm ? physical_mass * heat_source[i] : 0.0;
      T[i] += tau * (f * heat_W_[i] + source) / (physical_mass * specific_heat_[i]);
    }
    thermal_pending_s_ = 0.0;
  }
  evaluate_thermal_properties();
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) dT[i] = heat_source && i < nm ? heat_source[i] / specific_heat_[i] : 0.0;
}

double* Simulation::extend(std::vector<double>& ext, const double* src, int components, bool position,
                           const Symmetry& ghosts, std::size_t n) {
  const std::size_t c = static_cast<std::size_t>(components);
  ext.resize((n + ghosts.ghost_count()) * c);
  std::copy(src, src + n * c, ext.begin());
  if (components == 1) ghosts.fill_scalars(ext.data(), n);
  else if (position) ghosts.fill_positions(ext.data(), n);
  else ghosts.fill_vectors(ext.data(), n);
  return ext.data();
}

void Simulation::evaluate_thermal_properties() {
  const double* T = fields_.f64(field::temperature);
  for (const BodyRange& b : bodies_) {
    ThermalBatch batch{b.count, T + b.first, conductivity_.data() + b.first, specific_heat_.data() + b.first,
                       &fields_, b.first};
    materials_[b.material]->thermal_properties(batch);
  }
}

void Simulation::integrate() {
  // Symplectic Euler (leapfrog with velocities at half steps): v^{n+1/2} = v^{n-1/2} + dt a^n,
  // x^{n+1} = x^n + dt v^{n+1/2}  (eq. 14); with XSPH the particles move with the smoothed
  // velocity (eq. 19).
  const std::size_t n = mechanical_count_;
  if (n > 0) {
    double* x = fields_.f64(field::position);
    double* v = fields_.f64(field::velocity);
    const double* a = fields_.f64(field::acceleration);
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < 3 * n; ++i) v[i] += dt_ * a[i];
    if (settings_.xsph > 0.0) {
      xsph_scratch_.resize(3 * n);
      if (symmetry_.active())  // ghosts: the new velocities; x, m, rho as extended this step
        xsph_correction(neighbours_, settings_.kernel, h_, settings_.xsph, ext_x_.data(), extend(ext_v_, v, 3),
                        ext_m_.data(), ext_rho_.data(), xsph_scratch_.data(), n);
      else
        xsph_correction(neighbours_, settings_.kernel, h_, settings_.xsph, x, v, fields_.f64(field::mass),
                        fields_.f64(field::density), xsph_scratch_.data(), n);
#pragma omp parallel for schedule(static)
      for (std::size_t i = 0; i < 3 * n; ++i) x[i] += dt_ * (v[i] + xsph_scratch_[i]);
    } else {
#pragma omp parallel for schedule(static)
      for (std::size_t i = 0; i < 3 * n; ++i) x[i] += dt_ * v[i];
    }
  }
  if (settings_.thermal.enabled) {
    double* T = fields_.f64(field::temperature);
    const double* dT = fields_.f64(field::temperature_rate);
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < count_; ++i) T[i] += dt_ * dT[i];
  }
}

void Simulation::step() {
  dt_ = stable_time_step();
  if (step_ == 0) dt_initial_ = dt_;

  ProcessContext ctx = context();
  controllers_.update(time_, dt_);
  process_->before_step(ctx);
  for (auto& tool : tools_) tool.begin_step(time_, dt_);  // scheduled tool motion (eq. 45)
  if (step_ == 0) initial_kinetic_energy_ = kinetic_energy();  // after the process set initial velocities

  if (mechanical_count_ > 0) mechanics_rates();
  if (settings_.thermal.enabled) thermal_rates();
  // Prescribed velocities do work on the bodies (a piston pushing a bar), and they move the centre
  // of the constrained particles' step that the internal energy was booked with (eq. 27a): keep
  // v + dt a and a as the integrator would have had them.
  const std::size_t nm = process_->constrains_velocities() ? mechanical_count_ : 0;
  const double* v = nm > 0 ? fields_.f64(field::velocity) : nullptr;
  const double* a = nm > 0 ? fields_.f64(field::acceleration) : nullptr;
  if (nm > 0) {
    constrained_scratch_.resize(6 * nm);
    double* predicted = constrained_scratch_.data();
    double* total = predicted + 3 * nm;
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < 3 * nm; ++i) {
      predicted[i] = v[i] + dt_ * a[i];
      total[i] = a[i];
    }
  }
  process_->apply_constraints(ctx);
  if (nm > 0) {
    const Eigen::Vector3d body_scaled = body_now_ / settings_.mass_scaling;
    const ConstraintEnergy e = constraint_energy(
        fields_.f64(field::mass), constrained_scratch_.data(), constrained_scratch_.data() + 3 * nm, v, a,
        body_scaled.data(), tools_.empty() ? nullptr : fields_.f64(field::contact_force), dt_, nm);
    constraint_work_J_ += e.work_J;
    internal_energy_ += e.internal_energy_correction_J;
  }
  integrate();
  if (mechanical_count_ > 0 && body_now_.squaredNorm() > 0.0) {
    // Work of the body force with the step-centred velocity, sum m g . v^{n+1/2} dt (eq. 47): the
    // energy ledger of check_stability() counts it like the tools' work.
    body_force_work_J_ += body_force_work(body_now_.data(), settings_.mass_scaling, fields_.f64(field::mass),
                                          fields_.f64(field::velocity), mechanical_count_, dt_);
  }
  for (auto& tool : tools_) {
    tool.work_J += tool.power_W * dt_;
    tool.advance(dt_);
  }
  // Attached thermal bodies follow their tool's new pose exactly (eq. 90).
  if (any_attached_) {
    double* x = fields_.f64(field::position);
    const double* ref = fields_.f64(kToolReferencePosition);
    for (const BodyRange& b : bodies_)
      if (b.attached_tool >= 0) {
        place_on_tool(tools_[static_cast<std::size_t>(b.attached_tool)], ref + 3 * b.first, x + 3 * b.first, b.count);
        // In a sector, particles the tool turned across a cut re-enter through its image; the
        // reference positions turn with them (a rotation about z commutes with the pose, eq. 90).
        if (symmetry_.active()) symmetry_.wrap(fields_, b.first, b.first + b.count);
      }
  }
  // Friction heat of each tool and the share its thermal particles took, summed over the steps:
  // the ledger the heat content of the bodies is checked against (docs/verification.md section 13).
  const auto& contact_stats = contact_.tool_stats();
  for (std::size_t t = 0; t < tools_.size() && t < contact_stats.size(); ++t) {
    tool_friction_heat_J_[t] += contact_stats[t].friction_heat_W * dt_;
    tool_heat_to_tool_J_[t] += contact_stats[t].heat_to_tool_W * dt_;
  }
  time_ += dt_;
  ++step_;
  ctx.time_s = time_;
  ctx.step = step_;
  process_->measure(ctx);
  check_stability();
}

double Simulation::kinetic_energy() const {
  if (mechanical_count_ == 0) return 0.0;
  return sphforge::kinetic_energy(fields_.f64(field::mass), fields_.f64(field::velocity), mechanical_count_);
}

std::vector<std::string> Simulation::history_header() const {
  std::vector<std::string> h = {"time_s", "step_1", "dt_s", "dt_cfl_s", "dt_contact_s", "neighbour_builds_1",
                                "kinetic_energy_J", "tool_work_J", "kinetic_to_work_ratio_1", "contacts_1",
                                "sticking_fraction_1", "internal_energy_J", "kinetic_to_internal_ratio_1"};
  static_assert(kRatioColumn == 8);
  if (settings_.thermal.enabled) {
    h.push_back("dt_thermal_s");
    h.push_back("temperature_max_K");
    h.push_back("temperature_min_K");
    h.push_back("temperature_mean_K");
  }
  for (const auto& t : tools_) {
    h.push_back(t.name() + "_force_x_N");
    h.push_back(t.name() + "_force_y_N");
    h.push_back(t.name() + "_force_z_N");
    h.push_back(t.name() + "_torque_Nm");
    h.push_back(t.name() + "_contacts_1");
    h.push_back(t.name() + "_penetration_mean_m");
    h.push_back(t.name() + "_penetration_max_m");
    h.push_back(t.name() + "_sticking_fraction_1");
    h.push_back(t.name() + "_friction_heat_W");
    h.push_back(t.name() + "_heat_to_workpiece_W");
  }
  if (settings_.thermal.enabled)
    for (std::size_t k = 0; k < tools_.size(); ++k) {
      h.push_back(tools_[k].name() + "_friction_heat_J");
      if (!tool_takes_heat_[k]) continue;
      h.push_back(tools_[k].name() + "_heat_to_tool_W");
      h.push_back(tools_[k].name() + "_heat_to_tool_J");
    }
  for (const auto& t : tools_) {
    h.push_back(t.name() + "_position_m");
    h.push_back(t.name() + "_angle_rad");
  }
  for (const auto& c : process_columns_) h.push_back(c.name);
  for (const auto& c : controller_columns_) h.push_back(c.name);
  return h;
}

std::vector<double> Simulation::history_row() const {
  // Kinetic energy against the work the tools put in: the check that mass/time scaling keeps
  // the process quasi-static (the papers' rule of thumb: below about 0.1).
  double work = 0.0;
  for (const auto& t : tools_) work += t.work_J;
  const double ke = kinetic_energy();
  std::vector<double> r = {time_, static_cast<double>(step_), dt_, dt_cfl_, dt_contact_,
                           static_cast<double>(neighbours_.builds()), ke, work, work > 0.0 ? ke / work : 0.0,
                           static_cast<double>(contacts_), contact_.sticking_fraction(), internal_energy_,
                           internal_energy_ > 0.0 ? ke / internal_energy_ : 0.0};
  if (settings_.thermal.enabled) {
    const double* T = fields_.f64(field::temperature);
    const auto [lo, hi] = std::minmax_element(T, T + count_);
    r.push_back(dt_thermal_);
    r.push_back(*hi);
    r.push_back(*lo);
    // Mass-weighted mean over every particle (all bodies, thermal-only ones included).
    const double* m = fields_.f64(field::mass);
    double mt = 0.0, msum = 0.0;
    for (std::size_t i = 0; i < count_; ++i) {
      mt += m[i] * T[i];
      msum += m[i];
    }
    r.push_back(mt / msum);
  }
  const auto& stats = contact_.tool_stats();
  for (std::size_t k = 0; k < tools_.size(); ++k) {
    const auto& t = tools_[k];
    r.push_back(t.reaction_force_N.x());
    r.push_back(t.reaction_force_N.y());
    r.push_back(t.reaction_force_N.z());
    r.push_back(t.reaction_torque_Nm);
    const ToolContactStats st = k < stats.size() ? stats[k] : ToolContactStats{};
    r.push_back(static_cast<double>(st.contacts));
    r.push_back(st.penetration_mean_m);
    r.push_back(st.penetration_max_m);
    r.push_back(st.sticking_fraction);
    r.push_back(st.friction_heat_W);
    r.push_back(st.heat_to_workpiece_W);
  }
  if (settings_.thermal.enabled)
    for (std::size_t k = 0; k < tools_.size(); ++k) {
      r.push_back(tool_friction_heat_J_[k]);
      if (!tool_takes_heat_[k]) continue;
      r.push_back(k < stats.size() ? stats[k].heat_to_tool_W : 0.0);
      r.push_back(tool_heat_to_tool_J_[k]);
    }
  for (const auto& t : tools_) {
    r.push_back(t.axial_offset_m);
    r.push_back(t.angle_rad);
  }
  for (const auto& c : process_columns_) r.push_back(*c.value);
  for (const auto& c : controller_columns_) r.push_back(*c.value);
  return r;
}

// --- the run ----------------------------------------------------------------------------------------
void Simulation::prepare_run() {
  if (step_ > 0) return;
  ProcessContext ctx = context();
  process_->initialize(ctx);
  if (settings_.thermal.enabled) {
    const double* hc = fields_.f64(field::convection_coefficient);
    any_convection_ = std::any_of(hc, hc + count_, [](double c) { return c > 0.0; });
    evaluate_thermal_properties();  // for the first thermal time step
  }
  // The domain a particle may not leave: the initial scene enlarged on every side by
  // numerics.domain_margin, by default by its own size (at least 100 spacings). A particle
  // beyond it was thrown out by an instability; a long extrudate needs a larger margin.
  const double* x = fields_.f64(field::position);
  for (int d = 0; d < 3; ++d) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (std::size_t i = 0; i < count_; ++i) {
      lo = std::min(lo, x[3 * i + d]);
      hi = std::max(hi, x[3 * i + d]);
    }
    domain_min_[d] = lo;
    domain_max_[d] = hi;
  }
  double size = 100.0 * spacing_;
  for (int d = 0; d < 3; ++d) size = std::max(size, domain_max_[d] - domain_min_[d]);
  if (settings_.domain_margin_m >= 0.0) size = settings_.domain_margin_m;
  domain_margin_used_m_ = size;
  for (int d = 0; d < 3; ++d) {
    domain_min_[d] -= size;
    domain_max_[d] += size;
  }
}

Simulation::RunResult Simulation::run(const fs::path& out_dir, ProgressMode progress_mode) {
  if (settings_.threads > 0) omp_set_num_threads(settings_.threads);
  fs::create_directories(out_dir);
  io::ParticleSeriesWriter particle_writer(out_dir);
  io::ToolSeriesWriter tool_writer(out_dir);
  io::HistoryWriter history(out_dir / "history.csv", history_header());
  Progress progress(progress_mode, time_, step_, settings_.end_time_s);  // time_, step_: the checkpoint's on a restart

  // Arrays a frame writes besides the fields. The friction laws' memory, kept by the contact pass
  // for the touching particles only, is written like a field (friction_history_<tool>, 3 per
  // particle, zero where none; eq. 18b).
  auto frame_arrays = [&] {
    std::vector<io::ParticleArray> out;
    // L of the state the frame shows (the step reused its storage), with the density rate and the
    // gradient condition of that state.
    std::vector<double> drho, condition;
    output_velocity_gradient(drho, condition);
    if (mechanical_count_ > 0) out.push_back({field::density_rate, 1, "kg/m^3/s", std::move(drho)});
    if (mechanical_count_ > 0 && !condition.empty())
      out.push_back({field::gradient_condition, 1, "1", std::move(condition)});
    for (std::size_t t = 0; t < tools_.size(); ++t) {
      if (!tool_laws_[t]->needs_history()) continue;
      io::ParticleArray a{"friction_history_" + tools_[t].name(), 3, "N", std::vector<double>(3 * count_)};
      if (t < contact_.history_tools())
        contact_.friction_history_dense(t, fields_.i64(field::id), count_, a.values.data());
      out.push_back(std::move(a));
    }
    return out;
  };
  double last_frame_time = -1.0, last_history_time = -1.0;
  auto write_frame = [&] {
    particle_writer.write(cursor_.frame, time_, fields_, count_, frame_arrays());
    tool_writer.write(cursor_.frame, time_, tools_);
    last_frame_time = time_;
    ++cursor_.frame;
  };
  // history.csv reaches the disk at every frame and checkpoint, and with the first row after each 10 s
  // of wall time, so that a long run can be followed while it runs.
  auto last_history_flush = std::chrono::steady_clock::now();
  auto write_history = [&] {
    const std::vector<double> row = history_row();
    history.append(row);
    last_history_time = time_;
    const auto now = std::chrono::steady_clock::now();
    if (now - last_history_flush > std::chrono::seconds(10)) {
      history.flush();
      last_history_flush = now;
    }
    // Largest kinetic/work ratio once the process is under way (after the first 10 % of the run,
    // when both energies are still tiny and their ratio meaningless).
    if (time_ >= 0.1 * settings_.end_time_s)
      cursor_.max_kinetic_to_work = std::max(cursor_.max_kinetic_to_work, row[kRatioColumn]);
  };
  const bool restarted = !restarted_from_.empty();
  std::size_t history_rows_copied = 0;
  if (restarted) {
    // The rows the run wrote up to its checkpoint, so that this history.csv covers the whole run,
    // and its frames (left in their folder, listed by relative path) so that the .pvd files do.
    last_frame_time = last_history_time = time_;
    const fs::path earlier = restarted_from_.parent_path();
    history_rows_copied = io::copy_history_rows(earlier / "history.csv", history_header(), time_, history);
    particle_writer.continue_series(earlier / "particles.pvd", time_);
    tool_writer.continue_series(earlier / "tools.pvd", time_);
  } else {
    prepare_run();
    // Measure once so that the first history row is meaningful.
    ProcessContext ctx0 = context();
    process_->measure(ctx0);
    write_frame();
    write_history();
    cursor_.next_output = settings_.output_interval_s;
    cursor_.next_history = settings_.history_interval_s;
    cursor_.next_checkpoint = settings_.checkpoint_interval_s;
  }
  double last_checkpoint_time = restarted ? time_ : -1.0;

  RunResult result;
  std::string status = "completed";
  const auto wall_start = std::chrono::steady_clock::now();
  auto wall_so_far = [&] {
    return wall_before_restart_s_ + std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  };
  try {
    while (time_ < settings_.end_time_s * (1.0 - 1e-12)) {
      if (settings_.max_steps > 0 && step_ >= settings_.max_steps) { status = "max_steps"; break; }
      if (controllers_.finished()) { status = "phases_ended"; break; }
      ProcessContext ctx = context();
      if (process_->finished(ctx)) { status = "process_finished"; break; }
      step();
      if (time_ >= cursor_.next_history) {
        write_history();
        while (cursor_.next_history <= time_) cursor_.next_history += settings_.history_interval_s;
      }
      if (time_ >= cursor_.next_output) {
        write_frame();
        history.flush();
        while (cursor_.next_output <= time_) cursor_.next_output += settings_.output_interval_s;
      }
      // Last in the step, after everything that writes state (the frame's velocity gradient), with
      // the cursor already advanced: the checkpoint holds exactly what the next step starts from.
      if (settings_.checkpoint_interval_s > 0.0 && time_ >= cursor_.next_checkpoint) {
        while (cursor_.next_checkpoint <= time_) cursor_.next_checkpoint += settings_.checkpoint_interval_s;
        history.flush();
        write_checkpoint(out_dir, wall_so_far());
        last_checkpoint_time = time_;
      }
      progress.update(time_, step_);
    }
    progress.update(time_, step_, true);
  } catch (const InstabilityError& e) {
    progress.finish();
    status = "unstable";
    result.exit_code = 3;
    result.message = e.what();
    // Last frame for diagnosis (the state that blew up).
    try { write_frame(); } catch (...) {}
    // Full-precision state of every field for diagnosis (h5dump / h5py).
    try {
      io::write_particle_dump(out_dir / "instability_dump.h5", fields_, count_, time_, step_, frame_arrays());
      result.message += "; state dumped to instability_dump.h5";
    } catch (const std::exception&) {
    }
  }
  progress.finish();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  // The final state, unless the last step has just written it.
  if (result.exit_code == 0 && time_ > last_frame_time) write_frame();
  if (time_ > last_history_time) write_history();
  history.flush();
  // A final checkpoint, so that a finished run can be extended (a restart with a later run.end_time).
  if (result.exit_code == 0 && settings_.checkpoint_interval_s > 0.0 && time_ > last_checkpoint_time)
    write_checkpoint(out_dir, wall_before_restart_s_ + wall);

  json summary;
  summary["case"] = settings_.case_name;
  summary["case_file"] = case_file_;
  summary["status"] = status;
  if (!result.message.empty()) summary["diagnosis"] = result.message;
  summary["particles"] = count_;
  summary["steps"] = step_;
  summary["simulated_time_s"] = time_;
  // Wall time and throughput of this invocation (after a restart: of the steps since the checkpoint).
  summary["wall_time_s"] = wall;
  summary["particle_steps_per_s"] =
      wall > 0 ? static_cast<double>(count_) * static_cast<double>(step_ - restart_step_) / wall : 0.0;
  if (restarted)
    summary["restart"] = {{"checkpoint", restarted_from_.string()},
                          {"step", restart_step_},
                          {"time_s", restart_time_s_},
                          {"wall_time_before_s", wall_before_restart_s_},
                          {"wall_time_total_s", wall_before_restart_s_ + wall},
                          {"history_rows_copied", history_rows_copied}};
  if (settings_.checkpoint_interval_s > 0.0) summary["checkpoints"] = cursor_.checkpoint;
  summary["threads"] = omp_get_max_threads();
  summary["backend"] = backend_description();
  summary["frames"] = cursor_.frame;
  if (symmetry_.active()) {
    // Every quantity of the outputs (particles, history, tool reactions, process metrics) is the
    // simulated part's; the full body's reactions are `multiplier` times the axial ones.
    summary["symmetry"] = {{"multiplier", symmetry_.multiplier()},
                           {"ghosts", symmetry_.ghost_count()},
                           {"sector_angle_deg", settings_.symmetry.sector_angle_rad * 180.0 / std::numbers::pi},
                           {"mirror_planes", settings_.symmetry.mirror_planes.size()}};
  }
  summary["kinetic_to_work_ratio_max"] = cursor_.max_kinetic_to_work;
  if (const json phases = controllers_.summary(); !phases.empty()) summary["phases"] = phases;
  // The contact pass's share of the wall time (culling, distances, friction laws, reactions).
  summary["contact_time_s"] = contact_time_s_;
  summary["metrics"] = process_->metrics();
  // Return mappings that hit their iteration cap (docs/theory.md eq. 34): 0 in a sound run.
  long long failed_returns = failed_returns_before_restart_;
  for (const auto& material : materials_) failed_returns += material->failed_returns();
  summary["material_failed_returns"] = failed_returns;
  json versions;
  versions["core"] = kCoreVersion;
  versions["plugin_abi"] = kPluginAbiVersion;
  json plugins = json::object();
  for (const LoadedPlugin* p : loader_.loaded())
    plugins[p->descriptor->name] = {{"kind", to_string(p->descriptor->kind)}, {"version", p->descriptor->version}};
  versions["plugins"] = plugins;
  summary["versions"] = versions;
  io::write_summary(out_dir / "summary.json", summary);
  return result;
}

}  // namespace sphforge
