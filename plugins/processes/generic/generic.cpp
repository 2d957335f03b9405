// Process plugin `generic`: scenes built from primitives, for verification problems and quick
// experiments. Bodies (box, cylinder, tube, disc) with an initial velocity, rotation, cantilever
// mode shape or (deviatoric) stress; regions with prescribed velocity, rigid rotation or
// temperature; rigid planes normal to z moving at a constant speed; rigid tools of any shape
// (plane, cylinder, filleted profile of revolution, STL mesh) with constant, scheduled or
// commanded motion along and about z (docs/theory.md section 3.1); probes that follow one particle and write its displacement,
// velocity, stress or temperature to the history. Geometry conventions: docs/processes/generic.md.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <filesystem>
#include <random>

#include <Eigen/Geometry>

#include "sphforge/plugin.hpp"
#include "sphforge/units.hpp"

namespace {

using namespace sphforge;
using Vec = Eigen::Vector3d;

/// Reads a 3-vector given as an array of three numbers (SI) or quantity strings in `unit`.
Vec vector3(const ParamValues& p, const std::string& name, const std::string& unit) {
  const std::vector<double> v = p.quantities(name, 3, unit);
  return {v[0], v[1], v[2]};
}

/// Reads a symmetric tensor given as six numbers (SI) or quantity strings in `unit`, VTK order
/// (xx, yy, zz, xy, yz, xz).
std::array<double, 6> tensor6(const ParamValues& p, const std::string& name, const std::string& unit) {
  const std::vector<double> v = p.quantities(name, 6, unit);
  return {v[0], v[1], v[2], v[3], v[4], v[5]};
}

/// True when an optional array or object parameter was given (absent ones default to empty).
bool given(const ParamValues& p, const std::string& name) {
  if (!p.has(name)) return false;
  const json& v = p.raw(name);
  return !v.is_null() && !((v.is_array() || v.is_object()) && v.empty());
}

const ParamSpecs& body_specs() {
  static const ParamSpecs specs = {
      ParamSpec::string("name", std::nullopt, "body name (history columns, `body` field)"),
      ParamSpec::string("shape", std::nullopt, "primitive", {"box", "cylinder", "tube", "disc", "sphere"}),
      ParamSpec::array("min", "box: lower corner [x, y, z] (m)"),
      ParamSpec::array("max", "box: upper corner [x, y, z] (m)"),
      ParamSpec::array("center", "cylinder/tube/disc: centre of the base [x, y, z] (m), axis along z; sphere: centre"),
      ParamSpec::number("radius", "m", 0.0, "cylinder/disc/sphere radius; tube outer radius", 0.0),
      ParamSpec::number("inner_radius", "m", 0.0, "tube inner radius", 0.0),
      ParamSpec::number("height", "m", 0.0, "cylinder/tube height, disc thickness (along z)", 0.0),
      ParamSpec::string("material", std::string(), "key in the case's \"materials\" (empty: \"material\")"),
      ParamSpec::boolean("mechanics", true, "false: thermal-only particles (conduction only; move only when attached)"),
      ParamSpec::string("attached_to", std::string(),
                        "thermal-only bodies: name of the tool or plane they belong to; they move rigidly with it "
                        "and take its share of the friction heat (docs/contact.md, theory eqs. 90-91)"),
      ParamSpec::array("velocity", "initial velocity [vx, vy, vz] (m/s)"),
      ParamSpec::array("angular_velocity", "initial rigid rotation [wx, wy, wz] (rad/s) about `center`"),
      ParamSpec::object("velocity_profile",
                        "initial cantilever first-mode velocity: {axis_start, length, amplitude, direction}"),
      ParamSpec::array("initial_stress",
                       "uniform initial Cauchy stress [xx, yy, zz, xy, yz, xz] (Pa); must be deviatoric (traceless): "
                       "the equation of state takes the pressure from the density"),
      ParamSpec::number("temperature", "K", -1.0, "initial temperature (thermal cases; -1: thermal default)"),
      ParamSpec::number("convection_coefficient", "W/(m^2*K)", -1.0,
                        "heat transfer coefficient of this body's free surface (-1: thermal default)"),
  };
  return specs;
}

const ParamSpecs& profile_specs() {
  static const ParamSpecs specs = {
      ParamSpec::number("axis_start", "m", std::nullopt, "x of the clamped root (the beam lies along +x)"),
      ParamSpec::number("length", "m", std::nullopt, "free length L", 0.0),
      ParamSpec::number("amplitude", "m/s", std::nullopt, "velocity at the free end"),
      ParamSpec::string("direction", std::string("y"), "velocity direction", {"x", "y", "z"}),
  };
  return specs;
}

const ParamSpecs& region_specs() {
  static const ParamSpecs specs = {
      ParamSpec::string("name", std::nullopt, "region name"),
      ParamSpec::string("body", std::string(), "restrict to this body (empty: every body)"),
      ParamSpec::array("min", "lower corner of the region's box [x, y, z] (m)", true),
      ParamSpec::array("max", "upper corner of the region's box [x, y, z] (m)", true),
      ParamSpec::array("velocity", "prescribed velocity [vx, vy, vz] (m/s); [0, 0, 0] clamps"),
      ParamSpec::array("angular_velocity",
                       "prescribed rigid rotation [wx, wy, wz] (rad/s) about `center` (added to `velocity`): the "
                       "particles move exactly on their circles and see the exact spin as velocity gradient"),
      ParamSpec::array("center", "centre of the prescribed rotation [x, y, z] (m; default the origin)"),
      ParamSpec::number("temperature", "K", -1.0, "prescribed temperature (-1: free)"),
      ParamSpec::number("convection_coefficient", "W/(m^2*K)", -1.0, "surface coefficient here (-1: unchanged)"),
  };
  return specs;
}

const ParamSpecs& plane_specs() {
  static const ParamSpecs specs = {
      ParamSpec::string("name", std::nullopt, "tool name (history columns <name>_force_z_N, ...)"),
      ParamSpec::number("z", "m", std::nullopt, "initial height of the plane"),
      ParamSpec::string("side", std::string("above"), "where the workpiece is", {"above", "below"}),
      ParamSpec::number("radius", "m", 1.0, "extent of the plane (a disc about the z axis)", 0.0),
      ParamSpec::number("velocity", "m/s", 0.0, "constant velocity along +z"),
      ParamSpec::number("angular_velocity", "rad/s", 0.0, "rotation about the z axis"),
  };
  return specs;
}

const ParamSpecs& tool_specs() {
  static const ParamSpecs specs = {
      ParamSpec::string("name", std::nullopt, "tool name (history columns <name>_force_z_N, <name>_position_m, ...)"),
      ParamSpec::string("shape", std::nullopt, "surface", {"plane", "cylinder", "profile", "stl"}),
      ParamSpec::array("point", "plane: a point of the plane [x, y, z] (m)"),
      ParamSpec::array("normal", "plane: normal towards the workpiece [nx, ny, nz] (any length)"),
      ParamSpec::number("half_size", "m", 1.0, "plane: half-width of the square over which it acts", 0.0),
      ParamSpec::number("radius", "m", 0.0, "cylinder: radius", 0.0),
      ParamSpec::number("z_min", "m", 0.0, "cylinder: lower end"),
      ParamSpec::number("z_max", "m", 0.0, "cylinder: upper end"),
      ParamSpec::string("side", std::string("inside"), "cylinder: where the workpiece is", {"inside", "outside"}),
      ParamSpec::array("points", "profile: [[r, z], ...] (m), workpiece on the left when walked in order"),
      ParamSpec::number("fillet_radius", "m", 0.0, "profile: radius of the arcs rounding the corners", 0.0),
      ParamSpec::array("fillet_corners", "profile: indices of the rounded vertices (default: every interior one)"),
      ParamSpec::string("file", std::string(), "stl: path of the STL file (relative paths: from the case file)"),
      ParamSpec::number("scale", "1", 1.0, "stl: factor from the file's coordinates to metres", 0.0),
      ParamSpec::number("position", "m", 0.0, "initial translation along +z"),
      ParamSpec::number("angle", "rad", 0.0, "initial rotation about z"),
      ParamSpec::number("axial_velocity", "m/s", 0.0, "constant velocity along +z (initial command value)"),
      ParamSpec::number("angular_velocity", "rad/s", 0.0, "constant rotation speed about z (initial command value)"),
      ParamSpec::array("axial_schedule", "piecewise-linear axial velocity [[t, v], ...] (s, m/s)"),
      ParamSpec::array("angular_schedule", "piecewise-linear angular velocity [[t, w], ...] (s, rad/s)"),
      ParamSpec::boolean("command", false,
                         "true: controllers command <name>_axial_velocity (m/s) and <name>_angular_velocity (rad/s)"),
  };
  return specs;
}

/// A tool of the `tools` array (docs/processes/generic.md), in its initial pose.
RigidTool make_tool(const ParamValues& q) {
  const std::string name = q.string("name"), shape = q.string("shape");
  std::optional<RigidTool> tool;
  if (shape == "plane") {
    if (!given(q, "point") || !given(q, "normal")) q.fail("shape", "a plane needs point and normal");
    const Vec normal = vector3(q, "normal", "1");
    if (!(normal.norm() > 0.0)) q.fail("normal", "must not be zero");
    tool = RigidTool::plane(name, vector3(q, "point", "m"), normal, q.number("half_size"));
  } else if (shape == "cylinder") {
    if (!(q.number("radius") > 0.0)) q.fail("radius", "a cylinder needs a positive radius");
    if (!(q.number("z_max") > q.number("z_min"))) q.fail("z_max", "must exceed z_min");
    tool = RigidTool::cylinder(name, q.number("radius"), q.number("z_min"), q.number("z_max"), q.string("side") == "inside");
  } else if (shape == "profile") {
    if (!given(q, "points")) q.fail("shape", "a profile needs points");
    std::vector<Eigen::Vector2d> points;
    for (const auto& [r, z] : q.pairs("points", "m", "m")) points.emplace_back(r, z);
    std::vector<std::size_t> corners;
    if (given(q, "fillet_corners")) {
      const json& c = q.raw("fillet_corners");
      for (std::size_t k = 0; k < c.size(); ++k) {
        if (!c[k].is_number_integer() || c[k].get<long long>() < 0)
          q.fail("fillet_corners", "entry " + std::to_string(k) + ": expected a vertex index >= 0");
        corners.push_back(c[k].get<std::size_t>());
      }
    }
    try {
      ToolProfile profile(points);
      if (q.number("fillet_radius") > 0.0) profile = profile.with_fillets(q.number("fillet_radius"), corners);
      tool = RigidTool(name, profile);
    } catch (const std::invalid_argument& e) {
      q.fail(q.number("fillet_radius") > 0.0 ? "fillet_radius" : "points", e.what());
    }
  } else {  // stl
    std::filesystem::path file = q.string("file");
    if (file.empty()) q.fail("file", "an stl tool needs a file");
    if (file.is_relative()) file = std::filesystem::path(q.file()).parent_path() / file;
    try {
      tool = RigidTool::stl(name, file.string(), q.number("scale"));
    } catch (const std::runtime_error& e) {
      q.fail("file", e.what());
    }
  }
  tool->axial_offset_m = q.number("position");
  tool->angle_rad = q.number("angle");
  tool->axial_velocity_m_s = q.number("axial_velocity");
  tool->angular_velocity_rad_s = q.number("angular_velocity");
  try {
    if (given(q, "axial_schedule")) tool->axial_schedule = PiecewiseLinear(q.pairs("axial_schedule", "s", "m/s"));
  } catch (const std::invalid_argument& e) {
    q.fail("axial_schedule", e.what());
  }
  try {
    if (given(q, "angular_schedule"))
      tool->angular_schedule = PiecewiseLinear(q.pairs("angular_schedule", "s", "rad/s"));
  } catch (const std::invalid_argument& e) {
    q.fail("angular_schedule", e.what());
  }
  if (q.boolean("command") && (given(q, "axial_schedule") || given(q, "angular_schedule")))
    q.fail("command", "a commanded tool cannot also follow a schedule");
  return std::move(*tool);
}

/// A tool of the `tools` array once built: where it is, and its commanded velocities.
struct ToolEntry {
  std::size_t index = 0;
  bool commanded = false;
  double axial_velocity = 0.0, angular_velocity = 0.0;  // constant or commanded (m/s, rad/s)
  double force_z = 0.0, torque = 0.0, position = 0.0;   // measured signals (N, N*m, m)
};

const ParamSpecs& probe_specs() {
  static const ParamSpecs specs = {
      ParamSpec::string("name", std::nullopt, "probe name (history column prefix)"),
      ParamSpec::array("point", "the particle nearest this point [x, y, z] (m) at t = 0 is followed", true),
      ParamSpec::string("body", std::string(), "only particles of this body are candidates (empty: any body)"),
      ParamSpec::string("quantity", std::nullopt, "what to record",
                        {"displacement_x", "displacement_y", "displacement_z", "velocity_x", "velocity_y",
                         "velocity_z", "pressure", "stress_xx", "stress_yy", "stress_zz", "stress_xy", "stress_yz",
                         "stress_xz", "temperature"}),
  };
  return specs;
}

struct Region {
  std::string name;
  long long body = -1;  // -1: any
  Vec lo, hi;
  bool prescribe_velocity = false;
  Vec velocity = Vec::Zero();
  bool rotate = false;
  Vec omega = Vec::Zero(), center = Vec::Zero();
  double temperature = -1.0, convection = -1.0;
  std::vector<std::size_t> particles;  // indices, refreshed when the id check fails
  std::vector<std::int64_t> ids;
};

struct Probe {
  std::string name, quantity;
  Vec point;
  std::int64_t id = -1;
  long long body = -1;  // -1: the nearest particle of any body
  std::size_t index = 0;
  Vec initial_position = Vec::Zero();
  double value = 0.0;
  // For the period: upward crossings of the running mean.
  std::vector<double> times, values;
};

class Generic final : public Process {
 public:
  explicit Generic(const ParamValues& p) : spacing_(p.number("particle_spacing")), jitter_(p.number("jitter")) {
    seed_ = static_cast<unsigned>(p.integer("seed"));
    const json& bodies = p.raw("bodies");
    if (!bodies.is_array() || bodies.empty()) p.fail("bodies", "expected a non-empty array of bodies");
    for (std::size_t b = 0; b < bodies.size(); ++b) {
      bodies_.push_back(p.element("bodies", b, body_specs()));
      const ParamValues& body = bodies_.back();
      std::optional<std::array<double, 6>> stress;
      if (given(body, "initial_stress")) {
        stress = tensor6(body, "initial_stress", "Pa");
        const std::array<double, 6>& s = *stress;
        const double trace = s[0] + s[1] + s[2];
        double norm = 0.0;
        for (int c = 0; c < 6; ++c) norm = std::max(norm, std::abs(s[c]));
        // The material's equation of state computes the pressure from the density (theory eq. 17),
        // so a mean stress given here would be lost at the first step.
        if (std::abs(trace) > 1e-12 * norm)
          body.fail("initial_stress", "must be deviatoric (xx + yy + zz = 0): the pressure follows from the density");
      }
      initial_stress_.push_back(stress);
    }
    if (given(p, "regions"))
      for (std::size_t r = 0; r < p.raw("regions").size(); ++r) region_values_.push_back(p.element("regions", r, region_specs()));
    if (given(p, "planes"))
      for (std::size_t r = 0; r < p.raw("planes").size(); ++r) plane_values_.push_back(p.element("planes", r, plane_specs()));
    if (given(p, "tools"))
      for (std::size_t r = 0; r < p.raw("tools").size(); ++r) {
        tool_values_.push_back(p.element("tools", r, tool_specs()));
        RigidTool checked = make_tool(tool_values_.back());  // user errors now, at validation
        // Names key the history columns and contact.tool_laws: unique among tools and planes.
        bool taken = std::find(tool_names_.begin(), tool_names_.end(), checked.name()) != tool_names_.end();
        for (const ParamValues& plane : plane_values_) taken = taken || plane.string("name") == checked.name();
        if (taken) tool_values_.back().fail("name", "another tool or plane is already named '" + checked.name() + "'");
        tool_names_.push_back(checked.name());
      }
    if (given(p, "probes"))
      for (std::size_t r = 0; r < p.raw("probes").size(); ++r) {
        const ParamValues q = p.element("probes", r, probe_specs());
        Probe probe;
        probe.name = q.string("name");
        probe.quantity = q.string("quantity");
        probe.point = vector3(q, "point", "m");
        const std::string body = q.string("body");
        if (!body.empty()) {
          auto it = std::find_if(bodies_.begin(), bodies_.end(), [&](const ParamValues& b) { return b.string("name") == body; });
          if (it == bodies_.end()) q.fail("body", "no body named '" + body + "'");
          probe.body = it - bodies_.begin();
        }
        probes_.push_back(probe);
      }
    period_start_ = p.number("period_start");
    // Attached bodies (eq. 90): a thermal-only body that names an existing tool or plane.
    for (const ParamValues& b : bodies_) {
      const std::string tool = b.string("attached_to");
      if (tool.empty()) continue;
      bool exists = std::find(tool_names_.begin(), tool_names_.end(), tool) != tool_names_.end();
      std::string names;
      for (const ParamValues& plane : plane_values_) {
        exists = exists || plane.string("name") == tool;
        names += (names.empty() ? "" : ", ") + plane.string("name");
      }
      for (const std::string& t : tool_names_) names += (names.empty() ? "" : ", ") + t;
      if (!exists)
        b.fail("attached_to", "no tool or plane named '" + tool + "' (" + (names.empty() ? std::string("none") : names) + ")");
      if (b.boolean("mechanics")) b.fail("attached_to", "only a thermal-only body (\"mechanics\": false) can be attached to a tool");
    }
  }

