// Process plugin `friction_extrusion`: a billet in a fixed container under a die that rotates
// about z and plunges along -z; material leaves upwards through the die's central orifice as a rod
// (the force-controlled AA7075 friction extrusion of cases/friction_extrusion/reference/).
//
// Coordinates: z is the axis, the container bottom is the plane z = 0, the billet occupies
// 0 < z < H inside r < R (container radius), and the die face starts at z = H. Equations:
// docs/theory.md section 15 (eqs. 100-109); parameters: docs/processes/friction_extrusion.md.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "sphforge/errors.hpp"
#include "sphforge/plugin.hpp"

namespace {

using namespace sphforge;
using Vec = Eigen::Vector3d;

constexpr double kGasConstant = 8.314462618;  // J/(mol K), Zener-Hollomon (eq. 106)

/// An array parameter of lengths ("6.25 mm" or SI numbers), any count >= 1.
std::vector<double> lengths(const ParamValues& p, const std::string& name) {
  const json& v = p.raw(name);
  if (!v.is_array() || v.empty()) p.fail(name, "expected a non-empty array of lengths");
  return p.quantities(name, v.size(), "m");
}

/// Appends one ring of particle sites at radius r and height z: about 2 pi r / dx sites, a multiple
/// of the sector count and half a pitch off the cut planes, so that a 360/N deg sector maps onto
/// itself (theory eq. 30).
void append_ring(std::vector<Vec>& sites, double r, double z, double dx, int sectors) {
  const long per_sector = std::max(1L, std::lround(2.0 * std::numbers::pi * r / (dx * sectors)));
  const long count = per_sector * sectors;
  for (long m = 0; m < count; ++m) {
    const double angle = 2.0 * std::numbers::pi * (m + 0.5) / static_cast<double>(count);
    sites.emplace_back(r * std::cos(angle), r * std::sin(angle), z);
  }
}

class FrictionExtrusion final : public Process {
 public:
  explicit FrictionExtrusion(const ParamValues& p) : file_(p.file()) {
    radius_ = 0.5 * p.number("billet_diameter");
    height_ = p.number("billet_height");
    orifice_radius_ = 0.5 * p.number("orifice_diameter");
    orifice_length_ = p.number("orifice_length");
    edge_fillet_ = p.number("orifice_edge_fillet");
    face_depth_ = p.number("face_cone_depth");
    spacing_ = p.number("particle_spacing");
    stroke_ = p.number("stroke");
    sectors_ = static_cast<int>(p.integer("sector_count"));
    thermal_tools_ = p.boolean("thermal_tool_bodies");
    die_thickness_ = p.number("die_body_thickness");
    wall_thickness_ = p.number("container_wall_thickness");
    bottom_thickness_ = p.number("container_bottom_thickness");
    h_die_ = p.number("die_convection_coefficient");
    h_bottom_ = p.number("container_bottom_convection_coefficient");
    h_other_ = p.number("other_convection_coefficient");
    cooled_T_ = p.number("cooled_surface_temperature");
    beta_ = p.number("taylor_quinney");
    activation_ = p.number("activation_energy");
    target_ = p.number("target_force");
    band_ = p.number("settling_band");
    metrics_start_ = p.number("metrics_start_time");
    sample_interval_ = p.number("metrics_sample_interval");
    if (!(orifice_radius_ < radius_)) p.fail("orifice_diameter", "the orifice must be narrower than the billet");
    if (spacing_ * 4 > height_ || spacing_ * 2 > 2 * orifice_radius_ + 1e-12)
      p.fail("particle_spacing", "too coarse: need at least 4 particles over the billet height and 2 across the orifice");
    if (edge_fillet_ > 0.0 && edge_fillet_ > 0.5 * std::min(orifice_length_, radius_ - orifice_radius_))
      p.fail("orifice_edge_fillet", "does not fit on the die face and the orifice wall");
    // Thermocouples in the billet: every radius at every depth below the billet top.
    const std::vector<double> radii = lengths(p, "billet_thermocouple_radii");
    const std::vector<double> depths = lengths(p, "billet_thermocouple_depths");
    for (double d : depths)
      for (double r : radii) {
        if (!(d > 0.0 && d < height_)) p.fail("billet_thermocouple_depths", "every depth must lie inside the billet");
        if (!(r >= 0.0 && r < radius_)) p.fail("billet_thermocouple_radii", "every radius must lie inside the billet");
        thermocouples_.push_back({Vec(r, 0.0, height_ - d), r, d});
      }
    // Tracers P1.. at the given radii, `tracer_depth` below the top, on the +x axis rotated into
    // the middle of the sector (with a sector of 360/N deg the +x axis is a cut).
    const double depth = p.number("tracer_depth");
    if (!(depth > 0.0 && depth < height_)) p.fail("tracer_depth", "must lie inside the billet");
    const double phi = sectors_ > 1 ? std::numbers::pi / sectors_ : 0.0;
    for (double r : lengths(p, "tracer_radii")) {
      if (!(r >= 0.0 && r < radius_)) p.fail("tracer_radii", "every radius must lie inside the billet");
      tracers_.push_back({Vec(r * std::cos(phi), r * std::sin(phi), height_ - depth)});
    }
    die_tc_point_ = Vec(p.number("die_thermocouple_radius"), 0.0, height_ + p.number("die_thermocouple_depth"));
  }

