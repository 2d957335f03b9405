// Process plugin `friction_drilling`: a rotating flow drill (a rigid body of revolution r(z)) fed
// through a thin sheet (a disc clamped at its rim). The drill carries thermal-only particles that
// take its share of the friction heat and conduct heat away from the contact (docs/theory.md
// section 9.1); the process measures axial force, torque, a thermocouple on the upper surface and
// the bushing heights from the particle cloud, counting only material still joined to the clamped
// rim (docs/theory.md section 17, eqs. 120-129 and 127a; sheet_connectivity.hpp).
// Geometry and reference numbers: cases/friction_drilling/reference/friction_drilling.md.
//
// Coordinates: z is the drill axis; the sheet's upper surface is the plane z = 0 and its lower
// surface z = -t; the drill comes from above (+z) and is fed downwards. The drill profile is given
// in the drill's own frame with the tip at z = 0.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <vector>

#include "sheet_connectivity.hpp"
#include "sheet_far_field.hpp"
#include "sphforge/plugin.hpp"

namespace {

using namespace sphforge;
using Vec = Eigen::Vector3d;

/// Name of the per-particle clamp flag (1: part of the fixed rim, eq. 121).
constexpr const char* kClampedField = "clamped";
/// Name of the per-particle flag of the disc's outer ring, which exchanges heat with the sheet
/// beyond the disc (eq. 121b; declared only when that far field is on).
constexpr const char* kRingField = "far_field_ring";

/// The default drill (eq. 120): a typical M4 flow drill simplified to a body of revolution, in mm,
/// tip at z = 0, walked from the top of the modelled shank down to the tip (workpiece on the left,
/// tool.hpp): top face, 3.7 mm cylinder, forming cone (half-angle 19.7 deg), tip cone (half-angle
/// 60 deg, 120 deg included).
std::vector<Eigen::Vector2d> default_profile_mm() {
  return {{0.0, 9.0}, {1.85, 9.0}, {1.85, 3.85}, {0.6, 0.35}, {0.0, 0.0}};
}

class FrictionDrilling final : public Process {
 public:
  explicit FrictionDrilling(const ParamValues& p) {
    radius_ = 0.5 * p.number("sheet_diameter");
    thickness_ = p.number("sheet_thickness");
    spacing_ = p.number("particle_spacing");
    refined_radius_ = 0.5 * p.number("refined_diameter");
    fine_spacing_ = spacing_;
    if (refined_radius_ > 0.0) {
      // The refined centre (eq. 121c): the coarse lattice's cells within it split into ratio^3 cells.
      fine_spacing_ = p.number("refined_spacing");
      if (!(fine_spacing_ > 0.0) || fine_spacing_ >= spacing_)
        p.fail("refined_spacing", "must be positive and finer than particle_spacing when refined_diameter is set");
      refine_ratio_ = static_cast<int>(std::lround(spacing_ / fine_spacing_));
      if (std::abs(refine_ratio_ * fine_spacing_ - spacing_) > 1e-9 * spacing_)
        p.fail("refined_spacing", "particle_spacing must be a whole multiple of it (the refined cells tile the coarse ones)");
      if (p.integer("sector_count") > 1)
        p.fail("refined_diameter", "a refined centre needs the full disc (sector_count 1, no numerics.symmetry): the core "
               "does not run a sector with particles of several spacings");
    }
    clamp_width_ = p.number("clamp_width");
    clamp_temperature_ = p.number("clamp_temperature");
    far_radius_ = p.number("sheet_far_field_radius");
    if (far_radius_ > 0.0) {
      if (far_radius_ <= radius_) p.fail("sheet_far_field_radius", "must exceed the disc radius (0: no far field)");
      if (clamp_temperature_ > 0.0)
        p.fail("sheet_far_field_radius", "choose one heat path at the rim: clamp_temperature or the far field");
    }
    feed_ = p.number("feed_rate");
    speed_ = p.number("rotation_speed");
    stroke_ = p.number("stroke");
    gap_ = p.number("initial_gap");
    drill_body_ = p.boolean("drill_body");
    drill_material_ = p.string("drill_material");
    drill_body_length_ = p.number("drill_body_length");
    probe_radius_ = p.number("probe_radius");
    band_outer_ = p.number("bushing_outer_radius");
    rank_ = static_cast<std::size_t>(p.integer("bushing_rank"));
    sectors_ = static_cast<int>(p.integer("sector_count"));
    // Eq. 127a: 1.5 dx links the lattice neighbours at dx and sqrt(2) dx, but not particles across
    // the gap of one missing layer (2 dx) nor the cube diagonal (sqrt(3) dx, reached through the others).
    link_ = p.number("bushing_link_distance") > 0.0 ? p.number("bushing_link_distance") : 1.5 * spacing_;
    if (link_ <= spacing_ * (1.0 + 1e-9))
      p.fail("bushing_link_distance", "must exceed particle_spacing (0: 1.5 x particle_spacing), else the intact "
             "lattice falls apart");
    bushing_interval_ = p.number("bushing_interval");
    if (thickness_ < 2.0 * spacing_ - 1e-12)
      p.fail("particle_spacing", "too coarse: need at least 2 particle layers over the sheet thickness");
    if (clamp_width_ >= radius_) p.fail("clamp_width", "must be smaller than the sheet radius");
    if (probe_radius_ >= radius_ - clamp_width_) p.fail("probe_radius", "the probe must lie on the free sheet, inside the clamped rim");

    std::vector<Eigen::Vector2d> points;
    if (p.has("drill_profile") && p.raw("drill_profile").is_array() && !p.raw("drill_profile").empty()) {
      for (const auto& [r, z] : p.pairs("drill_profile", "m", "m")) points.emplace_back(r, z);
    } else {
      for (const Eigen::Vector2d& q : default_profile_mm()) points.push_back(1e-3 * q);
    }
    try {
      profile_ = ToolProfile(points);
      if (p.number("drill_fillet_radius") > 0.0) profile_ = profile_.with_fillets(p.number("drill_fillet_radius"));
    } catch (const std::invalid_argument& e) {
      p.fail(p.number("drill_fillet_radius") > 0.0 ? "drill_fillet_radius" : "drill_profile", e.what());
    }
    for (const Eigen::Vector2d& q : profile_.vertices()) drill_radius_ = std::max(drill_radius_, q.x());
    band_inner_ = p.number("bushing_inner_radius") > 0.0 ? p.number("bushing_inner_radius") : drill_radius_;
    if (band_outer_ <= band_inner_) p.fail("bushing_outer_radius", "must exceed the bushing inner radius (default: the drill radius)");
    if (band_outer_ >= radius_ - clamp_width_) p.fail("bushing_outer_radius", "must lie inside the clamped rim");
    if (refined_radius_ > 0.0 && refined_radius_ >= radius_ - clamp_width_ - 1.5 * spacing_)
      p.fail("refined_diameter", "the refined centre must end inside the clamped rim and the far field's ring");
  }