  std::vector<FieldInfo> fields() const override { return {}; }

  void build(SceneBuilder& scene) override {
    std::mt19937_64 rng(seed_);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    for (const ParamValues& b : bodies_) {
      BodySpec spec;
      spec.name = b.string("name");
      spec.spacing_m = spacing_;
      spec.material = b.string("material");
      spec.mechanics = b.boolean("mechanics");
      spec.attached_to = b.string("attached_to");
      spec.positions = lattice(b);
      if (spec.positions.empty()) b.fail("shape", "the body holds no particle at this spacing");
      // Jitter: each particle displaced by up to `jitter` spacings per axis (fixed seed).
      if (jitter_ > 0.0)
        for (Vec& x : spec.positions)
          for (int d = 0; d < 3; ++d) x[d] += jitter_ * spacing_ * unit(rng);
      spec.velocities = velocities(b, spec.positions);
      const std::size_t index = scene.add_body(std::move(spec));
      (void)index;
    }
    for (const ParamValues& q : plane_values_) {
      const double z = q.number("z"), radius = q.number("radius");
      // A disc in the (r, z) plane, walked so that the workpiece is on its left (tool.hpp): the
      // normal of a segment (dr, dz) is (-dz, dr), so a workpiece above (normal +z) needs dr > 0
      // (walked outwards) and one below needs the walk inwards, like a ram face.
      std::vector<Eigen::Vector2d> profile = q.string("side") == "above"
                                                 ? std::vector<Eigen::Vector2d>{{0.0, 0.0}, {radius, 0.0}}
                                                 : std::vector<Eigen::Vector2d>{{radius, 0.0}, {0.0, 0.0}};
      RigidTool tool(q.string("name"), profile);
      tool.axial_offset_m = z;
      tool.axial_velocity_m_s = q.number("velocity");
      tool.angular_velocity_rad_s = q.number("angular_velocity");
      scene.add_tool(std::move(tool));
      plane_velocity_.push_back({q.number("velocity"), q.number("angular_velocity")});
    }
    for (const ParamValues& q : tool_values_) {
      ToolEntry e;
      RigidTool tool = make_tool(q);
      e.commanded = q.boolean("command");
      e.axial_velocity = tool.axial_velocity_m_s;
      e.angular_velocity = tool.angular_velocity_rad_s;
      e.position = tool.axial_offset_m;
      e.index = scene.add_tool(std::move(tool));
      tools_.push_back(e);
    }
    for (const ParamValues& q : region_values_) {
      Region r;
      r.name = q.string("name");
      const std::string body = q.string("body");
      if (!body.empty()) {
        auto it = std::find_if(bodies_.begin(), bodies_.end(), [&](const ParamValues& b) { return b.string("name") == body; });
        if (it == bodies_.end()) q.fail("body", "no body named '" + body + "'");
        r.body = it - bodies_.begin();
      }
      r.lo = vector3(q, "min", "m");
      r.hi = vector3(q, "max", "m");
      if (given(q, "velocity")) {
        r.prescribe_velocity = true;
        r.velocity = vector3(q, "velocity", "m/s");
      }
      if (given(q, "angular_velocity")) {
        r.prescribe_velocity = true;
        r.rotate = true;
        r.omega = vector3(q, "angular_velocity", "rad/s");
        if (given(q, "center")) r.center = vector3(q, "center", "m");
      }
      r.temperature = q.number("temperature");
      r.convection = q.number("convection_coefficient");
      regions_.push_back(r);
    }
  }