  std::vector<FieldInfo> fields() const override {
    return {{"zener_hollomon", 1, "1/s", FieldType::Float64, true}};  // eq. (106)
  }

  void build(SceneBuilder& scene) override {
    const double dx = spacing_;
    const int nr = static_cast<int>(std::ceil((radius_ + wall_thickness_) / dx)) + 1;
    // Billet: cubic lattice with half-integer sites about the axis (maps onto itself in a 90 or
    // 180 deg sector, theory eq. 30), dx/2 from the container bottom and the die face, inside
    // r <= R - dx; around it one ring per layer at r = R - dx/2, so that the billet's side touches
    // the container wall as its bottom and top touch theirs. The lattice cut at R - dx/2 alone stood
    // a median 1.02 dx inside the wall (2 mm): out of the contact's reach (dx/2, eq. 11), so the
    // side wall held neither torque nor heat, and the billet had 8.7 % too little mass.
    const int nz = static_cast<int>(std::floor(height_ / dx + 1e-9));
    std::vector<Vec> billet;
    for (int k = 0; k < nz; ++k) {
      for (int j = -nr; j < nr; ++j)
        for (int i = -nr; i < nr; ++i) {
          const Vec x((i + 0.5) * dx, (j + 0.5) * dx, (k + 0.5) * dx);
          if (std::hypot(x.x(), x.y()) <= radius_ - dx + 1e-9 * dx) billet.push_back(x);
        }
      append_ring(billet, radius_ - 0.5 * dx, (k + 0.5) * dx, dx, sectors_);
    }
    scene.add_body("billet", billet, dx);
    face_z0_ = nz * dx;

    // Container: bottom z = 0 walked outwards (material above), then the wall r = R walked up
    // (material inside), reaching above the die's travel.
    const double top = face_z0_ + die_thickness_ + 4 * dx;
    container_ = scene.add_tool(RigidTool("container", {{0.0, 0.0}, {radius_, 0.0}, {radius_, top}}));
    // Die: face walked inwards (material below) from the container wall to the orifice edge,
    // optionally rising by face_cone_depth towards the orifice (a concave conical face), then up the
    // orifice wall (material at r < r_o), then out along the die's top (material above): a closed
    // ring. An open bore end let the rod, once longer than the bore, have particles just above the end
    // and beside the bore counted as inside the wall (negative distance): the penalty shot one out at
    // 175 m/s (the first coarse full run, stopped by the instability check at 69 s of process).
    // The orifice edge is rounded by an exact arc (eq. 41).
    std::vector<Eigen::Vector2d> die = {{radius_, 0.0}, {orifice_radius_, face_depth_},
                                        {orifice_radius_, face_depth_ + orifice_length_},
                                        {radius_, face_depth_ + orifice_length_}};
    ToolProfile profile(die);
    if (edge_fillet_ > 0.0) profile = profile.with_fillets(edge_fillet_, {1});
    RigidTool tool("die", profile);
    tool.axial_offset_m = face_z0_;
    die_ = scene.add_tool(std::move(tool));

    if (!thermal_tools_) return;
    // Thermal-only bodies (theory section 9.1) dx/2 behind the tool surfaces so that the contact
    // conducts like a perfect interface (eq. 92). The die body's columns follow the (possibly
    // conical) face: layer k sits at face(r) + (k + 1/2) dx. A fixed-z lattice cut by the cone left
    // its first layer between dx/2 and 3 dx/2 behind the face, a gap that eq. 92 does not allow for:
    // at 2 mm in the FSBE case the nearest die particles were 2 dx from the billet's top layer and
    // the die took almost no heat by conduction (the 2026-12-06 FSBE study).
    std::vector<Vec> die_body, container_body;
    const int nd = std::max(1, static_cast<int>(std::lround(die_thickness_ / dx)));
    for (int k = 0; k < nd; ++k)
      for (int j = -nr; j < nr; ++j)
        for (int i = -nr; i < nr; ++i) {
          const double px = (i + 0.5) * dx, py = (j + 0.5) * dx, r = std::hypot(px, py);
          if (r > radius_ - 0.5 * dx + 1e-9 * dx || r < orifice_radius_ + 0.5 * dx - 1e-9 * dx) continue;
          const double z = die_face_height(r) + (k + 0.5) * dx;
          // A rounded orifice edge (orifice_edge_fillet) cuts into the first layers: keep only sites
          // well inside the die (a sloped face leaves its first layer dx/2 cos(slope) from it).
          Eigen::Vector2d normal;
          if (profile.signed_distance({r, z - face_z0_}, normal) <= -0.25 * dx) die_body.emplace_back(px, py, z);
        }
    // Container bottom: the cubic lattice below z = 0 (a flat wall, dx/2 behind it already).
    const int nb = std::max(1, static_cast<int>(std::lround(bottom_thickness_ / dx)));
    for (int k = -nb; k < 0; ++k)
      for (int j = -nr; j < nr; ++j)
        for (int i = -nr; i < nr; ++i) {
          const double px = (i + 0.5) * dx, py = (j + 0.5) * dx;
          if (std::hypot(px, py) <= radius_ + wall_thickness_) container_body.emplace_back(px, py, (k + 0.5) * dx);
        }
    // Container wall: rings l = 0, 1, .. at r = R + (l + 1/2) dx, one per layer z = (k + 1/2) dx, each
    // with about 2 pi r / dx sites (a multiple of the sector count, half a pitch off the cut planes,
    // so that a 360/N deg sector maps onto itself, eq. 30). Sites of the cubic lattice outside
    // r = R + dx/2 stood a median 1.07 dx from the wall (2 mm, AA7075 case), not the dx/2 of eq. 92.
    const int nw = static_cast<int>(std::lround(wall_thickness_ / dx));
    const int nt = static_cast<int>(std::floor(top / dx));
    for (int l = 0; l < nw; ++l)
      for (int k = 0; k < nt; ++k) append_ring(container_body, radius_ + (l + 0.5) * dx, (k + 0.5) * dx, dx, sectors_);
    scene.add_tool_body("die_body", std::move(die_body), dx, "die_steel", "die");
    scene.add_tool_body("container_body", std::move(container_body), dx, "container_steel", "container");
  }