  std::vector<FieldInfo> fields() const override {
    std::vector<FieldInfo> f = {FieldInfo{kClampedField, 1, "1", FieldType::Int64, true}};
    if (far_radius_ > 0.0) f.push_back(FieldInfo{kRingField, 1, "1", FieldType::Int64, false});
    return f;
  }

  void build(SceneBuilder& scene) override {
    // Sheet: a cell-centred cubic lattice clipped to the disc (centres inside r <= R - dx/2, so
    // the lattice's material volume ends at about R), layers at z = -t + (k + 1/2) dx. The
    // half-integer sites about the axis make the lattice map onto itself under 90 deg rotations
    // (a sector, docs/theory.md eq. 30).
    // A refined centre (eq. 121c): every coarse cell whose centre lies within refined_radius is
    // split into ratio^3 cells of the fine spacing, which tile it exactly, so the sheet's volume and
    // surfaces are those of the coarse lattice.
    const int nr = static_cast<int>(std::ceil(radius_ / spacing_)) + 1;
    const int nz = std::max(2, static_cast<int>(std::lround(thickness_ / spacing_)));
    std::vector<Vec> sheet;
    std::vector<double> sheet_spacing;
    for (int k = 0; k < nz; ++k)
      for (int j = -nr; j < nr; ++j)
        for (int i = -nr; i < nr; ++i) {
          const double x = (i + 0.5) * spacing_, y = (j + 0.5) * spacing_;
          if (std::hypot(x, y) > radius_ - 0.5 * spacing_ + 1e-9 * spacing_) continue;
          const double z = -thickness_ + (k + 0.5) * spacing_;
          if (refined_radius_ > 0.0 && std::hypot(x, y) < refined_radius_) {
            for (int c = 0; c < refine_ratio_; ++c)
              for (int b = 0; b < refine_ratio_; ++b)
                for (int a = 0; a < refine_ratio_; ++a) {
                  const double o = -0.5 * spacing_ + 0.5 * fine_spacing_;  // first fine centre in the cell
                  sheet.emplace_back(x + o + a * fine_spacing_, y + o + b * fine_spacing_, z + o + c * fine_spacing_);
                  sheet_spacing.push_back(fine_spacing_);
                }
          } else {
            sheet.emplace_back(x, y, z);
            sheet_spacing.push_back(spacing_);
          }
        }
    BodySpec sheet_spec;
    sheet_spec.name = "sheet";
    sheet_spec.positions = std::move(sheet);
    sheet_spec.spacing_m = spacing_;
    if (refined_radius_ > 0.0) sheet_spec.particle_spacings_m = std::move(sheet_spacing);
    sheet_body_ = scene.add_body(std::move(sheet_spec));
    // The layers span nz dx; with t not a multiple of dx the top surface is at -t + nz dx.
    top_ = -thickness_ + nz * spacing_;

    // Drill: tip at height top + gap. The upper particle layer lies dx/2 below the surface and a
    // particle touches a tool closer than dx/2 (theory section 3), so with gap 0 the tip touches
    // the sheet at t = 0 and depth 0 is first contact.
    RigidTool drill("drill", profile_);
    tip_start_ = top_ + gap_;
    drill.axial_offset_m = tip_start_;
    drill.angular_velocity_rad_s = speed_;
    drill_ = scene.add_tool(std::move(drill));

    if (!drill_body_) return;
    // The drill's thermal body (eq. 122): the lattice sites inside the profile, up to
    // drill_body_length above the tip, each moved along the profile's normal onto the nearest depth
    // (n + 1/2) dx behind the surface, so that the outer layer sits dx/2 behind the wall as the
    // sheet's particles sit dx/2 in front: perfect thermal contact (theory eq. 92). The sites of
    // the slab n dx <= depth < (n + 1) dx go to its middle, so every slab keeps its particles and
    // the body its volume. Without the move, a cubic lattice cut by the cones and the 3.7 mm
    // cylinder left the surface about 1.0 dx from its nearest drill particle instead of the
    // 0.65 dx of a lattice aligned with a flat wall (2026-12-06, eq. 122).
    // With a refined centre the drill body takes the fine spacing, that of the sheet it touches.
    const double ds = fine_spacing_;
    std::vector<Vec> body;
    const int nb = static_cast<int>(std::ceil(drill_radius_ / ds)) + 1;
    const int nzb = static_cast<int>(std::floor(drill_body_length_ / ds));
    Eigen::Vector2d normal;
    for (int k = 0; k < nzb; ++k)
      for (int j = -nb; j < nb; ++j)
        for (int i = -nb; i < nb; ++i) {
          const double x = (i + 0.5) * ds, y = (j + 0.5) * ds, z = (k + 0.5) * ds;
          const double r = std::hypot(x, y);
          const double d = profile_.signed_distance({r, z}, normal);
          if (d > 0.0) continue;
          const double depth = (std::floor(-d / ds) + 0.5) * ds;
          const double move = -depth - d;  // along the outward normal, |move| <= dx/2
          // r >= dx/sqrt(2) on this lattice, so r_new > 0.2 dx: the site keeps its azimuth.
          const double r_new = r + move * normal.x(), z_new = z + move * normal.y();
          body.emplace_back(x * r_new / r, y * r_new / r, z_new + tip_start_);
        }
    if (body.empty()) throw std::invalid_argument("friction_drilling: the drill body holds no particle at this spacing");
    scene.add_tool_body("drill_body", std::move(body), ds, drill_material_, "drill");
  }

