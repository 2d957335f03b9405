// Process plugin `ram_extrusion`: a billet in a cylindrical barrel, pushed by a flat ram through
// a die with a square (flat) entry, a filleted entry corner and a cylindrical land.
// Geometry and reference numbers: cases/ram_extrusion/reference/paste_ram_extrusion.md.
//
// Coordinates: z is the extrusion axis, the die face is the plane z = 0, the billet occupies
// 0 < z < billet_height inside r < D0/2, and the extrudate leaves downwards (z < 0).
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "die_geometry.hpp"
#include "sphforge/plugin.hpp"

namespace {

using namespace sphforge;

class RamExtrusion final : public Process {
 public:
  explicit RamExtrusion(const ParamValues& p) {
    barrel_radius_ = 0.5 * p.number("barrel_diameter");
    ram_radius_ = 0.5 * p.number("ram_diameter");
    billet_height_ = p.number("billet_height");
    die_radius_ = 0.5 * p.number("die_diameter");
    land_length_ = p.number("land_length");
    fillet_ = p.number("entry_fillet_radius");
    spacing_ = p.number("particle_spacing");
    stroke_ = p.number("stroke");
    window_start_ = p.number("steady_window_start");
    window_end_ = p.number("steady_window_end");
    if (window_end_ <= window_start_) p.fail("steady_window_end", "must be larger than steady_window_start");
    rings_ = p.string("billet_lattice") == "rings";
    with_die_ = p.boolean("die");
    fill_die_ = p.boolean("fill_die");
    sectors_ = static_cast<int>(p.integer("sector_count"));
    section_height_ = p.number("pressure_section_height_over_barrel_radius") * barrel_radius_;
    if (ram_radius_ > barrel_radius_) p.fail("ram_diameter", "the ram must fit in the barrel");
    if (with_die_) make_die(p);
    if (spacing_ * 4 > billet_height_ || (with_die_ && spacing_ * 2 > die_radius_ * 2 + 1e-12))
      p.fail("particle_spacing", "too coarse: need at least 4 particles over the billet height and 2 across the die");
    exit_z_ = with_die_ ? die_.exit_z : 0.0;
  }

  void build(SceneBuilder& scene) override {
    // Billet: a cubic lattice inside the barrel, half a spacing away from every wall so that the
    // particles start exactly touching the tools (contact distance = spacing/2).
    std::vector<Eigen::Vector3d> points;
    const int nr = static_cast<int>(std::ceil(barrel_radius_ / spacing_));
    const int nz = static_cast<int>(std::floor(billet_height_ / spacing_ + 1e-9));
    const double rmax = barrel_radius_ - 0.5 * spacing_ + 1e-9 * spacing_;
    if (rings_) {
      // Polar rings r = R0 - (k + 1/2) dx (k = 0 outermost), each with round(2 pi r / dx)
      // particles, so that the whole outer ring lies dx/2 from the barrel wall and touches it
      // (a cubic lattice clipped to the circle leaves its outer particles at scattered distances,
      // most of them out of contact). The outer ring holds round(2 pi R0 / dx) particles: their
      // contact areas dx^2 then add up to the wall's 2 pi R0 dx per layer (wall laws act on that
      // area, docs/contact.md).
      const int rings = static_cast<int>(std::floor(barrel_radius_ / spacing_ - 0.5 + 1e-9)) + 1;
      for (int k = 0; k < nz; ++k)
        for (int q = 0; q < rings; ++q) {
          const double r = barrel_radius_ - (q + 0.5) * spacing_;
          if (r < 0.25 * spacing_) {
            points.emplace_back(0.0, 0.0, (k + 0.5) * spacing_);
            continue;
          }
          append_ring(points, r, q == 0 ? barrel_radius_ : r, (k + 0.5) * spacing_, (q + k) % 2);
        }
    } else {
      for (int k = 0; k < nz; ++k)
        for (int j = -nr; j < nr; ++j)
          for (int i = -nr; i < nr; ++i) {
            const Eigen::Vector3d x((i + 0.5) * spacing_, (j + 0.5) * spacing_, (k + 0.5) * spacing_);
            if (std::hypot(x.x(), x.y()) <= rmax) points.push_back(x);
          }
    }
    if (with_die_ && fill_die_) append_die_fill(points);
    scene.add_body("billet", points, spacing_);
    ram_top_start_ = nz * spacing_;

    // Barrel wall r = R0, walked upwards (material on the left = inside).
    barrel_ = scene.add_tool(RigidTool("barrel", {{barrel_radius_, 0.0}, {barrel_radius_, ram_top_start_ + 4 * spacing_}}));
    if (!with_die_) {
      // Open barrel end: the billet leaves the barrel at z = 0 (plug flow, docs/verification.md 11.5).
      RigidTool ram("ram", {{ram_radius_, 0.0}, {0.0, 0.0}});
      ram.axial_offset_m = ram_top_start_;
      ram_ = scene.add_tool(std::move(ram));
      return;
    }
    // Die: the family's wall (die_geometry.hpp, docs/theory.md eqs. 80-86), walked in along its
    // underside (so that extrudate swelling below the exit is outside the die, not behind an open
    // edge), up the land and the entry to the barrel wall; its arcs are exact (eq. 41).
    die_tool_ = scene.add_tool(RigidTool("die", die_.profile(barrel_radius_)));
    // Ram face, walked inwards (material below), moved to the billet top.
    RigidTool ram("ram", {{ram_radius_, 0.0}, {0.0, 0.0}});
    ram.axial_offset_m = ram_top_start_;
    ram_ = scene.add_tool(std::move(ram));
  }