  void bind_signals(SignalBus& bus) override {
    for (std::size_t t = 0; t < tools_.size(); ++t) {
      const std::string& name = tool_names_[t];
      bus.add_measured(name + "_force_z", "N", &tools_[t].force_z);
      bus.add_measured(name + "_torque", "N*m", &tools_[t].torque);
      bus.add_measured(name + "_position", "m", &tools_[t].position);
      if (!tools_[t].commanded) continue;
      bus.add_command(name + "_axial_velocity", "m/s", &tools_[t].axial_velocity);
      bus.add_command(name + "_angular_velocity", "rad/s", &tools_[t].angular_velocity);
    }
    // Probes are measured signals too (a phase may end when a thermocouple reads a temperature).
    for (Probe& p : probes_) bus.add_measured(p.name + "_" + p.quantity, signal_unit_of(p.quantity), &p.value);
  }

  void initialize(ProcessContext& ctx) override {
    FieldRegistry& f = *ctx.fields;
    const double* x = f.f64(field::position);
    const std::int64_t* body = f.i64(field::body);
    const std::int64_t* ids = f.i64(field::id);
    const std::size_t n = f.size();
    double* T = f.f64_if(field::temperature);
    double* hc = f.f64_if(field::convection_coefficient);
    double* S = f.f64_if(field::deviatoric_stress);
    for (std::size_t i = 0; i < n; ++i) {
      const ParamValues& b = bodies_[static_cast<std::size_t>(body[i])];
      if (T && b.number("temperature") >= 0.0) T[i] = b.number("temperature");
      if (hc && b.number("convection_coefficient") >= 0.0) hc[i] = b.number("convection_coefficient");
      const auto& stress = initial_stress_[static_cast<std::size_t>(body[i])];
      if (stress && S && i < ctx.mechanical_count)
        for (int c = 0; c < 6; ++c) S[6 * i + c] = (*stress)[static_cast<std::size_t>(c)];
    }
    for (Region& r : regions_) {
      for (std::size_t i = 0; i < n; ++i) {
        if (r.body >= 0 && body[i] != r.body) continue;
        bool inside = true;
        for (int d = 0; d < 3; ++d) inside = inside && x[3 * i + d] >= r.lo[d] && x[3 * i + d] <= r.hi[d];
        if (!inside) continue;
        r.particles.push_back(i);
        r.ids.push_back(ids[i]);
        if (T && r.temperature >= 0.0) T[i] = r.temperature;
        if (hc && r.convection >= 0.0) hc[i] = r.convection;
      }
      if (r.particles.empty())
        throw std::invalid_argument("generic: region '" + r.name + "' contains no particle");
    }
    for (Probe& p : probes_) {
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t i = 0; i < n; ++i) {
        if (p.body >= 0 && body[i] != p.body) continue;
        const double d2 = (Vec(x[3 * i], x[3 * i + 1], x[3 * i + 2]) - p.point).squaredNorm();
        if (d2 < best) {
          best = d2;
          p.index = i;
        }
      }
      p.id = ids[p.index];
      p.initial_position = Vec(x[3 * p.index], x[3 * p.index + 1], x[3 * p.index + 2]);
      if (p.quantity == "temperature" && !T)
        throw std::invalid_argument("generic: probe '" + p.name + "' records temperature in an isothermal case");
    }
  }