  void bind_signals(SignalBus& bus) override {
    bus.add_command("drill_feed_rate", "m/s", &feed_);
    bus.add_command("drill_rotation_speed", "rad/s", &speed_);
    bus.add_measured("drill_axial_force", "N", &axial_force_);
    bus.add_measured("drill_torque", "N*m", &torque_);
    bus.add_measured("drill_depth", "m", &depth_);
    bus.add_measured("probe_temperature", "K", &probe_temperature_);
    bus.add_measured("sheet_temperature_max", "K", &temperature_max_);
  }

  void initialize(ProcessContext& ctx) override {
    FieldRegistry& f = *ctx.fields;
    const double* x = f.f64(field::position);
    const std::int64_t* ids = f.i64(field::id);
    std::int64_t* clamped = f.i64(kClampedField);
    // Fixed rim (eq. 121): every sheet particle within clamp_width of the sheet's edge.
    for (std::size_t i = 0; i < f.size(); ++i)
      clamped[i] = i < ctx.mechanical_count && std::hypot(x[3 * i], x[3 * i + 1]) >= radius_ - clamp_width_ ? 1 : 0;
    // The sheet beyond the disc (eq. 121b): the outer ring of lattice sites (centres within 1.5 dx of
    // the edge; the lattice is clipped at R - dx/2) exchanges heat with it.
    if (far_radius_ > 0.0 && f.f64_if(field::temperature)) {
      std::int64_t* ring = f.i64(kRingField);
      const double* T = f.f64(field::temperature);
      double radius_sum = 0.0, T_sum = 0.0;
      std::size_t count = 0;
      for (std::size_t i = 0; i < f.size(); ++i) {
        const double r = std::hypot(x[3 * i], x[3 * i + 1]);
        ring[i] = i < ctx.mechanical_count && r > radius_ - 1.5 * spacing_ ? 1 : 0;
        if (ring[i]) radius_sum += r, T_sum += T[i], ++count;
      }
      if (count == 0) throw std::invalid_argument("friction_drilling: no particle on the disc's rim for the far field");
      ring_count_ = static_cast<double>(count);
      const double T_ring = T_sum / count;
      sheet_thermal_properties(ctx, T_ring);
      ring_heat_capacity_ = far_heat_capacity_ * ring_count_ * spacing_ * spacing_ * spacing_;
      far_field_.emplace(radius_sum / count, radius_, far_radius_, thickness_eff(), 2.0 * std::numbers::pi / sectors_,
                         far_conductivity_, far_heat_capacity_, T_ring, spacing_);
    }
    // Thermocouple (eq. 126): the upper-surface sheet particle nearest (probe_radius, 0, top).
    if (f.f64_if(field::temperature)) {
      const Vec target(probe_radius_, 0.0, top_);
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t i = 0; i < ctx.mechanical_count; ++i) {
        const double d2 = (Vec(x[3 * i], x[3 * i + 1], x[3 * i + 2]) - target).squaredNorm();
        if (d2 < best) {
          best = d2;
          probe_index_ = i;
        }
      }
      probe_id_ = ids[probe_index_];
      probe_position_ = Vec(x[3 * probe_index_], x[3 * probe_index_ + 1], x[3 * probe_index_ + 2]);
    }
  }

