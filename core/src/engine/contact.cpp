#include "engine/contact.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace sphforge {

void PenaltyContact::configure(const ContactSettings& settings, std::vector<const ContactLaw*> laws,
                               double spacing, double p_wave_modulus, double finest_spacing) {
  settings_ = settings;
  laws_ = std::move(laws);
  spacing_ = spacing;
  stats_.assign(laws_.size(), ToolContactStats{});
  history_.assign(laws_.size(), {});
  // A particle pressed on a wall is resisted like a column of its own material of cross-section
  // dx^2 and length dx: k = M dx^2 / dx (eq. 10). Its frequency sqrt(k/m) = c/dx is then of the
  // order of the bulk's own, so the contact does not need a smaller step than the CFL limit.
  // The paper's per-mass lambda1 = P / (2 dt^2) is this k divided by m (eq. 10a).
  stiffness_ = settings.stiffness_factor * p_wave_modulus * spacing;
  // Several spacings (eq. 141): the laws' scalar stiffness (their tangential spring) is the finest
  // particle's, which keeps that spring inside every particle's stability limit.
  law_stiffness_ = finest_spacing > 0.0 ? stiffness_ * finest_spacing / spacing : stiffness_;
}

namespace {
// The entry of particle `id` in a friction memory sorted by id, or null (not touching last pass).
const FrictionHistoryEntry* find_history(const std::vector<FrictionHistoryEntry>& h, std::int64_t id) {
  const auto it = std::lower_bound(h.begin(), h.end(), id,
                                   [](const FrictionHistoryEntry& e, std::int64_t key) { return e.id < key; });
  return it != h.end() && it->id == id ? &*it : nullptr;
}
}  // namespace

FrictionHistoryEntry* PenaltyContact::friction_history_entry(std::size_t tool, std::int64_t id) {
  return const_cast<FrictionHistoryEntry*>(find_history(history_[tool], id));
}

void PenaltyContact::friction_history_dense(std::size_t tool, const std::int64_t* id, std::size_t n,
                                            double* out) const {
  const std::vector<FrictionHistoryEntry>& h = history_[tool];
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const FrictionHistoryEntry* e = h.empty() ? nullptr : find_history(h, id[i]);
    for (int d = 0; d < 3; ++d) out[3 * i + d] = e ? e->value[d] : 0.0;
  }
}

double PenaltyContact::stable_time_step(double min_mass) const {
  if (stiffness_ <= 0.0) return std::numeric_limits<double>::infinity();
  // Central difference on a damped oscillator: dt < 2/omega (sqrt(1+zeta^2) - zeta)  (eq. 12)
  const double omega = std::sqrt(stiffness_ / min_mass);
  const double z = settings_.damping_ratio;
  return 2.0 / omega * (std::sqrt(1.0 + z * z) - z);
}

void PenaltyContact::bin_particles(const double* x, std::size_t n) {
  // Cells of edge 2 dx over the particles' bounding box, particles counted into them (a counting
  // sort, allocation-free once warmed up). One distance query per cell then decides whether its
  // particles can touch a tool.
  double lo[3] = {x[0], x[1], x[2]}, hi[3] = {x[0], x[1], x[2]};
  for (std::size_t i = 1; i < n; ++i)
    for (int d = 0; d < 3; ++d) {
      lo[d] = std::min(lo[d], x[3 * i + d]);
      hi[d] = std::max(hi[d], x[3 * i + d]);
    }
  cell_edge_ = 2.0 * spacing_;
  std::size_t total = 1;
  for (int d = 0; d < 3; ++d) {
    grid_lo_[d] = lo[d];
    grid_dims_[d] = static_cast<std::size_t>((hi[d] - lo[d]) / cell_edge_) + 1;
    total *= grid_dims_[d];
  }
  // A scene far larger than its particle count (a particle thrown away) would make the grid
  // huge: then one cell holds everything and every particle is tested, as without culling.
  if (total > 8 * n + 64) {
    for (int d = 0; d < 3; ++d) grid_dims_[d] = 1;
    cell_edge_ = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], spacing_});
    total = 1;
  }
  // 4-byte indices: particles and cells (at most 8 n + 64) fit, as in the neighbour lists.
  if (n > std::numeric_limits<std::uint32_t>::max() / 16) throw std::length_error("too many particles");
  cell_start_.assign(total + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t c[3];
    for (int d = 0; d < 3; ++d)
      c[d] = std::min(grid_dims_[d] - 1, static_cast<std::size_t>((x[3 * i + d] - grid_lo_[d]) / cell_edge_));
    cell_of_[i] = static_cast<std::uint32_t>((c[2] * grid_dims_[1] + c[1]) * grid_dims_[0] + c[0]);
    ++cell_start_[cell_of_[i] + 1];
  }
  for (std::size_t c = 0; c < total; ++c) cell_start_[c + 1] += cell_start_[c];
  cell_fill_.assign(cell_start_.begin(), cell_start_.end() - 1);
  for (std::size_t i = 0; i < n; ++i) cell_particles_[cell_fill_[cell_of_[i]]++] = static_cast<std::uint32_t>(i);
  cell_near_.resize(total);
}