  void bind_signals(SignalBus& bus) override {
    bus.add_command("die_plunge_velocity", "m/s", &plunge_velocity_);
    bus.add_command("die_angular_velocity", "rad/s", &angular_velocity_);
    bus.add_measured("extrusion_force", "N", &force_);
    bus.add_measured("die_torque", "N*m", &torque_);
    bus.add_measured("die_displacement", "m", &displacement_);
    bus.add_measured("interface_temperature", "K", &interface_T_);
    bus.add_measured("die_thermocouple_temperature", "K", &die_tc_T_);
    bus.add_measured("process_time", "s", &process_time_);
  }

  void initialize(ProcessContext& ctx) override {
    FieldRegistry& f = *ctx.fields;
    const std::size_t n = f.size();
    const double* x = f.f64(field::position);
    const std::int64_t* ids = f.i64(field::id);
    const std::int64_t* body = f.i64(field::body);
    T_ = f.f64_if(field::temperature) != nullptr;
    // The billet is made of the case's "material" (build() gives no key): its section must request
    // the plastic rate, and the case must be thermal (user errors, exit code 2).
    if (!f.f64_if("plastic_strain_rate"))
      throw InputError(file_, "/material/output_fields",
                       "friction_extrusion needs \"plastic_strain_rate\" in the billet material's output_fields "
                       "(Zener-Hollomon field, plastic heat rate)");
    if (!T_) throw InputError(file_, "/thermal", "friction_extrusion needs a \"thermal\" section");
    auto body_index = [&](const std::string& name) {
      for (std::size_t b = 0; b < ctx.bodies->size(); ++b)
        if ((*ctx.bodies)[b].name == name) return static_cast<long long>(b);
      return -1LL;
    };
    const long long billet = body_index("billet"), die_body = body_index("die_body"),
                    container_body = body_index("container_body");
    auto nearest = [&](const Vec& q, long long b) {
      double best = std::numeric_limits<double>::infinity();
      std::size_t k = 0;
      for (std::size_t i = 0; i < n; ++i) {
        if (body[i] != b) continue;
        const double d2 = (Vec(x[3 * i], x[3 * i + 1], x[3 * i + 2]) - q).squaredNorm();
        if (d2 < best) best = d2, k = i;
      }
      return std::pair{k, std::sqrt(best)};
    };
    for (Tracer& t : tracers_) {
      const auto [i, d] = nearest(t.start, billet);
      t.id = ids[i];
      t.start = Vec(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
    }
    if (die_body >= 0) {
      const std::size_t i = nearest(die_tc_point_, die_body).first;
      die_tc_id_ = ids[i];
      die_tc_point_ = Vec(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
    }
    // Convection coefficients (eq. 23 acts on the free surface only): the die body and the
    // container bottom lose heat to the machine (h_die, h_bottom), every other surface h_other.
    double* hc = f.f64(field::convection_coefficient);
    double* T = f.f64(field::temperature);
    const double dx = spacing_;
    for (std::size_t i = 0; i < n; ++i) {
      const double z = x[3 * i + 2], r = std::hypot(x[3 * i], x[3 * i + 1]);
      hc[i] = h_other_;
      if (body[i] == die_body) hc[i] = h_die_;
      if (body[i] == container_body && z < 0.0) hc[i] = h_bottom_;
      if (cooled_T_ < 0.0) continue;
      // Actively cooled variant: the outer layer of the die body (its back) and of the container
      // (outer wall and underside) held at cooled_surface_temperature.
      const bool die_back = body[i] == die_body && z - die_face_height(r) > die_thickness_ - dx;
      const bool container_outer =
          body[i] == container_body && (r > radius_ + wall_thickness_ - dx || z < -bottom_thickness_ + dx);
      if (die_back || container_outer) {
        cooled_ids_.push_back(ids[i]);
        T[i] = cooled_T_;
      }
    }
    index_of_id_.clear();  // forces the first lookup
    distance_.resize(ctx.mechanical_count);
    normal_.resize(3 * ctx.mechanical_count);
    refresh(f);
  }

  void before_step(ProcessContext& ctx) override {
    // Commands are process (physical) speeds; the scene runs f times faster (eqs. 25, 100).
    RigidTool& die = (*ctx.tools)[die_];
    die.axial_velocity_m_s = -plunge_velocity_ * ctx.time_scaling;
    die.angular_velocity_rad_s = angular_velocity_ * ctx.time_scaling;
  }

  void apply_constraints(ProcessContext& ctx) override {
    if (cooled_index_.empty()) return;
    FieldRegistry& f = *ctx.fields;
    refresh(f);
    double* dT = f.f64(field::temperature_rate);
    const double* T = f.f64(field::temperature);
    // Relax exactly onto the prescribed surface temperature within the step.
    for (std::size_t i : cooled_index_) dT[i] = ctx.dt_s > 0.0 ? (cooled_T_ - T[i]) / ctx.dt_s : 0.0;
  }

  void measure(ProcessContext& ctx) override {
    FieldRegistry& f = *ctx.fields;
    refresh(f);
    const double fs = ctx.time_scaling;
    const double previous_time = process_time_;
    process_time_ = ctx.time_s * fs;  // eq. (102)
    const RigidTool& die = (*ctx.tools)[die_];
    // Extrusion force: z reaction (contact + friction) on the die, full body (eq. 101).
    force_ = sectors_ * die.reaction_force_N.z();
    // Running integrals of F and (F - F_t)^2 over process time (eq. 108a): this step's force acted
    // over the step.
    const double step = process_time_ - previous_time;
    force_integral_ += force_ * step;
    error_sq_integral_ += (force_ - target_) * (force_ - target_) * step;
    torque_ = sectors_ * die.reaction_torque_Nm;
    displacement_ = face_z0_ - die.axial_offset_m;
    const double face = die.axial_offset_m;
    const std::size_t n = ctx.mechanical_count;
    const double* x = f.f64(field::position);
    const double* m = f.f64(field::mass);
    const double* rho = f.f64(field::density);
    const double* s = f.f64(field::deviatoric_stress);
    const double* fc = f.f64(field::contact_force);
    const double* T = f.f64(field::temperature);
    const double* rate = f.f64("plastic_strain_rate");
    double* Z = f.f64("zener_hollomon");
    die.signed_distance(n, x, distance_.data(), normal_.data(), spacing_);
    const double q_over_r = activation_ / kGasConstant, dx = spacing_;
    double zmax = -std::numeric_limits<double>::infinity(), t_sum = 0.0, t_count = 0.0, q_p = 0.0;
#pragma omp parallel for reduction(max : zmax) reduction(+ : t_sum, t_count, q_p) schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      const double* xi = x + 3 * i;
      zmax = std::max(zmax, xi[2]);
      // Plastic heat (eq. 105): beta sigma_vm epsdot_p V, physical rate, V = m / rho (scale-free).
      const double* si = s + 6 * i;
      const double j2 = si[0] * si[0] + si[1] * si[1] + si[2] * si[2] + 2.0 * (si[3] * si[3] + si[4] * si[4] + si[5] * si[5]);
      q_p += beta_ * std::sqrt(1.5 * j2) * rate[i] * m[i] / rho[i];
      // Zener-Hollomon parameter (eq. 106), 0 where the material does not flow.
      Z[i] = rate[i] > 0.0 ? rate[i] * std::exp(q_over_r / T[i]) : 0.0;
      // Die contacts: within the contact distance dx/2 of the die, pressed (eq. 103).
      const double d = distance_[i];
      if (!(d < 0.5 * dx * (1.0 + 1e-6))) continue;
      const double* fi = fc + 3 * i;
      if (fi[0] * fi[0] + fi[1] * fi[1] + fi[2] * fi[2] == 0.0) continue;
      t_sum += T[i];
      t_count += 1.0;
    }
    contacts_ = sectors_ * t_count;
    interface_T_ = t_count > 0.0 ? t_sum / t_count : std::numeric_limits<double>::quiet_NaN();
    // Heat rates per second of process time, full body: the die's friction heat sum |f_t| |v_t| from
    // the contact pass runs f times faster in the scaled scene (eq. 104); the plastic rate is already
    // physical (eq. 105).
    friction_heat_ = sectors_ * die.friction_heat_W / fs;
    plastic_heat_ = sectors_ * q_p;
    rod_length_ = std::max(0.0, zmax + 0.5 * dx - face);  // eq. (107)
    for (Thermocouple& tc : thermocouples_) {
      // A fixed thermocouple: the billet particle nearest its point now (Eulerian probe).
      double best = std::numeric_limits<double>::infinity();
      std::size_t k = 0;
      for (std::size_t i = 0; i < n; ++i) {
        const double d2 = (Vec(x[3 * i], x[3 * i + 1], x[3 * i + 2]) - tc.point).squaredNorm();
        if (d2 < best) best = d2, k = i;
      }
      tc.value = T[k];
    }
    if (die_tc_id_ >= 0) die_tc_T_ = T[index_of_id_[static_cast<std::size_t>(die_tc_id_)]];
    const double* eps = f.f64(field::plastic_strain);
    for (Tracer& t : tracers_) {
      const std::size_t i = index_of_id_[static_cast<std::size_t>(t.id)];
      for (int c = 0; c < 3; ++c) t.x[c] = x[3 * i + c];
      t.T = T[i];
      t.eps = eps[i];
    }
    // Samples for the Table D.1 metrics (eq. 108), every metrics_sample_interval of process time.
    if (ctx.dt_s > 0.0 && process_time_ >= next_sample_) {
      samples_.push_back({process_time_, force_, plunge_velocity_, force_integral_, error_sq_integral_});
      next_sample_ = process_time_ + sample_interval_;
    }
    peak_interface_T_ = std::max(peak_interface_T_, std::isnan(interface_T_) ? 0.0 : interface_T_);
  }

  bool finished(const ProcessContext&) const override { return displacement_ >= stroke_; }

  // Restart (docs/checkpoints.md): the Table D.1 samples and the running peak. Tracers and
  // thermocouples are found again by id (initialize() on the rebuilt scene, refresh()); the
  // signals (force, displacement, commands) are on the bus, which the core saves.
  bool supports_restart() const override { return true; }
  nlohmann::json save_state() const override {
    json samples = json::array();
    for (const Sample& x : samples_) samples.push_back({x.t, x.force, x.velocity, x.force_integral, x.error_sq_integral});
    return {{"samples", samples},
            {"next_sample", next_sample_},
            {"peak_interface_temperature", peak_interface_T_},
            {"process_time", process_time_},
            {"force_integral", force_integral_},
            {"error_sq_integral", error_sq_integral_}};
  }
  void restore_state(const nlohmann::json& s) override {
    samples_.clear();
    // Checkpoints written before eq. 108a carry no integrals: the time means then read NaN.
    const double none = std::numeric_limits<double>::quiet_NaN();
    for (const json& x : s.at("samples"))
      samples_.push_back({x.at(0).get<double>(), x.at(1).get<double>(), x.at(2).get<double>(),
                          x.size() > 3 ? x.at(3).get<double>() : none, x.size() > 4 ? x.at(4).get<double>() : none});
    next_sample_ = s.at("next_sample").get<double>();
    peak_interface_T_ = s.at("peak_interface_temperature").get<double>();
    process_time_ = s.value("process_time", none);
    force_integral_ = s.value("force_integral", none);
    error_sq_integral_ = s.value("error_sq_integral", none);
  }

  std::vector<HistoryColumn> history_columns() const override {
    std::vector<HistoryColumn> c = {
        {"process_time_s", &process_time_},
        {"extrusion_force_N", &force_},
        {"extrusion_torque_Nm", &torque_},
        {"die_displacement_m", &displacement_},
        {"die_plunge_velocity_m_s", &plunge_velocity_},
        {"die_angular_velocity_rad_s", &angular_velocity_},
        {"die_contacts_full_1", &contacts_},
        {"interface_temperature_K", &interface_T_},
        {"die_thermocouple_K", &die_tc_T_},
        {"friction_heat_rate_W", &friction_heat_},
        {"plastic_heat_rate_W", &plastic_heat_},
        {"rod_length_m", &rod_length_}};
    for (const Thermocouple& tc : thermocouples_)
      c.push_back({"billet_tc_r" + mm(tc.radius) + "_d" + mm(tc.depth) + "_K", &tc.value});
    for (std::size_t k = 0; k < tracers_.size(); ++k) {
      const std::string p = "tracer_P" + std::to_string(k + 1) + "_";
      c.push_back({p + "x_m", &tracers_[k].x[0]});
      c.push_back({p + "y_m", &tracers_[k].x[1]});
      c.push_back({p + "z_m", &tracers_[k].x[2]});
      c.push_back({p + "temperature_K", &tracers_[k].T});
      c.push_back({p + "plastic_strain_1", &tracers_[k].eps});
    }
    return c;
  }

  nlohmann::json metrics() const override {
    json m;
    m["final_process_time_s"] = process_time_;
    m["final_die_displacement_m"] = displacement_;
    m["rod_length_m"] = rod_length_;
    m["peak_interface_temperature_K"] = peak_interface_T_;
    m["final_interface_temperature_K"] = std::isnan(interface_T_) ? json(nullptr) : json(interface_T_);
    m["final_die_thermocouple_K"] = die_tc_T_;
    m["final_plastic_heat_rate_W"] = plastic_heat_;
    m["final_friction_heat_rate_W"] = friction_heat_;
    m["sector_count"] = sectors_;
    m["die_thermocouple_position_m"] = {die_tc_point_.x(), die_tc_point_.y(), die_tc_point_.z()};
    for (std::size_t k = 0; k < tracers_.size(); ++k) {
      const std::string p = "tracer_P" + std::to_string(k + 1) + "_";
      m[p + "start_m"] = {tracers_[k].start.x(), tracers_[k].start.y(), tracers_[k].start.z()};
      m[p + "plastic_strain"] = tracers_[k].eps;
    }
    // Table D.1 (eq. 108): settling time t_s, the last time the force error left the band
    // |F - F_t| <= band F_t (counted from metrics_start_time), then over t >= t_s the mean |error|
    // in per cent of F_t, the mean force, the RMSE against F_t and min / max / CV of the die velocity.
    m["target_force_N"] = target_;
    std::vector<Sample> s;
    for (const Sample& x : samples_)
      if (x.t >= metrics_start_) s.push_back(x);
    if (s.size() < 2 || !(target_ > 0.0)) return m;
    double settle = s.front().t;
    bool ever_outside = false;
    for (const Sample& x : s)
      if (std::abs(x.force - target_) > band_ * target_) settle = x.t, ever_outside = true;
    m["settling_time_s"] = settle - metrics_start_;
    m["settled"] = !ever_outside || settle < s.back().t;
    double n = 0, err = 0, sq = 0, fsum = 0, vsum = 0, v2 = 0;
    double vmin = std::numeric_limits<double>::infinity(), vmax = -vmin;
    const Sample* first = nullptr;  // the first steady sample: where the time means of eq. 108a start
    for (const Sample& x : s) {
      if (x.t <= settle && ever_outside) continue;
      if (first == nullptr) first = &x;
      n += 1;
      err += std::abs(x.force - target_);
      sq += (x.force - target_) * (x.force - target_);
      fsum += x.force;
      vsum += x.velocity;
      v2 += x.velocity * x.velocity;
      vmin = std::min(vmin, x.velocity);
      vmax = std::max(vmax, x.velocity);
    }
    m["steady_samples"] = n;
    if (n < 2) return m;
    const double vmean = vsum / n;
    m["steady_mean_force_error_pct"] = 100.0 * err / n / target_;
    m["steady_mean_force_N"] = fsum / n;
    m["steady_force_rmse_N"] = std::sqrt(sq / n);
    // Eq. 108a: the same window's time means over every step, independent of the samples' phase
    // (the PID's command moves the force within a sample interval; docs/validation/friction_extrusion.md).
    const double span = process_time_ - first->t;
    const double time_mean = span > 0.0 ? (force_integral_ - first->force_integral) / span : first->force;
    m["steady_start_time_s"] = first->t;
    m["steady_time_mean_force_N"] = time_mean;
    m["steady_time_mean_force_deviation_pct"] = 100.0 * (time_mean - target_) / target_;
    m["steady_time_force_rmse_N"] =
        span > 0.0 ? std::sqrt(std::max(0.0, error_sq_integral_ - first->error_sq_integral) / span) : std::abs(first->force - target_);
    m["steady_die_velocity_min_m_s"] = vmin;
    m["steady_die_velocity_max_m_s"] = vmax;
    m["steady_die_velocity_mean_m_s"] = vmean;
    m["steady_die_velocity_cv_pct"] =
        vmean != 0.0 ? 100.0 * std::sqrt(std::max(0.0, v2 / n - vmean * vmean)) / std::abs(vmean) : 0.0;
    return m;
  }

 private:
  // Height of the die face at radius r at the start (it rises linearly by face_cone_depth from the
  // container wall to the orifice edge; flat when that is 0), the orifice edge's fillet left out.
  double die_face_height(double r) const {
    return face_z0_ + face_depth_ * std::clamp((radius_ - r) / (radius_ - orifice_radius_), 0.0, 1.0);
  }

  static std::string mm(double length) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", length * 1e3);
    std::string t(buf);
    std::replace(t.begin(), t.end(), '.', 'p');
    return t + "mm";
  }