  void before_step(ProcessContext& ctx) override {
    // Commands are physical (eq. 123); the tool runs f times faster in the scaled time (eq. 25).
    RigidTool& drill = (*ctx.tools)[drill_];
    drill.axial_velocity_m_s = -feed_ * ctx.time_scaling;
    drill.angular_velocity_rad_s = speed_ * ctx.time_scaling;
  }

  bool constrains_velocities() const override { return true; }

  void apply_constraints(ProcessContext& ctx) override {
    // Clamped rim (eq. 121): zero velocity and acceleration, so the rim never moves.
    FieldRegistry& f = *ctx.fields;
    const std::int64_t* clamped = f.i64(kClampedField);
    double* v = f.f64(field::velocity);
    double* a = f.f64(field::acceleration);
    const std::size_t n = ctx.mechanical_count;
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      if (!clamped[i]) continue;
      for (int d = 0; d < 3; ++d) {
        v[3 * i + d] = 0.0;
        a[3 * i + d] = 0.0;
      }
    }
    // A clamp held at a given temperature (eq. 121a): the rim relaxes onto it within each step.
    double* dT = clamp_temperature_ > 0.0 ? f.f64_if(field::temperature_rate) : nullptr;
    if (dT && ctx.dt_s > 0.0) {
      const double* T = f.f64(field::temperature);
      for (std::size_t i = 0; i < n; ++i)
        if (clamped[i]) dT[i] = (clamp_temperature_ - T[i]) / ctx.dt_s;
    }
    // The sheet beyond the disc (eq. 121b): over the step's process time f dt the far field takes
    // the heat P from the ring at its mean temperature, and the ring loses it evenly (its
    // temperature falls by P f dt / C_ring).
    double* dT_ring = far_field_ ? f.f64_if(field::temperature_rate) : nullptr;
    if (dT_ring && ctx.dt_s > 0.0) {
      const double* T = f.f64(field::temperature);
      const std::int64_t* ring = f.i64(kRingField);
      double T_sum = 0.0;
#pragma omp parallel for reduction(+ : T_sum) schedule(static)
      for (std::size_t i = 0; i < n; ++i)
        if (ring[i]) T_sum += T[i];
      const double process_dt = ctx.time_scaling * ctx.dt_s;
      const double P = far_field_->advance(T_sum / ring_count_, process_dt);
      const double rate = ctx.time_scaling * P / ring_heat_capacity_;
#pragma omp parallel for schedule(static)
      for (std::size_t i = 0; i < n; ++i)
        if (ring[i]) dT_ring[i] -= rate;
      far_field_heat_ = sectors_ * P;
      far_field_energy_ = sectors_ * far_field_->absorbed_J();
    }
  }

  void measure(ProcessContext& ctx) override {
    const RigidTool& drill = (*ctx.tools)[drill_];
    FieldRegistry& f = *ctx.fields;
    // Eq. 123-124: the reaction on the drill; a sector carries 1/N of it (theory section 11).
    axial_force_ = sectors_ * drill.reaction_force_N.z();  // the sheet pushes the drill up (+z)
    torque_ = -sectors_ * drill.reaction_torque_Nm;        // resisting torque the spindle supplies
    tip_z_ = drill.axial_offset_m;
    depth_ = top_ - tip_z_;  // tip below the original upper surface (negative before it reaches it)
    process_time_ = ctx.time_s * ctx.time_scaling;
    feed_out_ = feed_;
    speed_out_ = speed_;

    const std::size_t n = ctx.mechanical_count;
    // Sheet temperatures (eq. 125-126).
    if (const double* T = f.f64_if(field::temperature)) {
      double tmax = -std::numeric_limits<double>::infinity();
#pragma omp parallel for reduction(max : tmax) schedule(static)
      for (std::size_t i = 0; i < n; ++i) tmax = std::max(tmax, T[i]);
      temperature_max_ = tmax;
      const std::int64_t* ids = f.i64(field::id);
      if (ids[probe_index_] != probe_id_)  // the core reordered the particles: look the id up again
        for (std::size_t i = 0; i < f.size(); ++i)
          if (ids[i] == probe_id_) {
            probe_index_ = i;
            break;
          }
      probe_temperature_ = T[probe_index_];
    }
    // Material separation state (docs/failure.md): how many sheet particles have failed, and the
    // largest equivalent plastic strain (the failure criterion's variable).
    if (const double* failed = f.f64_if(field::failed)) {
      double count = 0.0;
#pragma omp parallel for reduction(+ : count) schedule(static)
      for (std::size_t i = 0; i < n; ++i) count += failed[i] > 0.5 ? 1.0 : 0.0;
      failed_ = count;
    }
    if (const double* eps = f.f64_if(field::plastic_strain)) {
      double emax = 0.0;
#pragma omp parallel for reduction(max : emax) schedule(static)
      for (std::size_t i = 0; i < n; ++i) emax = std::max(emax, eps[i]);
      plastic_strain_max_ = emax;
    }
    // Bushing (eqs. 127-129, 127a) every bushing_interval of simulated time, on the same grid as
    // the core's history rows (the Process API does not say which steps write a row: with
    // bushing_interval = run.history_interval, or a divisor of it, each row holds the bushing of its
    // own step), and on the final state when the stroke ends the run (finished() then stops the loop).
    if (ctx.time_s >= next_bushing_ || depth_ >= stroke_) {
      measure_bushing(f, n);
      while (next_bushing_ <= ctx.time_s) next_bushing_ += bushing_interval_;
    }

    if (ctx.dt_s > 0.0) {
      if (axial_force_ > max_force_) {
        max_force_ = axial_force_;
        max_force_time_ = process_time_;
        max_force_depth_ = depth_;
      }
      max_torque_ = std::max(max_torque_, torque_);
      if (probe_temperature_ > max_probe_) {
        max_probe_ = probe_temperature_;
        max_probe_time_ = process_time_;
      }
      max_temperature_ = std::max(max_temperature_, temperature_max_);
    }
  }

  bool finished(const ProcessContext&) const override { return depth_ >= stroke_; }

  // Restart (docs/checkpoints.md): the maxima and the bushing, which is measured only every
  // bushing_interval. The thermocouple particle is found again by id; the signals are on the bus.
  bool supports_restart() const override { return true; }
  nlohmann::json save_state() const override {
    return {{"next_bushing", next_bushing_},
            {"bushing", {upper_, lower_, total_, detached_}},
            {"max_force", {max_force_, max_force_time_, max_force_depth_}},
            {"max_torque", max_torque_},
            {"max_probe", {max_probe_, max_probe_time_}},
            {"max_temperature", max_temperature_},
            {"far_field", far_field_ ? nlohmann::json{{"temperatures", far_field_->temperatures()},
                                                      {"absorbed_J", far_field_->absorbed_J()}}
                                     : nlohmann::json()}};
  }
  void restore_state(const nlohmann::json& s) override {
    auto at = [](const nlohmann::json& a, std::size_t k) { return a.at(k).get<double>(); };
    next_bushing_ = s.at("next_bushing").get<double>();
    const nlohmann::json& b = s.at("bushing");
    upper_ = at(b, 0), lower_ = at(b, 1), total_ = at(b, 2), detached_ = at(b, 3);
    const nlohmann::json& f = s.at("max_force");
    max_force_ = at(f, 0), max_force_time_ = at(f, 1), max_force_depth_ = at(f, 2);
    max_torque_ = s.at("max_torque").get<double>();
    const nlohmann::json& q = s.at("max_probe");
    max_probe_ = at(q, 0), max_probe_time_ = at(q, 1);
    max_temperature_ = s.at("max_temperature").get<double>();
    if (far_field_) {
      const nlohmann::json& ff = s.at("far_field");
      far_field_->set_temperatures(ff.at("temperatures").get<std::vector<double>>());
      far_field_->set_absorbed_J(ff.at("absorbed_J").get<double>());
      far_field_energy_ = sectors_ * far_field_->absorbed_J();
    }
  }

  std::vector<HistoryColumn> history_columns() const override {
    std::vector<HistoryColumn> columns = {{"process_time_s", &process_time_},
            {"drill_tip_z_m", &tip_z_},
            {"drill_depth_m", &depth_},
            {"drill_feed_rate_m_s", &feed_out_},
            {"drill_rotation_speed_rad_s", &speed_out_},
            {"axial_force_N", &axial_force_},
            {"torque_Nm", &torque_},
            {"probe_temperature_K", &probe_temperature_},
            {"sheet_temperature_max_K", &temperature_max_},
            {"bushing_upper_m", &upper_},
            {"bushing_lower_m", &lower_},
            {"bushing_total_m", &total_},
            {"bushing_detached_particles_1", &detached_},
            {"failed_particles_1", &failed_},
            {"plastic_strain_max_1", &plastic_strain_max_}};
    if (far_radius_ > 0.0) {
      columns.push_back({"far_field_heat_W", &far_field_heat_});
      columns.push_back({"far_field_energy_J", &far_field_energy_});
    }
    return columns;
  }

  nlohmann::json metrics() const override {
    nlohmann::json m;
    m["max_axial_force_N"] = max_force_;
    m["max_axial_force_process_time_s"] = max_force_time_;
    m["max_axial_force_depth_m"] = max_force_depth_;
    m["max_torque_Nm"] = max_torque_;
    m["max_probe_temperature_K"] = max_probe_;
    m["max_probe_temperature_degC"] = max_probe_ - 273.15;
    m["max_probe_temperature_process_time_s"] = max_probe_time_;
    m["probe_x0_m"] = probe_position_.x();
    m["probe_y0_m"] = probe_position_.y();
    m["probe_z0_m"] = probe_position_.z();
    m["max_sheet_temperature_K"] = max_temperature_;
    m["bushing_upper_m"] = upper_;
    m["bushing_lower_m"] = lower_;
    m["bushing_total_m"] = total_;
    m["bushing_detached_particles"] = detached_;
    m["bushing_link_distance_m"] = link_;
    m["final_drill_depth_m"] = depth_;
    m["final_process_time_s"] = process_time_;
    m["sheet_thickness_lattice_m"] = thickness_eff();
    m["sector_count"] = sectors_;
    m["refined_diameter_m"] = 2.0 * refined_radius_;
    m["refined_spacing_m"] = fine_spacing_;
    m["failed_particles"] = failed_;
    m["plastic_strain_max"] = plastic_strain_max_;
    if (far_radius_ > 0.0) {
      m["far_field_energy_J"] = far_field_energy_;
      // The sheet material's values the annulus uses (eq. 121b), for the record.
      m["far_field_conductivity_W_per_m_K"] = far_conductivity_;
      m["far_field_heat_capacity_J_per_m3_K"] = far_heat_capacity_;
    }
    return m;
  }

 private:
  /// The far field's k and rho c (eq. 121b) are the sheet material's, taken from the material plugin
  /// so that the case states them once. The annulus is linear: with temperature-dependent properties
  /// it keeps the values at the rim's initial temperature T (a restart rebuilds the initial scene
  /// before initialize(), so it gets the same values).
  void sheet_thermal_properties(const ProcessContext& ctx, double T) {
    if (!ctx.materials) throw std::logic_error("friction_drilling: the core gives no materials to the process");
    const BodyRange& sheet = (*ctx.bodies)[sheet_body_];
    const Material& material = *(*ctx.materials)[sheet.material];
    double k = 0.0, c = 0.0;
    ThermalBatch batch{1, &T, &k, &c, ctx.fields, sheet.first};
    material.thermal_properties(batch);
    far_conductivity_ = k;
    far_heat_capacity_ = material.reference_density() * c;
    if (!(far_conductivity_ > 0.0 && far_heat_capacity_ > 0.0))
      throw std::invalid_argument("friction_drilling: the far field needs a sheet material that conducts heat");
  }

  /// Sheet thickness as built: nz dx (equals the nominal t when t is a multiple of dx).
  double thickness_eff() const { return top_ + thickness_; }

  /// Bushing heights (eqs. 127-129): the rank-th highest and lowest sheet particle in the band
  /// band_inner <= r <= band_outer around the hole, among the particles joined to the clamped rim
  /// (eq. 127a); particle centres lie dx/2 inside the surface.
  void measure_bushing(FieldRegistry& f, std::size_t n) {
    friction_drilling::SheetParticles sheet;
    sheet.count = n;
    sheet.position = f.f64(field::position);
    sheet.seed = f.i64(kClampedField);
    // The core's bond rule (eqs. 111-112) on the flags and stresses the next step starts from.
    sheet.failed = f.f64_if(field::failed);
    sheet.pressure = f.f64_if(field::pressure);
    sheet.deviatoric_stress = f.f64_if(field::deviatoric_stress);
    if (!sheet.pressure || !sheet.deviatoric_stress) sheet.failed = nullptr;
    // A refined centre: each particle's link is the link distance x s_i / dx (eq. 121c), s_i / dx
    // read from its smoothing length over the largest (the coarse particles').
    if (const double* hl = refined_radius_ > 0.0 ? f.f64_if(field::smoothing_length) : nullptr) {
      double hmax = 0.0;
      for (std::size_t i = 0; i < n; ++i) hmax = std::max(hmax, hl[i]);
      link_of_.resize(n);
      for (std::size_t i = 0; i < n; ++i) link_of_[i] = link_ * hl[i] / hmax;
      sheet.link = link_of_.data();
    }
    connectivity_.compute(sheet, link_, sectors_);
    const friction_drilling::BandExtremes e =
        friction_drilling::band_extremes(sheet, &connectivity_, band_inner_, band_outer_, rank_, highest_, lowest_);
    const double t = thickness_eff();
    if (e.found) {
      // The bushing's particles come from the hole: with a refined centre they have the fine spacing.
      upper_ = std::max(0.0, e.z_high + 0.5 * fine_spacing_ - top_);
      lower_ = std::max(0.0, (top_ - t) - (e.z_low - 0.5 * fine_spacing_));
    } else {
      upper_ = lower_ = 0.0;
    }
    total_ = upper_ + t + lower_;
    detached_ = static_cast<double>(e.detached);
  }

  // Parameters.
  double radius_ = 0.0, thickness_ = 0.0, spacing_ = 0.0, clamp_width_ = 0.0, stroke_ = 0.0, gap_ = 0.0;
  // Refined centre (eq. 121c): radius (0: none), its spacing (= spacing_ without one), and
  // refine_ratio_ = spacing_ / fine_spacing_.
  double refined_radius_ = 0.0, fine_spacing_ = 0.0;
  int refine_ratio_ = 1;
  std::vector<double> link_of_;
  double clamp_temperature_ = -1.0;
  double far_radius_ = 0.0, far_conductivity_ = 0.0, far_heat_capacity_ = 0.0;
  double drill_body_length_ = 0.0, probe_radius_ = 0.0, band_inner_ = 0.0, band_outer_ = 0.0;
  double drill_radius_ = 0.0;
  bool drill_body_ = true;
  std::string drill_material_;
  std::size_t rank_ = 3;
  int sectors_ = 1;
  double link_ = 0.0, bushing_interval_ = 0.0;
  ToolProfile profile_;
  // Commands (physical units, eq. 123).
  double feed_ = 0.0, speed_ = 0.0;
  // Scene.
  std::size_t drill_ = 0;
  double top_ = 0.0, tip_start_ = 0.0;
  std::size_t probe_index_ = 0;
  std::int64_t probe_id_ = -1;
  Vec probe_position_ = Vec::Zero();
  // Measured.
  double process_time_ = 0.0, tip_z_ = 0.0, depth_ = 0.0, feed_out_ = 0.0, speed_out_ = 0.0;
  double axial_force_ = 0.0, torque_ = 0.0, probe_temperature_ = 0.0, temperature_max_ = 0.0;
  double upper_ = 0.0, lower_ = 0.0, total_ = 0.0, failed_ = 0.0, plastic_strain_max_ = 0.0;
  double detached_ = 0.0;
  // The sheet beyond the disc (eq. 121b): heat flow into it (W, whole disc) and its total (J).
  std::optional<friction_drilling::SheetFarField> far_field_;
  // The ring's particle count is fixed at initialize(): the flag moves with its particles, none is deleted.
  double ring_count_ = 0.0, ring_heat_capacity_ = 0.0, far_field_heat_ = 0.0, far_field_energy_ = 0.0;
  std::size_t sheet_body_ = 0;  ///< the sheet's body index (add_body's, = ProcessContext::bodies')
  // Bushing evaluation: next simulated time, connectivity and band scratch (storage kept between calls).
  double next_bushing_ = 0.0;
  friction_drilling::SheetConnectivity connectivity_;
  std::vector<double> highest_, lowest_;
  double max_force_ = 0.0, max_force_time_ = 0.0, max_force_depth_ = 0.0, max_torque_ = 0.0;
  double max_probe_ = 0.0, max_probe_time_ = 0.0, max_temperature_ = 0.0;
};