  void before_step(ProcessContext& ctx) override {
    // Constant or commanded tool speeds; a schedule, when given, overrides them in the core
    // (RigidTool::begin_step, eq. 45).
    for (const ToolEntry& e : tools_) {
      (*ctx.tools)[e.index].axial_velocity_m_s = e.axial_velocity;
      (*ctx.tools)[e.index].angular_velocity_rad_s = e.angular_velocity;
    }
    // Prescribed rotation, part 1: the velocity the gradient pass sees is the exact rigid field
    // v = v0 + w x (x^n - c) of the current positions, so L is the spin W exactly (D = 0 to
    // round-off). With the lagged field of the last step, L(x^n, v^{n-1/2}) has a symmetric part
    // of order dt |w|^2 that a rigid rotation does not have.
    if (std::none_of(regions_.begin(), regions_.end(), [](const Region& r) { return r.rotate; })) return;
    FieldRegistry& f = *ctx.fields;
    refresh(f);
    const double* x = f.f64(field::position);
    double* v = f.f64_if(field::velocity);
    if (!v) return;
    for (const Region& r : regions_) {
      if (!r.rotate) continue;
      for (std::size_t i : r.particles) {
        if (i >= ctx.mechanical_count) continue;
        const Vec u = r.velocity + r.omega.cross(Vec(x[3 * i], x[3 * i + 1], x[3 * i + 2]) - r.center);
        for (int d = 0; d < 3; ++d) v[3 * i + d] = u[d];
      }
    }
  }