std::size_t PenaltyContact::apply(std::vector<RigidTool>& tools, ContactArrays& a) {
  const double contact_radius = 0.5 * spacing_;  // a particle's half-width touches the wall
  const double area = spacing_ * spacing_;
  const std::size_t n = a.n;
  // Variable spacing (eq. 141): each touching particle's own half-width, area and stiffness, from its
  // smoothing length; the culling below keeps the largest reach.
  const double* h_of = a.smoothing_length;
  auto spacing_of = [&](std::size_t i) { return h_of ? h_of[i] * a.spacing_per_h : spacing_; };
  const double* x = a.x;
  const double* v = a.v;
  // The per-particle indices: in the borrowed storage when it holds them (the pass scratch, idle
  // after the momentum pass), so that a scene does not hold both; else in this object's arrays.
  if (a.borrow.size() * sizeof(double) >= 3 * n * sizeof(std::uint32_t)) {
    std::vector<std::uint32_t>().swap(own_slot_of_);
    std::vector<std::uint32_t>().swap(own_cell_of_);
    std::vector<std::uint32_t>().swap(own_cell_particles_);
    slot_of_ = reinterpret_cast<std::uint32_t*>(a.borrow.data());
    cell_of_ = slot_of_ + n;
    cell_particles_ = cell_of_ + n;
    lent_base_ = (3 * n * sizeof(std::uint32_t) + sizeof(double) - 1) / sizeof(double);
  } else {
    lent_base_ = a.borrow.size();  // nothing left to lend
    own_slot_of_.resize(n);
    own_cell_of_.resize(n);
    own_cell_particles_.resize(n);
    slot_of_ = own_slot_of_.data();
    cell_of_ = own_cell_of_.data();
    cell_particles_ = own_cell_particles_.data();
  }
  lent_ = a.borrow;
  if (stats_.size() != tools.size()) stats_.assign(tools.size(), ToolContactStats{});
  if (history_.size() != tools.size()) history_.resize(tools.size());
  std::size_t total = 0, stuck = 0;
  tool_heat_.clear();
  if (n > 0) bin_particles(x, n);
  const std::size_t ncells = cell_near_.size();
  const double half_diagonal = 0.5 * std::sqrt(3.0) * cell_edge_;

  for (std::size_t t = 0; t < tools.size(); ++t) {
    RigidTool& tool = tools[t];
    ToolContactStats& st = stats_[t];
    st = ToolContactStats{};
    tool.reaction_force_N.setZero();
    tool.reaction_torque_Nm = 0.0;
    tool.power_W = 0.0;
    tool.friction_heat_W = 0.0;
    const ContactLaw* law = t < laws_.size() ? laws_[t] : nullptr;
    // The law's per-contact memory (eq. 18b), kept for the touching particles by id.
    const bool keeps_history = law != nullptr && law->needs_history();
    if (keeps_history && a.id == nullptr) throw std::logic_error("PenaltyContact: a friction memory needs particle ids");
    std::vector<FrictionHistoryEntry>& history = history_[t];
    // A wall law may act a little beyond touching (eq. 18i); the penalty still needs g > 0.
    const double reach = contact_radius + (law ? law->wall_range() * spacing_ : 0.0);
    Eigen::Vector3d lo, hi;
    tool.bounds(lo, hi);
    lo.array() -= reach;
    hi.array() += reach;

    // Culling (cells of 2 dx): a cell outside the tool's bounds (+ reach), or whose centre lies
    // farther from the surface than its half-diagonal + reach, holds no particle that can touch
    // (the distance to the surface changes at most as fast as the position); only the particles
    // of the remaining cells ask the tool for their signed distance.
#pragma omp parallel for schedule(dynamic, 16)
    for (std::size_t c = 0; c < ncells; ++c) {
      cell_near_[c] = 0;
      if (cell_start_[c] == cell_start_[c + 1]) continue;
      const std::size_t cx = c % grid_dims_[0], cy = (c / grid_dims_[0]) % grid_dims_[1],
                        cz = c / (grid_dims_[0] * grid_dims_[1]);
      const Eigen::Vector3d cmin(grid_lo_[0] + cx * cell_edge_, grid_lo_[1] + cy * cell_edge_,
                                 grid_lo_[2] + cz * cell_edge_);
      const Eigen::Vector3d cmax = cmin.array() + cell_edge_;
      if ((cmax.array() < lo.array()).any() || (cmin.array() > hi.array()).any()) continue;
      Eigen::Vector3d nrm;
      const double dc = tool.signed_distance(0.5 * (cmin + cmax), nrm);
      cell_near_[c] = dc <= half_diagonal + reach ? 1 : 0;
    }
    // The particles of the near cells ask the tool for their distance in one batch query
    // (docs/theory.md eqs. 40-46: one virtual call per chunk of points, not per particle).
    // Cell order (not index order) on purpose: a mesh tool's query starts from the previous point's
    // nearest triangle, so the order of the batch may decide between equidistant features.
    near_particles_.clear();
    for (std::size_t s = 0; s < n; ++s)
      if (cell_near_[cell_of_[cell_particles_[s]]]) near_particles_.push_back(cell_particles_[s]);
    const std::size_t m = near_particles_.size();
    // This tool's arrays: the previous tool's are dead, so the lent storage is reused from its start.
    std::size_t used = lent_base_;
    near_x_.resize(3 * m, lent_, used);
    near_distance_.resize(m, lent_, used);
    near_normal_.resize(3 * m, lent_, used);
#pragma omp parallel for schedule(static)
    for (std::size_t k = 0; k < m; ++k)
      for (int c = 0; c < 3; ++c) near_x_[3 * k + c] = x[3 * near_particles_[k] + c];
    tool.signed_distance(m, near_x_.data(), near_distance_.data(), near_normal_.data(), reach);
    // Each particle's slot in the query (a particle outside the near cells is farther than reach).
    std::fill(slot_of_, slot_of_ + n, kFar);
#pragma omp parallel for schedule(static)
    for (std::size_t k = 0; k < m; ++k) slot_of_[near_particles_[k]] = static_cast<std::uint32_t>(k);
    const double range = law ? law->wall_range() : 0.0;
    auto touching = [&](std::size_t i) {
      if (slot_of_[i] == kFar) return false;
      const double reach_i = h_of ? (0.5 + range) * spacing_of(i) : reach;
      return near_distance_[slot_of_[i]] < reach_i;
    };
    // Gather the touching particles in index order (deterministic).
    particle_.clear();
    for (std::size_t i = 0; i < n; ++i)
      if (touching(i)) particle_.push_back(i);
    const std::size_t nc = particle_.size();
    // A particle that left the contact forgets its tangential spring (eq. 18b): the memory kept
    // is that of this pass's contacts only (rebuilt below).
    if (nc == 0) history.clear();
    if (nc == 0) continue;
    batch_mass_.resize(nc, lent_, used);
    batch_normal_.resize(3 * nc, lent_, used);
    batch_fn_.resize(nc, lent_, used);
    batch_gap_.resize(nc, lent_, used);
    batch_vn_.resize(nc, lent_, used);
    batch_damping_.resize(nc, lent_, used);
    batch_vt_.resize(3 * nc, lent_, used);
    batch_acc_.resize(3 * nc, lent_, used);
    batch_vwall_.resize(3 * nc, lent_, used);
    batch_area_.resize(nc, lent_, used);
    if (h_of)
      for (std::size_t c = 0; c < nc; ++c) batch_area_[c] = spacing_of(particle_[c]) * spacing_of(particle_[c]);
    else
      std::fill(batch_area_.data(), batch_area_.data() + nc, area);
    batch_yield_.resize(nc, lent_, used);
    batch_history_.resize(3 * nc, lent_, used);
    batch_ft_.resize(3 * nc, lent_, used);
    std::fill(batch_ft_.data(), batch_ft_.data() + 3 * nc, 0.0);
    batch_stick_.resize(nc, lent_, used);
    std::fill(batch_stick_.data(), batch_stick_.data() + nc, 0.0);

#pragma omp parallel for schedule(static)
    for (std::size_t c = 0; c < nc; ++c) {
      const std::size_t i = particle_[c], k = slot_of_[i];
      const Eigen::Vector3d xi(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
      const Eigen::Vector3d nrm(near_normal_[3 * k], near_normal_[3 * k + 1], near_normal_[3 * k + 2]);
      const Eigen::Vector3d v_wall = tool.surface_velocity(xi);
      const Eigen::Vector3d v_rel = Eigen::Vector3d(v[3 * i], v[3 * i + 1], v[3 * i + 2]) - v_wall;
      const double vn = v_rel.dot(nrm);
      const double gap = (h_of ? 0.5 * spacing_of(i) : contact_radius) - near_distance_[k];
      // Damped penalty (eq. 11); a wall only pushes, never pulls.
      const double k_i = h_of ? stiffness_ * spacing_of(i) / spacing_ : stiffness_;
      const double damping = 2.0 * settings_.damping_ratio * std::sqrt(k_i * a.mass[i]);
      const double fn = gap > 0.0 ? std::max(0.0, k_i * gap - damping * vn) : 0.0;
      // Tangential relative velocity: v - (v.n) n  (never a component-wise product).
      const Eigen::Vector3d vt = v_rel - vn * nrm;
      batch_mass_[c] = a.mass[i];
      batch_fn_[c] = fn;
      batch_gap_[c] = gap;
      batch_vn_[c] = vn;
      batch_damping_[c] = damping;
      batch_yield_[c] = a.yield ? a.yield[i] : std::numeric_limits<double>::infinity();
      // a_other of the sticking force (eq. 18a): the internal acceleration plus the contact forces
      // the tools before this one have already put on the particle in this pass. Without the
      // latter, a particle touching two tools (the corner of die face and container wall) is held
      // twice over in their shared tangential direction and ends the step at neither wall's
      // velocity (70 % of the die's in ContactPass.ParticleHeldByTwoToolsEndsAtTheLastToolsTangentialVelocity).
      const double inv_mass = 1.0 / a.mass[i];
      for (int d = 0; d < 3; ++d) {
        batch_normal_[3 * c + d] = nrm[d];
        batch_vt_[3 * c + d] = vt[d];
        batch_vwall_[3 * c + d] = v_wall[d];
        batch_acc_[3 * c + d] = (a.acceleration ? a.acceleration[3 * i + d] : 0.0) + a.force[3 * i + d] * inv_mass;
      }
      // Its memory from the last pass, zero for a particle that was not touching then.
      const FrictionHistoryEntry* e = keeps_history && !history.empty() ? find_history(history, a.id[i]) : nullptr;
      for (int d = 0; d < 3; ++d) batch_history_[3 * c + d] = e ? e->value[d] : 0.0;
    }

    if (law != nullptr) {
      ContactBatch batch;
      batch.count = nc;
      batch.dt = a.dt;
      batch.stiffness = law_stiffness_;
      batch.particle = particle_.data();
      batch.mass = batch_mass_.data();
      batch.normal = batch_normal_.data();
      batch.normal_force = batch_fn_.data();
      batch.penetration = batch_gap_.data();
      batch.normal_velocity = batch_vn_.data();
      batch.damping = batch_damping_.data();
      batch.tangential_velocity = batch_vt_.data();
      batch.acceleration = batch_acc_.data();
      batch.contact_area = batch_area_.data();
      batch.yield_stress = batch_yield_.data();
      batch.history = keeps_history ? batch_history_.data() : nullptr;
      batch.tangential_force = batch_ft_.data();
      batch.sticking = batch_stick_.data();
      law->tangential_forces(batch);
    }

    history_next_.clear();
    double rx = 0.0, ry = 0.0, rz = 0.0, torque = 0.0, power = 0.0, heat = 0.0, gap_sum = 0.0, gap_max = 0.0;
    std::size_t tool_stuck = 0;
    const bool takes_heat = a.tool_takes_heat && a.tool_takes_heat[t] != 0;
    double to_tool = 0.0;
    const double phi = settings_.heat_to_workpiece, inv_s = 1.0 / a.mass_scaling;
    // Sequential over the contacts (a small fraction of the particles): the tool's sums then
    // come out in the same order, bit for bit, whatever the thread count.
    for (std::size_t c = 0; c < nc; ++c) {
      const std::size_t i = particle_[c];
      double f[3];
      for (int d = 0; d < 3; ++d) {
        f[d] = batch_fn_[c] * batch_normal_[3 * c + d] + batch_ft_[3 * c + d];
        a.force[3 * i + d] += f[d];
      }
      if (keeps_history)
        history_next_.push_back({a.id[i], {batch_history_[3 * c], batch_history_[3 * c + 1], batch_history_[3 * c + 2]}});
      // Newton's third law: the tool receives -f; torque about the z axis (x f_y - y f_x).
      rx -= f[0];
      ry -= f[1];
      rz -= f[2];
      torque -= x[3 * i] * f[1] - x[3 * i + 1] * f[0];
      power += f[0] * batch_vwall_[3 * c] + f[1] * batch_vwall_[3 * c + 1] + f[2] * batch_vwall_[3 * c + 2];
      // Friction heat |f_t| |v_t| (eq. 18e); the workpiece's share phi heats the particle (eq. 18f).
      // A contact held on the wall kinematically does not slip and makes none (eq. 18j): its holding
      // force carries the mass-scaled inertia, which is not a dissipation.
      const double* ft = &batch_ft_[3 * c];
      const double* vt = &batch_vt_[3 * c];
      const double q = batch_stick_[c] == kHeldOnWall
                           ? 0.0
                           : std::sqrt(ft[0] * ft[0] + ft[1] * ft[1] + ft[2] * ft[2]) *
                                 std::sqrt(vt[0] * vt[0] + vt[1] * vt[1] + vt[2] * vt[2]);
      heat += q;
      if (a.heat_source) a.heat_source[i] += phi * q / (a.mass[i] * inv_s);
      // The rest, (1 - phi) q, goes to the tool's thermal particles near i (eq. 91), when it has any.
      if (takes_heat) {
        tool_heat_.push_back({t, i, (1.0 - phi) * q});
        to_tool += (1.0 - phi) * q;
      }
      gap_sum += std::max(batch_gap_[c], 0.0);
      gap_max = std::max(gap_max, batch_gap_[c]);
      tool_stuck += batch_stick_[c] > 0.5 ? 1 : 0;
    }
    // The touching particles' memory becomes the tool's, sorted by id for the next pass's lookups.
    if (keeps_history) {
      std::sort(history_next_.begin(), history_next_.end(),
                [](const FrictionHistoryEntry& p, const FrictionHistoryEntry& q) { return p.id < q.id; });
      history.swap(history_next_);
    } else {
      history.clear();
    }
    tool.reaction_force_N = Eigen::Vector3d(rx, ry, rz);
    tool.reaction_torque_Nm = torque;
    tool.power_W = power;
    tool.friction_heat_W = heat;
    st.contacts = nc;
    st.penetration_mean_m = gap_sum / static_cast<double>(nc);
    st.penetration_max_m = gap_max;
    st.sticking_fraction = static_cast<double>(tool_stuck) / static_cast<double>(nc);
    st.friction_heat_W = heat;
    st.heat_to_workpiece_W = phi * heat;
    st.heat_to_tool_W = to_tool;
    stuck += tool_stuck;
    total += nc;
  }
  sticking_fraction_ = total ? static_cast<double>(stuck) / static_cast<double>(total) : 0.0;
  return total;
}

}  // namespace sphforge