const PluginDescriptor& descriptor() {
  static const PluginDescriptor d = make_plugin_descriptor<FrictionDrilling>(
      "friction_drilling", "0.1.0",
      "flow drill (rigid r(z) profile, rotating and fed, with a conducting thermal body) through a sheet disc "
      "clamped at its rim; force, torque, thermocouple, bushing heights (docs/processes/friction_drilling.md)",
      {
          ParamSpec::number("sheet_diameter", "m", 10e-3, "diameter of the sheet disc", 1e-6),
          ParamSpec::number("sheet_thickness", "m", 1.2e-3, "sheet thickness t (upper surface at z = 0)", 1e-6),
          ParamSpec::number("particle_spacing", "m", std::nullopt, "lattice spacing dx of the sheet and the drill body", 1e-7),
          ParamSpec::number("refined_diameter", "m", 0.0,
                            "diameter of a refined centre (eq. 121c; the paper: 5 mm): the coarse cells whose centres "
                            "lie inside it are split into cells of refined_spacing; the full disc only (sector_count 1); "
                            "0: one spacing everywhere", 0.0),
          ParamSpec::number("refined_spacing", "m", 0.0,
                            "particle spacing inside refined_diameter (the paper: 0.2 mm); particle_spacing must be a "
                            "whole multiple of it; the drill body takes it too", 0.0),
          ParamSpec::number("clamp_width", "m", 0.5e-3, "width of the fixed rim ring at the sheet's edge (eq. 121)", 0.0),
          ParamSpec::number("clamp_temperature", "K", -1.0,
                            "temperature the clamped rim is held at (a heat sink, eq. 121a); -1: the rim is "
                            "clamped mechanically only and conducts like the rest of the sheet"),
          ParamSpec::number("sheet_far_field_radius", "m", 0.0,
                            "outer radius of the sheet beyond the disc that takes heat from the disc's rim (eq. 121b): "
                            "a thin annulus, radial conduction only, faces adiabatic; 0: none (the rim is adiabatic)", 0.0),
          ParamSpec::number("feed_rate", "m/s", 50e-3 / 60.0,
                            "initial value of the command drill_feed_rate (downwards, physical; x time_scaling)", 0.0),
          ParamSpec::number("rotation_speed", "rad/s", 5800.0 * 2.0 * std::numbers::pi / 60.0,
                            "initial value of the command drill_rotation_speed (about +z, physical; x time_scaling)"),
          ParamSpec::number("stroke", "m", 7.5e-3, "the run ends when the drill tip is this far below the upper surface", 0.0),
          ParamSpec::number("initial_gap", "m", 0.0, "height of the drill tip above the upper surface at t = 0 (0: touching)", 0.0),
          ParamSpec::array("drill_profile",
                           "drill r(z) [[r, z], ...] in the drill frame (tip at z = 0), walked from the top down to the "
                           "tip; default: the M4 flow drill of eq. 120"),
          ParamSpec::number("drill_fillet_radius", "m", 0.0, "radius of the arcs rounding the profile's corners", 0.0),
          ParamSpec::boolean("drill_body", true,
                             "true: the drill carries thermal-only particles (conduction, its friction-heat share)"),
          ParamSpec::string("drill_material", std::string("drill"), "key in the case's \"materials\" of the drill body"),
          ParamSpec::number("drill_body_length", "m", 6e-3,
                            "length of the drill (from the tip) filled with thermal particles, at most the "
                            "profile's height (default profile: 9 mm)", 0.0),
          ParamSpec::number("probe_radius", "m", 4e-3, "thermocouple: distance from the axis on the upper surface (eq. 126)", 0.0),
          ParamSpec::number("bushing_inner_radius", "m", 0.0,
                            "inner radius of the band in which the bushing is measured (0: the drill's largest radius)", 0.0),
          ParamSpec::number("bushing_outer_radius", "m", 3.5e-3, "outer radius of the bushing band (eq. 127)", 0.0),
          ParamSpec::integer("bushing_rank", 3,
                             "the bushing ends at the rank-th highest / lowest particle of the band (robust to a stray "
                             "particle, eq. 127)", 1, 1000),
          ParamSpec::number("bushing_link_distance", "m", 0.0,
                            "the bushing counts only particles joined to the clamped rim by a chain of links: pairs "
                            "closer than this whose bond the core's failure rule has not broken (eq. 127a); 0: 1.5 x "
                            "particle_spacing (links the lattice neighbours at dx and sqrt(2) dx, not across a "
                            "missing particle layer)", 0.0),
          ParamSpec::number("bushing_interval", "s", 5e-5,
                            "simulated time between two evaluations of the bushing and its connectivity (eq. 127a; "
                            "the history shows the latest): use run.history_interval or a divisor of it", 1e-12),
          ParamSpec::integer("sector_count", 1,
                             "N when numerics.symmetry is a sector of 360/N deg (force and torque x N; the bushing's "
                             "connectivity passes through the cut planes, eq. 127a)", 1, 64),
      });
  return d;
}

}  // namespace

SPHFORGE_PLUGIN(descriptor)