  bool constrains_velocities() const override {
    return std::any_of(regions_.begin(), regions_.end(), [](const Region& r) { return r.prescribe_velocity || r.rotate; });
  }

  void apply_constraints(ProcessContext& ctx) override {
    FieldRegistry& f = *ctx.fields;
    refresh(f);
    double* v = f.f64_if(field::velocity);
    double* a = f.f64_if(field::acceleration);
    double* dT = f.f64_if(field::temperature_rate);
    const double* T = f.f64_if(field::temperature);
    const double* x = f.f64(field::position);
    for (const Region& r : regions_) {
      // Prescribed rotation, part 2: the velocity that moves each particle over the step exactly
      // onto its circle, x^{n+1} = c + v0 dt + R(w dt) (x^n - c): the chord (R - I)(x^n - c)/dt.
      Eigen::Matrix3d chord = Eigen::Matrix3d::Zero();
      if (r.rotate && ctx.dt_s > 0.0) {
        const double angle = r.omega.norm() * ctx.dt_s;
        if (angle > 0.0)
          chord = (Eigen::AngleAxisd(angle, r.omega.normalized()).toRotationMatrix() - Eigen::Matrix3d::Identity()) /
                  ctx.dt_s;
      }
      for (std::size_t i : r.particles) {
        if (r.prescribe_velocity && v && i < ctx.mechanical_count) {
          Vec u = r.velocity;
          if (r.rotate) u += chord * (Vec(x[3 * i], x[3 * i + 1], x[3 * i + 2]) - r.center);
          for (int d = 0; d < 3; ++d) {
            v[3 * i + d] = u[d];
            a[3 * i + d] = 0.0;
          }
        }
        // Relax exactly onto the prescribed temperature within the step.
        if (dT && r.temperature >= 0.0) dT[i] = ctx.dt_s > 0.0 ? (r.temperature - T[i]) / ctx.dt_s : 0.0;
      }
    }
  }