  /// Tracer and thermocouple particles are followed by id; the core may reorder the arrays.
  void refresh(FieldRegistry& f) {
    const std::int64_t* ids = f.i64(field::id);
    const std::size_t n = f.size();
    bool stale = index_of_id_.size() != n;
    if (!stale) {
      for (const Tracer& t : tracers_) stale = stale || ids[index_of_id_[static_cast<std::size_t>(t.id)]] != t.id;
      if (die_tc_id_ >= 0) stale = stale || ids[index_of_id_[static_cast<std::size_t>(die_tc_id_)]] != die_tc_id_;
      if (!cooled_ids_.empty()) stale = stale || cooled_index_.empty() || ids[cooled_index_.front()] != cooled_ids_.front();
    }
    if (!stale) return;
    index_of_id_.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i) index_of_id_[static_cast<std::size_t>(ids[i])] = i;
    cooled_index_.clear();
    for (std::int64_t id : cooled_ids_) cooled_index_.push_back(index_of_id_[static_cast<std::size_t>(id)]);
  }

  struct Thermocouple {
    Vec point;
    double radius = 0.0, depth = 0.0, value = 0.0;
  };
  struct Tracer {
    Vec start;
    std::int64_t id = 0;
    double x[3] = {0, 0, 0};
    double T = 0.0, eps = 0.0;
  };
  struct Sample {
    double t, force, velocity;
    double force_integral, error_sq_integral;  // running integrals at t (eq. 108a)
  };