  void bind_signals(SignalBus& bus) override {
    bus.add_command("ram_velocity", "m/s", &ram_velocity_);
    bus.add_measured("ram_force", "N", &ram_force_);
    bus.add_measured("ram_displacement", "m", &ram_displacement_);
    bus.add_measured("extrusion_pressure", "Pa", &pressure_);
  }

  void before_step(ProcessContext& ctx) override {
    // The ram moves down (-z) at the commanded speed, f times faster under time scaling (eq. 25):
    // the command stays the physical speed. Navier slip evaluates its wall stress at the simulated
    // slip speed, so paste cases with navier_slip walls must keep f = 1 (docs/processes/ram_extrusion.md).
    (*ctx.tools)[ram_].axial_velocity_m_s = -ram_velocity_ * ctx.time_scaling;
  }

  void measure(ProcessContext& ctx) override {
    const RigidTool& ram = (*ctx.tools)[ram_];
    ram_displacement_ = ram_top_start_ - ram.axial_offset_m;
    // A sector of 360/N deg carries 1/N of the ram's reaction (theory.md section 11): the
    // full-body force is N times it (eq. 70).
    ram_force_ = sectors_ * ram.reaction_force_N.z();  // material pushes the ram up (+z)
    pressure_ = ram_force_ / (std::numbers::pi * barrel_radius_ * barrel_radius_);  // eq. (70)
    const double* x = ctx.fields->f64(field::position);
    const double* v = ctx.fields->f64(field::velocity);
    const double* m = ctx.fields->f64(field::mass);
    const double* rho = ctx.fields->f64(field::density);
    const double* p = ctx.fields->f64(field::pressure);
    const double* s = ctx.fields->f64(field::deviatoric_stress);
    const std::size_t n = ctx.mechanical_count;
    const double zs = section_height_, half = 0.5 * spacing_;
    double zmin = std::numeric_limits<double>::infinity();
    std::size_t below = 0;
    double ex_mass = 0.0, ex_momentum = 0.0, sec_volume = 0.0, sec_stress = 0.0, kinetic = 0.0;
#pragma omp parallel for reduction(min : zmin) \
    reduction(+ : below, ex_mass, ex_momentum, sec_volume, sec_stress, kinetic) schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      const double z = x[3 * i + 2];
      kinetic += 0.5 * m[i] * (v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] + v[3 * i + 2] * v[3 * i + 2]);
      zmin = std::min(zmin, z);
      if (z < exit_z_) {
        below += 1;
        ex_mass += m[i];
        ex_momentum -= m[i] * v[3 * i + 2];  // extrudate moves in -z (eq. 72)
      }
      if (std::abs(z - zs) < half) {
        // The slab |z - z_s| < dx/2 samples the whole barrel cross-section (eq. 73).
        const double vol = m[i] / rho[i];
        sec_volume += vol;
        sec_stress += vol * (s[6 * i + 2] - p[i]);  // sigma_zz = s_zz - p
      }
    }
    extrudate_length_ = std::max(0.0, exit_z_ - (zmin - 0.5 * spacing_));
    extruded_ = static_cast<double>(below);
    extrudate_velocity_ = ex_mass > 0.0 ? ex_momentum / ex_mass : 0.0;
    // The section must lie in the billet, at least a spacing below the ram face.
    const bool section_valid = sec_volume > 0.0 && zs < ram.axial_offset_m - spacing_;
    section_pressure_ = section_valid ? -sec_stress / sec_volume : std::numeric_limits<double>::quiet_NaN();
    // Energy ratio of the paper's mass-scaling rule (eq. 71): kinetic energy over the ram's work
    // less it (what the material stored or dissipated), both for the full body.
    ram_work_ += ram_force_ * (-ram.axial_velocity_m_s) * ctx.dt_s;
    kinetic_ = sectors_ * kinetic;
    energy_ratio_ = ram_work_ > kinetic_ ? kinetic_ / (ram_work_ - kinetic_) : 0.0;
    if (ctx.dt_s > 0.0) {
      peak_pressure_ = std::max(peak_pressure_, pressure_);
      if (ram_displacement_ >= window_start_ && ram_displacement_ <= window_end_)
        energy_ratio_window_max_ = std::max(energy_ratio_window_max_, energy_ratio_);
      if (ram_force_ > peak_force_) {  // eq. (75): F_L and where it occurs
        peak_force_ = ram_force_;
        peak_force_displacement_ = ram_displacement_;
      }
      if (ram_displacement_ >= window_start_ && ram_displacement_ <= window_end_) {
        window_.add(pressure_, ctx.dt_s);
        if (section_valid) section_window_.add(section_pressure_, ctx.dt_s);
      }
    }
  }

  bool finished(const ProcessContext&) const override { return ram_displacement_ >= stroke_; }

  std::vector<HistoryColumn> history_columns() const override {
    return {{"ram_displacement_m", &ram_displacement_}, {"ram_velocity_m_s", &ram_velocity_},
            {"ram_force_N", &ram_force_},               {"extrusion_pressure_Pa", &pressure_},
            {"extrudate_length_m", &extrudate_length_}, {"extruded_particles_1", &extruded_},
            {"extrudate_velocity_m_s", &extrudate_velocity_}, {"section_pressure_Pa", &section_pressure_},
            {"ram_work_J", &ram_work_},                 {"kinetic_to_ram_internal_ratio_1", &energy_ratio_}};
  }

  // Restart (docs/checkpoints.md): what measure() accumulates over the steps. The instantaneous
  // signals (ram force, displacement, pressure) are on the bus, which the core saves.
  bool supports_restart() const override { return true; }
  nlohmann::json save_state() const override {
    auto window = [](const WindowStats& w) { return nlohmann::json::array({w.sum, w.sum2, w.time}); };
    return {{"window", window(window_)},
            {"section_window", window(section_window_)},
            {"peak_pressure", peak_pressure_},
            {"peak_force", peak_force_},
            {"peak_force_displacement", peak_force_displacement_},
            {"ram_work", ram_work_},
            {"energy_ratio_window_max", energy_ratio_window_max_}};
  }
  void restore_state(const nlohmann::json& s) override {
    auto window = [](const nlohmann::json& a) {
      return WindowStats{a.at(0).get<double>(), a.at(1).get<double>(), a.at(2).get<double>()};
    };
    window_ = window(s.at("window"));
    section_window_ = window(s.at("section_window"));
    peak_pressure_ = s.at("peak_pressure").get<double>();
    peak_force_ = s.at("peak_force").get<double>();
    peak_force_displacement_ = s.at("peak_force_displacement").get<double>();
    ram_work_ = s.at("ram_work").get<double>();
    energy_ratio_window_max_ = s.at("energy_ratio_window_max").get<double>();
  }

  nlohmann::json metrics() const override {
    nlohmann::json m;
    m["peak_extrusion_pressure_Pa"] = peak_pressure_;
    m["final_ram_displacement_m"] = ram_displacement_;
    m["extrudate_length_m"] = extrudate_length_;
    m["extruded_particles"] = extruded_;
    m["steady_window_start_m"] = window_start_;
    m["steady_window_end_m"] = window_end_;
    m["peak_force_N"] = peak_force_;  // F_L (eq. 75)
    m["peak_force_ram_displacement_m"] = peak_force_displacement_;
    m["sector_count"] = sectors_;
    m["kinetic_to_ram_internal_ratio_window_max"] = energy_ratio_window_max_;  // eq. (71)
    m["pressure_section_height_m"] = section_height_;
    m["steady_window_duration_s"] = window_.time;
    // Time-weighted mean and standard deviation over the steady window (eq. 74); null when the
    // window was never reached (or the section never lay in the billet).
    m["steady_extrusion_pressure_Pa"] = window_.mean();
    m["steady_extrusion_pressure_scatter_Pa"] = window_.scatter();
    m["steady_section_pressure_Pa"] = section_window_.mean();
    m["steady_section_pressure_scatter_Pa"] = section_window_.scatter();
    return m;
  }

 private:
  // Die from the case's family parameters (docs/processes/ram_extrusion.md "Dies"); geometry
  // errors become input errors at the parameter that caused them.
  void make_die(const ParamValues& p) {
    namespace re = ram_extrusion;
    const std::string family = p.string("die_family");
    std::string blame = "die_family";
    try {
      if (family == "square") {
        blame = "die_diameter";
        die_ = re::square_die(barrel_radius_, die_radius_, land_length_, fillet_);
      } else if (family == "conical" || family == "CS") {
        blame = "entry_angle";
        // CS: the dry-ice conical dies, whose cone reaches the barrel wall (insert height ignored).
        die_ = re::conical_die(barrel_radius_, die_radius_, p.number("entry_angle"),
                               family == "CS" ? 0.0 : p.number("insert_height"), land_length_, fillet_);
      } else if (family == "WK" || family == "WP" || family == "WKWP") {
        const re::ArcSection convex{p.number("arc_radius_1"), p.number("arc_length_1"),
                                    re::bulge_from_string(p.string("convex_bulge"))};
        const re::ArcSection concave{p.number("arc_radius_2"), p.number("arc_length_2"),
                                     re::bulge_from_string(p.string("concave_bulge"))};
        blame = family == "WP" ? "arc_radius_2" : "arc_radius_1";
        if (family != "WP" && !(convex.radius > 0.0 && convex.length > 0.0))
          p.fail("arc_radius_1", family + " die needs arc_radius_1 and arc_length_1 > 0");
        if (family != "WK" && !(concave.radius > 0.0 && concave.length > 0.0))
          p.fail("arc_radius_2", family + " die needs arc_radius_2 and arc_length_2 > 0");
        std::vector<re::ArcSection> sections;
        if (family != "WP") sections.push_back(convex);
        if (family != "WK") sections.push_back(concave);
        die_ = re::spherical_die(barrel_radius_, die_radius_, sections, land_length_);
      } else {  // profile
        blame = "die_profile";
        if (!p.has("die_profile") || !p.raw("die_profile").is_array())
          p.fail("die_profile", "die_family 'profile' needs die_profile: [{\"r\": ..., \"z\": ..., \"fillet\": ...}, ...]");
        const ParamSpecs point{ParamSpec::number("r", "m", std::nullopt, "radius of the wall point", 0.0),
                               ParamSpec::number("z", "m", std::nullopt, "height of the wall point (die entry z = 0)"),
                               ParamSpec::number("fillet", "m", 0.0, "radius of the arc rounding this corner", 0.0)};
        std::vector<re::WallVertex> wall;
        for (std::size_t i = 0; i < p.raw("die_profile").size(); ++i) {
          const ParamValues v = p.element("die_profile", i, point);
          wall.push_back({{v.number("r"), v.number("z")}, v.number("fillet")});
        }
        die_ = re::profile_die(std::move(wall));
        die_radius_ = die_.exit_radius;
      }
      (void)die_.profile(barrel_radius_);  // fillets that do not fit throw here, not in build()
    } catch (const std::invalid_argument& e) {
      p.fail(blame, e.what());
    }
  }

  /// One polar ring of the rings lattice (theory.md eq. 79) at radius r and height z, for the billet
  /// and the die fill alike; its count follows from the circumference at `count_radius` (the wall's
  /// radius for the outer ring, whose contact areas then add up to the wall's). `stagger` (0 or 1)
  /// shifts alternate rings and layers by half a pitch.
  void append_ring(std::vector<Eigen::Vector3d>& points, double r, double count_radius, double z, int stagger) const {
    const double circumference = 2.0 * std::numbers::pi * count_radius;
    // With a sector of 360/N deg (numerics.symmetry) every ring holds a multiple of N particles,
    // so that the ring maps onto itself and the core's clip (theory.md eq. 30) keeps exactly 1/N
    // of it; N = 1 is the plain rounding. Otherwise the pitch across a cut differs from the pitch
    // within the sector: a gap or a near-pair at every cut.
    const int count = sectors_ * std::max(1, static_cast<int>(std::lround(circumference / (spacing_ * sectors_))));
    // In a sector the angles are shifted by a quarter of the pitch so that no particle lies on a
    // cut (theta = 0 or 360/N deg): one there would be kept twice, once as itself at
    // theta ~ 360/N - eps (round-off) and once as the ghost of its twin at theta = 0, the two on
    // top of each other for the whole run (eq. 79; measured: 1768 particles in the sector for
    // 7016 / 4, and in the die fill before it used this routine, 6 coincident pairs at dx = 1 mm).
    const double phase = 0.5 * stagger + (sectors_ > 1 ? 0.25 : 0.0);
    // A sector's ring holds at least N particles; near the axis (a die fill's innermost ring can
    // lie at 0.25-0.75 dx) they would crowd closer than dx / sqrt(2), the nearest pair of the billet's
    // innermost ring (4 at r = dx/2), and that ring blew up (WK70 at dx = 2 and 3 mm, step 180-190):
    // such a ring moves out to the radius where its chord is dx / sqrt(2). A ring at a wall
    // (count_radius > r: the outer one, dx/2 from the barrel or the die) never moves: outwards it
    // would start inside the wall's contact band (CS50 at dx = 4 mm: a 16-particle ring in the
    // taper moved 0.33 mm into it, a 3.7 kN kick at step 1 and `unstable` at step 10).
    const double min_radius = spacing_ / (2.0 * std::numbers::sqrt2 * std::sin(std::numbers::pi / count));
    const bool at_wall = count_radius > r;
    const double radius = count > 1 && !at_wall && r < min_radius ? min_radius : r;  // one particle: no pair
    for (int a = 0; a < count; ++a) {
      const double angle = 2.0 * std::numbers::pi * (a + phase) / count;
      points.emplace_back(radius * std::cos(angle), radius * std::sin(angle), z);
    }
  }

  // Lattice points of the material already in the die cavity (the dry-ice paper's residual
  // compressed material): the billet's lattice (cubic or rings) continued below z = 0, kept dx/2
  // inside the die wall (the contact distance, as for the billet at the barrel) and above the exit.
  void append_die_fill(std::vector<Eigen::Vector3d>& points) const {
    const ToolProfile wall = die_.profile(barrel_radius_);
    const int nr = static_cast<int>(std::ceil(barrel_radius_ / spacing_));
    const int kmin = static_cast<int>(std::floor(die_.exit_z / spacing_));
    Eigen::Vector2d normal;
    auto inside = [&](double r, double z) { return wall.signed_distance({r, z}, normal) >= 0.5 * spacing_ * (1.0 - 1e-9); };
    for (int k = kmin; k < 0; ++k) {
      const double z = (k + 0.5) * spacing_;
      if (z < die_.exit_z + 0.5 * spacing_ * (1.0 - 1e-9)) continue;
      if (rings_) {
        // Polar rings as the billet's (see build()): the outer ring at the largest radius r_o that
        // is dx/2 from the wall (bisection: inside the converging wall the distance falls with r),
        // so that it touches the die wall as the billet's outer ring touches the barrel.
        if (!inside(0.0, z)) continue;
        double lo = 0.0, hi = barrel_radius_;
        for (int it = 0; it < 60; ++it) (inside(0.5 * (lo + hi), z) ? lo : hi) = 0.5 * (lo + hi);
        for (int q = 0;; ++q) {
          const double r = lo - q * spacing_;
          if (r < 0.25 * spacing_) {
            points.emplace_back(0.0, 0.0, z);
            break;
          }
          append_ring(points, r, q == 0 ? lo + 0.5 * spacing_ : r, z, (q + k + 2 * std::abs(kmin)) % 2);
          if (r < 0.75 * spacing_) break;  // the next ring would sit on the axis side of the centre
        }
        continue;
      }
      for (int j = -nr; j < nr; ++j)
        for (int i = -nr; i < nr; ++i) {
          const Eigen::Vector3d x((i + 0.5) * spacing_, (j + 0.5) * spacing_, z);
          const double r = std::hypot(x.x(), x.y());
          if (r < barrel_radius_ && inside(r, z)) points.push_back(x);
        }
    }
  }

  double barrel_radius_, ram_radius_, billet_height_, die_radius_, land_length_, fillet_, spacing_, stroke_;
  double window_start_, exit_z_, ram_top_start_ = 0.0;
  bool rings_ = false, with_die_ = true;
  std::size_t barrel_ = 0, die_tool_ = 0, ram_ = 0;
  bool fill_die_ = false;
  ram_extrusion::DieShape die_;
  double ram_velocity_ = 0.0, ram_force_ = 0.0, ram_displacement_ = 0.0, pressure_ = 0.0;
  double extrudate_length_ = 0.0, extruded_ = 0.0, peak_pressure_ = 0.0;
  // Time-weighted running sums of a signal over the steady window (eq. 74).
  struct WindowStats {
    double sum = 0.0, sum2 = 0.0, time = 0.0;
    void add(double value, double dt) {
      sum += value * dt;
      sum2 += value * value * dt;
      time += dt;
    }
    nlohmann::json mean() const { return time > 0.0 ? nlohmann::json(sum / time) : nlohmann::json(nullptr); }
    nlohmann::json scatter() const {
      if (time <= 0.0) return nullptr;
      const double mu = sum / time;
      return std::sqrt(std::max(0.0, sum2 / time - mu * mu));
    }
  };
  WindowStats window_, section_window_;
  double window_end_ = 0.0, section_height_ = 0.0, extrudate_velocity_ = 0.0, section_pressure_ = 0.0;
  double peak_force_ = 0.0, peak_force_displacement_ = 0.0;
  double ram_work_ = 0.0, kinetic_ = 0.0, energy_ratio_ = 0.0, energy_ratio_window_max_ = 0.0;
  int sectors_ = 1;
};