  void measure(ProcessContext& ctx) override {
    FieldRegistry& f = *ctx.fields;
    refresh(f);
    // Mass-weighted mean temperature of each body (thermal cases), a summary metric.
    if (const double* T = f.f64_if(field::temperature)) {
      const double* m = f.f64(field::mass);
      const std::int64_t* body = f.i64(field::body);
      std::vector<double> mt(bodies_.size(), 0.0), ms(bodies_.size(), 0.0);
      for (std::size_t i = 0; i < f.size(); ++i) {
        mt[static_cast<std::size_t>(body[i])] += m[i] * T[i];
        ms[static_cast<std::size_t>(body[i])] += m[i];
      }
      body_mean_temperature_.resize(bodies_.size());
      for (std::size_t b = 0; b < bodies_.size(); ++b) body_mean_temperature_[b] = ms[b] > 0.0 ? mt[b] / ms[b] : 0.0;
    }
    const double* x = f.f64(field::position);
    for (Probe& p : probes_) {
      const std::size_t i = p.index;
      const std::string& q = p.quantity;
      if (q.rfind("displacement_", 0) == 0) {
        const int d = q.back() - 'x';
        p.value = x[3 * i + d] - p.initial_position[d];
      } else if (q.rfind("velocity_", 0) == 0) {
        p.value = f.f64(field::velocity)[3 * i + (q.back() - 'x')];
      } else if (q == "temperature") {
        p.value = f.f64(field::temperature)[i];
      } else if (q == "pressure") {
        p.value = f.f64(field::pressure)[i];
      } else {  // stress_ab = S_ab - p delta_ab
        static const std::vector<std::string> names = {"stress_xx", "stress_yy", "stress_zz",
                                                       "stress_xy", "stress_yz", "stress_xz"};
        const int c = static_cast<int>(std::find(names.begin(), names.end(), q) - names.begin());
        p.value = f.f64(field::deviatoric_stress)[6 * i + c] - (c < 3 ? f.f64(field::pressure)[i] : 0.0);
      }
      if (ctx.time_s >= period_start_) {
        p.times.push_back(ctx.time_s);
        p.values.push_back(p.value);
      }
    }
    extents(f, ctx.mechanical_count);
    // Linear and angular momentum (about the origin) of the mechanical particles.
    if (ctx.mechanical_count > 0) {
      const double* v = f.f64(field::velocity);
      const double* m = f.f64(field::mass);
      Vec P = Vec::Zero(), H = Vec::Zero();
      for (std::size_t i = 0; i < ctx.mechanical_count; ++i) {
        const Vec xi(x[3 * i], x[3 * i + 1], x[3 * i + 2]), pi(m[i] * v[3 * i], m[i] * v[3 * i + 1], m[i] * v[3 * i + 2]);
        P += pi;
        H += xi.cross(pi);
      }
      for (int d = 0; d < 3; ++d) {
        momentum_[d] = P[d];
        angular_momentum_[d] = H[d];
      }
    }
    for (ToolEntry& e : tools_) {
      e.force_z = (*ctx.tools)[e.index].reaction_force_N.z();
      e.torque = (*ctx.tools)[e.index].reaction_torque_Nm;
      e.position = (*ctx.tools)[e.index].axial_offset_m;
    }
    for (std::size_t t = 0; t < plane_velocity_.size(); ++t) {
      (*ctx.tools)[t].axial_velocity_m_s = plane_velocity_[t].first;
      (*ctx.tools)[t].angular_velocity_rad_s = plane_velocity_[t].second;
    }
  }

  // Restart (docs/checkpoints.md): the probes' recorded samples (min, max, period) and the bodies'
  // extents at the first measurement. Regions and probes are found again by id (initialize() on
  // the rebuilt scene, refresh()); probe values and tool signals are on the bus.
  bool supports_restart() const override { return true; }
  nlohmann::json save_state() const override {
    json probes = json::array();
    for (const Probe& p : probes_) probes.push_back({{"times", p.times}, {"values", p.values}});
    json extents = json::array();
    for (const Extent& e : extent_initial_) extents.push_back({e.seen, e.length, e.radius, e.base_radius});
    return {{"probes", probes}, {"extent_initial", extents}};
  }
  void restore_state(const nlohmann::json& s) override {
    const json& probes = s.at("probes");
    if (probes.size() != probes_.size()) throw std::runtime_error("generic: another number of probes");
    for (std::size_t k = 0; k < probes_.size(); ++k) {
      probes_[k].times = probes[k].at("times").get<std::vector<double>>();
      probes_[k].values = probes[k].at("values").get<std::vector<double>>();
    }
    extent_initial_.clear();
    for (const json& e : s.at("extent_initial"))
      extent_initial_.push_back({e.at(0).get<bool>(), e.at(1).get<double>(), e.at(2).get<double>(), e.at(3).get<double>()});
  }

  std::vector<HistoryColumn> history_columns() const override {
    std::vector<HistoryColumn> c;
    for (const Probe& p : probes_) c.push_back({p.name + "_" + p.quantity + "_" + unit_of(p.quantity), &p.value});
    const char* axes[3] = {"x", "y", "z"};
    for (int d = 0; d < 3; ++d) c.push_back({std::string("momentum_") + axes[d] + "_kg_m_s", &momentum_[d]});
    for (int d = 0; d < 3; ++d) c.push_back({std::string("angular_momentum_") + axes[d] + "_kg_m2_s", &angular_momentum_[d]});
    return c;
  }

  nlohmann::json metrics() const override {
    json m = json::object();
    for (const Probe& p : probes_) {
      const std::string key = p.name + "_" + p.quantity;
      const std::string unit = unit_of(p.quantity);
      m[key + "_final_" + unit] = p.value;
      // Where the followed particle started (the lattice point nearest the probe's point).
      m[key + "_x0_m"] = p.initial_position[0];
      m[key + "_y0_m"] = p.initial_position[1];
      m[key + "_z0_m"] = p.initial_position[2];
      if (p.values.empty()) continue;
      m[key + "_min_" + unit] = *std::min_element(p.values.begin(), p.values.end());
      m[key + "_max_" + unit] = *std::max_element(p.values.begin(), p.values.end());
      const double period = oscillation_period(p);
      if (period > 0.0) m[key + "_period_s"] = period;
    }
    for (std::size_t b = 0; b < body_mean_temperature_.size(); ++b)
      m[bodies_[b].string("name") + "_temperature_mean_K"] = body_mean_temperature_[b];
    for (std::size_t b = 0; b < extent_.size(); ++b) {
      if (!extent_[b].seen) continue;
      const std::string name = bodies_[b].string("name");
      m[name + "_length_z_m"] = extent_[b].length;
      m[name + "_radius_max_m"] = extent_[b].radius;
      m[name + "_base_radius_m"] = extent_[b].base_radius;
      m[name + "_length_z_initial_m"] = extent_initial_[b].length;
      m[name + "_radius_max_initial_m"] = extent_initial_[b].radius;
    }
    return m;
  }