  std::string file_;
  double radius_, height_, orifice_radius_, orifice_length_, edge_fillet_, face_depth_, spacing_, stroke_;
  double die_thickness_, wall_thickness_, bottom_thickness_, h_die_, h_bottom_, h_other_, cooled_T_, beta_;
  double activation_, target_, band_, metrics_start_, sample_interval_;
  int sectors_ = 1;
  bool thermal_tools_ = true, T_ = false;
  std::size_t die_ = 0, container_ = 0;
  double face_z0_ = 0.0;
  std::vector<Thermocouple> thermocouples_;
  std::vector<Tracer> tracers_;
  Vec die_tc_point_ = Vec::Zero();
  std::int64_t die_tc_id_ = -1;
  std::vector<std::int64_t> cooled_ids_;
  std::vector<std::size_t> cooled_index_, index_of_id_;
  std::vector<double> distance_, normal_;
  std::vector<Sample> samples_;
  double next_sample_ = 0.0;
  // Commands (process units) and measurements.
  double plunge_velocity_ = 0.0, angular_velocity_ = 0.0;
  double force_ = 0.0, torque_ = 0.0, displacement_ = 0.0, interface_T_ = 0.0, die_tc_T_ = 0.0, process_time_ = 0.0;
  double contacts_ = 0.0, friction_heat_ = 0.0, plastic_heat_ = 0.0, rod_length_ = 0.0, peak_interface_T_ = 0.0;
  double force_integral_ = 0.0, error_sq_integral_ = 0.0;  // N s and N^2 s of process time (eq. 108a)
};