const PluginDescriptor& descriptor() {
  static const PluginDescriptor d = make_plugin_descriptor<RamExtrusion>(
      "ram_extrusion", "0.1.0",
      "billet in a barrel pushed by a ram through a die (square or conical entry, dry-ice CS/WK/WP/WKWP, or a "
      "general profile) and its land",
      {
        ParamSpec::number("barrel_diameter", "m", 25e-3, "barrel inner diameter D0", 1e-6),
        ParamSpec::number("ram_diameter", "m", 24.93e-3, "ram diameter", 1e-6),
        ParamSpec::number("billet_height", "m", 40e-3, "initial billet height", 1e-6),
        ParamSpec::number("die_diameter", "m", 3e-3, "die (orifice and land) diameter D", 1e-6),
        ParamSpec::number("land_length", "m", 0.0, "die land length L (0: orifice die)", 0.0),
        ParamSpec::number("entry_fillet_radius", "m", 0.3e-3, "radius of the fillet on the die entry corner", 0.0),
        ParamSpec::number("particle_spacing", "m", std::nullopt, "initial particle spacing dx", 1e-7),
        ParamSpec::number("stroke", "m", 1.0, "the run ends when the ram has moved this far", 0.0),
        ParamSpec::number("steady_window_start", "m", 0.0,
                          "ram displacement from which the steady extrusion pressure is averaged", 0.0),
        ParamSpec::string("billet_lattice", std::string("cubic"),
                          "cubic: lattice clipped to the barrel; rings: polar rings whose outer ring touches the "
                          "barrel wall (wall laws such as navier_slip)",
                          {"cubic", "rings"}),
        ParamSpec::boolean("die", true, "false: no die, the barrel is open at z = 0 (plug flow through the barrel)"),
        ParamSpec::string("die_family", std::string("square"),
                          "die shape (docs/processes/ram_extrusion.md, Dies): square entry, conical entry, the dry-ice "
                          "CS (cone to the barrel wall), WK (arc 1), WP (arc 2), WKWP (arc 1 then arc 2), or a general "
                          "profile",
                          {"square", "conical", "CS", "WK", "WP", "WKWP", "profile"}),
        ParamSpec::number("entry_angle", "rad", std::numbers::pi / 4,
                          "conical / CS: cone half-angle to the axis, e.g. \"45 deg\"", 1e-6, std::numbers::pi / 2),
        ParamSpec::number("insert_height", "m", 0.0,
                          "conical: axial height of the cone (0: the cone reaches the barrel wall)", 0.0),
        ParamSpec::number("arc_radius_1", "m", 0.0, "WK / WKWP: radius R1 of the convex spherical section", 0.0),
        ParamSpec::number("arc_length_1", "m", 0.0, "WK / WKWP: axial length h1 of the convex section", 0.0),
        ParamSpec::number("arc_radius_2", "m", 0.0, "WP / WKWP: radius R2 of the concave spherical section", 0.0),
        ParamSpec::number("arc_length_2", "m", 0.0, "WP / WKWP: axial length h2 of the concave section", 0.0),
        ParamSpec::string("convex_bulge", std::string("outward"),
                          "side of its chord the convex (WK) arc lies on: outward (away from the axis; tangent to the "
                          "barrel at the entry) or inward",
                          {"outward", "inward"}),
        ParamSpec::string("concave_bulge", std::string("inward"),
                          "side of its chord the concave (WP) arc lies on: inward (towards the axis; tangent to the "
                          "land at the exit) or outward",
                          {"outward", "inward"}),
        ParamSpec::array("die_profile", "profile: die wall from the entry (z = 0) down to the exit, "
                                        "[{\"r\": \"14 mm\", \"z\": \"0 mm\", \"fillet\": \"2 mm\"}, ...]"),
        ParamSpec::boolean("fill_die", false,
                           "true: the material also fills the die cavity below z = 0 at the start (dry-ice cases)"),
        ParamSpec::number("steady_window_end", "m", 1e9,
                          "ram displacement up to which the steady extrusion pressure is averaged", 0.0),
        ParamSpec::integer("sector_count", 1,
                           "N when numerics.symmetry is a sector of 360/N deg: the ram force is multiplied by N and "
                           "the rings lattice holds multiples of N per ring (must match numerics.symmetry)",
                           1, 64),
        ParamSpec::number("pressure_section_height_over_barrel_radius", "1", 1.5,
                          "height of the barrel cross-section, above the die face, over which the axial stress is "
                          "averaged, in barrel radii (the paper's P_ex: 1.5)", 0.0),
    });
  return d;
}

}  // namespace

SPHFORGE_PLUGIN(descriptor)