 private:
  /// The unit of a probe's quantity as a unit expression (signals), and as a column suffix (unit_of).
  static std::string signal_unit_of(const std::string& q) {
    const std::string u = unit_of(q);
    return u == "m_s" ? "m/s" : u;
  }
  static std::string unit_of(const std::string& q) {
    if (q.rfind("displacement_", 0) == 0) return "m";
    if (q.rfind("velocity_", 0) == 0) return "m_s";
    if (q == "temperature") return "K";
    return "Pa";
  }

  /// Mean period between upward crossings of the signal's mean (linear interpolation between
  /// samples); 0 when fewer than two crossings were seen.
  static double oscillation_period(const Probe& p) {
    double mean = 0.0;
    for (double v : p.values) mean += v;
    mean /= static_cast<double>(p.values.size());
    std::vector<double> crossings;
    for (std::size_t k = 1; k < p.values.size(); ++k) {
      const double a = p.values[k - 1] - mean, b = p.values[k] - mean;
      if (a < 0.0 && b >= 0.0) crossings.push_back(p.times[k - 1] + (p.times[k] - p.times[k - 1]) * (-a) / (b - a));
    }
    if (crossings.size() < 2) return 0.0;
    return (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
  }

  /// Extent of each mechanical body (e.g. a Taylor bar): length along z, the largest distance of
  /// a particle from the body's axis (parallel to z through its current centroid) and the same
  /// within the lowest particle layer (z < z_min + dx/2, the impact face). Particle centres are
  /// dx/2 inside the material's surface, so dx is added to the length and dx/2 to the radii; the
  /// values at the first measurement are kept too (`_initial_`): on a cubic lattice clipped to a
  /// cylinder they differ from the nominal radius by up to about dx/2.
  void extents(const FieldRegistry& f, std::size_t n) {
    const double* x = f.f64(field::position);
    const std::int64_t* body = f.i64(field::body);
    const std::size_t nb = bodies_.size();
    std::vector<double> cx(nb, 0.0), cy(nb, 0.0), count(nb, 0.0), zmin(nb, std::numeric_limits<double>::infinity()),
        zmax(nb, -std::numeric_limits<double>::infinity());
    for (std::size_t i = 0; i < n; ++i) {
      const auto b = static_cast<std::size_t>(body[i]);
      cx[b] += x[3 * i];
      cy[b] += x[3 * i + 1];
      count[b] += 1.0;
      zmin[b] = std::min(zmin[b], x[3 * i + 2]);
      zmax[b] = std::max(zmax[b], x[3 * i + 2]);
    }
    extent_.assign(nb, Extent{});
    for (std::size_t i = 0; i < n; ++i) {
      const auto b = static_cast<std::size_t>(body[i]);
      const double r = std::hypot(x[3 * i] - cx[b] / count[b], x[3 * i + 1] - cy[b] / count[b]);
      extent_[b].radius = std::max(extent_[b].radius, r);
      if (x[3 * i + 2] < zmin[b] + 0.5 * spacing_) extent_[b].base_radius = std::max(extent_[b].base_radius, r);
    }
    for (std::size_t b = 0; b < nb; ++b) {
      if (count[b] == 0.0) continue;
      extent_[b].seen = true;
      extent_[b].length = zmax[b] - zmin[b] + spacing_;
      extent_[b].radius += 0.5 * spacing_;
      extent_[b].base_radius += 0.5 * spacing_;
    }
    if (extent_initial_.empty()) extent_initial_ = extent_;
  }

  /// Regions and probes remember particle indices; when the core reorders particles (locality)
  /// the ids no longer match and the indices are looked up again.
  void refresh(FieldRegistry& f) {
    const std::int64_t* ids = f.i64(field::id);
    bool stale = false;
    for (const Probe& p : probes_) stale = stale || ids[p.index] != p.id;
    for (const Region& r : regions_) stale = stale || (!r.particles.empty() && ids[r.particles.front()] != r.ids.front());
    if (!stale) return;
    std::vector<std::size_t> index_of_id(f.size());
    for (std::size_t i = 0; i < f.size(); ++i) index_of_id[static_cast<std::size_t>(ids[i])] = i;
    for (Probe& p : probes_) p.index = index_of_id[static_cast<std::size_t>(p.id)];
    for (Region& r : regions_)
      for (std::size_t k = 0; k < r.particles.size(); ++k) r.particles[k] = index_of_id[static_cast<std::size_t>(r.ids[k])];
  }

  std::vector<Vec> lattice(const ParamValues& b) const {
    std::vector<Vec> points;
    const std::string shape = b.string("shape");
    const double dx = spacing_;
    if (shape == "box") {
      if (!given(b, "min") || !given(b, "max")) b.fail("shape", "a box needs min and max");
      const Vec lo = vector3(b, "min", "m"), hi = vector3(b, "max", "m");
      int n[3];
      for (int d = 0; d < 3; ++d) {
        if (!(hi[d] > lo[d])) b.fail("max", "each component must exceed min's");
        n[d] = std::max(1, static_cast<int>(std::lround((hi[d] - lo[d]) / dx)));
      }
      // Cell-centred lattice filling the box exactly when its edges are multiples of dx.
      for (int k = 0; k < n[2]; ++k)
        for (int j = 0; j < n[1]; ++j)
          for (int i = 0; i < n[0]; ++i)
            points.emplace_back(lo[0] + (i + 0.5) * dx, lo[1] + (j + 0.5) * dx, lo[2] + (k + 0.5) * dx);
      return points;
    }
    if (!given(b, "center")) b.fail("shape", "a " + shape + " needs center");
    const Vec c = vector3(b, "center", "m");
    const double ro = b.number("radius"), ri = shape == "tube" ? b.number("inner_radius") : 0.0;
    if (!(ro > 0.0)) b.fail("radius", "must be positive");
    if (shape == "sphere") {
      // Cubic lattice clipped to the ball (particle centres inside), centred on `center`.
      const int nr = static_cast<int>(std::ceil(ro / dx)) + 1;
      for (int k = -nr; k < nr; ++k)
        for (int j = -nr; j < nr; ++j)
          for (int i = -nr; i < nr; ++i) {
            const Vec offset((i + 0.5) * dx, (j + 0.5) * dx, (k + 0.5) * dx);
            if (offset.norm() <= ro) points.push_back(c + offset);
          }
      return points;
    }
    const double height = b.number("height");
    if (!(height > 0.0)) b.fail("height", "must be positive");
    if (shape == "tube" && !(ri < ro)) b.fail("inner_radius", "must be smaller than radius");
    // Cubic lattice clipped to the annulus ri <= r <= ro (particle centres inside).
    const int nr = static_cast<int>(std::ceil(ro / dx)) + 1;
    const int nz = std::max(1, static_cast<int>(std::lround(height / dx)));
    for (int k = 0; k < nz; ++k)
      for (int j = -nr; j < nr; ++j)
        for (int i = -nr; i < nr; ++i) {
          const double px = (i + 0.5) * dx, py = (j + 0.5) * dx, r = std::hypot(px, py);
          if (r <= ro && r >= ri) points.emplace_back(c[0] + px, c[1] + py, c[2] + (k + 0.5) * dx);
        }
    return points;
  }

  std::vector<Vec> velocities(const ParamValues& b, const std::vector<Vec>& x) const {
    const bool translate = given(b, "velocity");
    const bool rotate = given(b, "angular_velocity");
    const bool mode = given(b, "velocity_profile");
    if (!translate && !rotate && !mode) return {};
    const Vec v0 = translate ? vector3(b, "velocity", "m/s") : Vec::Zero();
    const Vec w = rotate ? vector3(b, "angular_velocity", "rad/s") : Vec::Zero();
    const Vec c = rotate ? (given(b, "center") ? vector3(b, "center", "m") : Vec::Zero()) : Vec::Zero();
    std::vector<Vec> v(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) v[i] = v0 + w.cross(x[i] - c);
    if (mode) {
      // First bending mode of a clamped-free beam along +x (Euler-Bernoulli, kL = 1.875104):
      // phi(s) = (cos ks - cosh ks) - r (sin ks - sinh ks), r = (cos kL + cosh kL)/(sin kL + sinh kL),
      // scaled to `amplitude` at the free end.
      const ParamValues q = b.sub("velocity_profile", profile_specs());
      const double root = q.number("axis_start"), length = q.number("length"), amplitude = q.number("amplitude");
      const int dir = q.string("direction")[0] - 'x';
      const double kL = 1.8751040687, k = kL / length;
      const double ratio = (std::cos(kL) + std::cosh(kL)) / (std::sin(kL) + std::sinh(kL));
      auto phi = [&](double s) { return (std::cos(k * s) - std::cosh(k * s)) - ratio * (std::sin(k * s) - std::sinh(k * s)); };
      const double tip = phi(length);
      for (std::size_t i = 0; i < x.size(); ++i) {
        const double s = std::clamp(x[i][0] - root, 0.0, length);
        v[i][dir] += amplitude * phi(s) / tip;
      }
    }
    return v;
  }

  double spacing_, jitter_;
  unsigned seed_ = 1;
  double period_start_ = 0.0;
  std::vector<ParamValues> bodies_, region_values_, plane_values_, tool_values_;
  std::vector<std::string> tool_names_;
  std::vector<ToolEntry> tools_;
  std::vector<std::optional<std::array<double, 6>>> initial_stress_;  // per body
  std::vector<Region> regions_;
  std::vector<Probe> probes_;
  std::vector<std::pair<double, double>> plane_velocity_;
  double momentum_[3] = {0, 0, 0}, angular_momentum_[3] = {0, 0, 0};
  std::vector<double> body_mean_temperature_;
  struct Extent {
    bool seen = false;
    double length = 0.0, radius = 0.0, base_radius = 0.0;
  };
  std::vector<Extent> extent_, extent_initial_;
};

const PluginDescriptor& descriptor() {
  static const PluginDescriptor d = make_plugin_descriptor<Generic>(
      "generic", "0.1.0",
      "bodies from primitives (box, cylinder, tube, disc) with initial motion, prescribed regions, rigid z-planes, "
      "rigid tools (plane, cylinder, profile, STL), probes",
      {
          ParamSpec::number("particle_spacing", "m", std::nullopt, "lattice spacing dx of every body", 1e-9),
          ParamSpec::number("jitter", "1", 0.0, "random displacement of each particle, fraction of dx per axis", 0.0, 0.45),
          ParamSpec::integer("seed", 1, "seed of the jitter (runs are reproducible)", 0),
          ParamSpec::array("bodies", "the bodies: see docs/processes/generic.md", true),
          ParamSpec::array("regions", "prescribed velocity / temperature / convection regions"),
          ParamSpec::array("planes", "rigid planes normal to z (tools)"),
          ParamSpec::array("tools", "rigid tools: plane, cylinder, filleted profile, STL mesh (docs/processes/generic.md)"),
          ParamSpec::array("probes", "particles followed and recorded in the history"),
          ParamSpec::number("period_start", "s", 0.0, "probe samples before this time are ignored by the metrics", 0.0),
      });
  return d;
}

}  // namespace

SPHFORGE_PLUGIN(descriptor)