const PluginDescriptor& descriptor() {
  static const PluginDescriptor d = make_plugin_descriptor<FrictionExtrusion>(
      "friction_extrusion", "0.1.0",
      "billet in a fixed container under a rotating, plunging die with a central orifice (friction extrusion, "
      "FSBE); thermal die and container bodies, force, torque, temperatures, tracers, Table D.1 metrics",
      {
          ParamSpec::number("billet_diameter", "m", 50e-3, "billet (= container bore) diameter", 1e-6),
          ParamSpec::number("billet_height", "m", 40e-3, "initial billet height H", 1e-6),
          ParamSpec::number("orifice_diameter", "m", 14e-3, "die orifice diameter", 1e-6),
          ParamSpec::number("orifice_length", "m", 20e-3, "length of the orifice bore above the die face", 1e-6),
          ParamSpec::number("orifice_edge_fillet", "m", 0.0, "radius of the arc rounding the orifice edge", 0.0),
          ParamSpec::number("face_cone_depth", "m", 0.0,
                            "rise of the die face from the container wall to the orifice edge (0: flat face; > 0: "
                            "concave conical face as an FSBE tool)", 0.0),
          ParamSpec::number("particle_spacing", "m", std::nullopt, "initial particle spacing dx (all bodies)", 1e-7),
          ParamSpec::number("stroke", "m", 1.0, "the run ends when the die has plunged this far", 0.0),
          ParamSpec::integer("sector_count", 1,
                             "N when numerics.symmetry is a sector of 360/N deg (forces x N)", 1, 64),
          ParamSpec::boolean("thermal_tool_bodies", true,
                             "thermal-only die and container bodies attached to their tools (theory section 9.1)"),
          ParamSpec::number("die_body_thickness", "m", 10e-3, "thickness of the die's thermal body above its face", 0.0),
          ParamSpec::number("container_wall_thickness", "m", 10e-3, "container wall thickness (thermal body)", 0.0),
          ParamSpec::number("container_bottom_thickness", "m", 10e-3, "container bottom thickness (thermal body)", 0.0),
          ParamSpec::number("die_convection_coefficient", "W/(m^2*K)", 1000.0, "h on the die body's free surface", 0.0),
          ParamSpec::number("container_bottom_convection_coefficient", "W/(m^2*K)", 1000.0,
                            "h on the container bottom's free surface", 0.0),
          ParamSpec::number("other_convection_coefficient", "W/(m^2*K)", 25.0, "h on every other free surface", 0.0),
          ParamSpec::number("cooled_surface_temperature", "K", -1.0,
                            "active cooling: the die's back layer and the container's outer layers held at this "
                            "temperature (-1: off)"),
          ParamSpec::number("taylor_quinney", "1", 0.9,
                            "beta of the plastic heat rate column (eq. 105); the material's own value heats the billet",
                            0.0, 1.0),
          ParamSpec::number("activation_energy", "J/mol", 150e3, "Q of the Zener-Hollomon parameter (eq. 106)", 0.0),
          ParamSpec::number("die_thermocouple_radius", "m", 16.5e-3, "die thermocouple distance from the axis", 0.0),
          ParamSpec::number("die_thermocouple_depth", "m", 0.5e-3, "die thermocouple depth behind the die face", 0.0),
          ParamSpec::array("billet_thermocouple_radii", "radii of the billet thermocouples [\"0 mm\", ...]", true),
          ParamSpec::array("billet_thermocouple_depths", "depths below the billet top [\"5 mm\", ...]", true),
          ParamSpec::array("tracer_radii", "start radii of the tracers P1, P2, ... [\"6 mm\", ...]", true),
          ParamSpec::number("tracer_depth", "m", 10e-3, "tracer start depth below the billet top", 0.0),
          ParamSpec::number("target_force", "N", 0.0, "force target of the Table D.1 metrics (0: none)", 0.0),
          ParamSpec::number("settling_band", "1", 0.15, "settling band |F - F_t| <= band F_t (Table D.1: 0.15)", 0.0),
          ParamSpec::number("metrics_start_time", "s", 0.0,
                            "process time from which the Table D.1 metrics are evaluated (after heating phases)", 0.0),
          ParamSpec::number("metrics_sample_interval", "s", 0.01, "process time between metric samples (dt_pid)", 0.0),
      });
  return d;
}

}  // namespace

SPHFORGE_PLUGIN(descriptor)
