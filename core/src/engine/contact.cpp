#include "engine/contact.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sphforge {

void PenaltyContact::configure(const ContactSettings& settings, std::vector<const ContactLaw*> laws,
                               double spacing, double p_wave_modulus) {
  settings_ = settings;
  laws_ = std::move(laws);
  spacing_ = spacing;
  // A particle pressed on a wall is resisted like a column of its own material of cross-section
  // dx^2 and length dx: k = M dx^2 / dx (eq. 10). Its frequency sqrt(k/m) = c/dx is then of the
  // order of the bulk's own, so the contact does not need a smaller step than the CFL limit.
  stiffness_ = settings.stiffness_factor * p_wave_modulus * spacing;
}

double PenaltyContact::stable_time_step(double min_mass) const {
  if (stiffness_ <= 0.0) return std::numeric_limits<double>::infinity();
  // Central difference on a damped oscillator: dt < 2/omega (sqrt(1+zeta^2) - zeta)  (eq. 12)
  const double omega = std::sqrt(stiffness_ / min_mass);
  const double z = settings_.damping_ratio;
  return 2.0 / omega * (std::sqrt(1.0 + z * z) - z);
}

std::size_t PenaltyContact::apply(std::vector<RigidTool>& tools, const double* x, const double* v,
                                  const double* mass, const double* yield, std::size_t n, double dt,
                                  double* force) {
  const double contact_radius = 0.5 * spacing_;  // a particle's half-width touches the wall
  const double area = spacing_ * spacing_;
  distance_.resize(n);
  normal_.resize(3 * n);
  std::size_t total = 0, stuck = 0;

  for (std::size_t t = 0; t < tools.size(); ++t) {
    RigidTool& tool = tools[t];
    tool.reaction_force_N.setZero();
    tool.reaction_torque_Nm = 0.0;
    tool.power_W = 0.0;
    // One batch query per tool (docs/theory.md eqs. 40-46); particles farther than the contact
    // radius outside the tool's bounds come back at infinite distance.
    tool.signed_distance(n, x, distance_.data(), normal_.data(), contact_radius);

    // Gather the touching particles in index order (deterministic).
    particle_.clear();
    for (std::size_t i = 0; i < n; ++i)
      if (distance_[i] < contact_radius) particle_.push_back(i);
    const std::size_t nc = particle_.size();
    if (nc == 0) continue;
    batch_mass_.resize(nc);
    batch_normal_.resize(3 * nc);
    batch_fn_.resize(nc);
    batch_gap_.resize(nc);
    batch_vt_.resize(3 * nc);
    batch_vwall_.resize(3 * nc);
    batch_area_.assign(nc, area);
    batch_yield_.resize(nc);
    batch_ft_.assign(3 * nc, 0.0);
    batch_stick_.assign(nc, 0.0);

    for (std::size_t c = 0; c < nc; ++c) {
      const std::size_t i = particle_[c];
      const Eigen::Vector3d xi(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
      const Eigen::Vector3d nrm(normal_[3 * i], normal_[3 * i + 1], normal_[3 * i + 2]);
      const Eigen::Vector3d v_wall = tool.surface_velocity(xi);
      const Eigen::Vector3d v_rel = Eigen::Vector3d(v[3 * i], v[3 * i + 1], v[3 * i + 2]) - v_wall;
      const double vn = v_rel.dot(nrm);
      const double gap = contact_radius - distance_[i];
      // Damped penalty (eq. 11); a wall only pushes, never pulls.
      const double damping = 2.0 * settings_.damping_ratio * std::sqrt(stiffness_ * mass[i]);
      const double fn = std::max(0.0, stiffness_ * gap - damping * vn);
      // Tangential relative velocity: v - (v.n) n  (never a component-wise product).
      const Eigen::Vector3d vt = v_rel - vn * nrm;
      batch_mass_[c] = mass[i];
      batch_fn_[c] = fn;
      batch_gap_[c] = gap;
      batch_yield_[c] = yield ? yield[i] : std::numeric_limits<double>::infinity();
      for (int d = 0; d < 3; ++d) {
        batch_normal_[3 * c + d] = nrm[d];
        batch_vt_[3 * c + d] = vt[d];
        batch_vwall_[3 * c + d] = v_wall[d];
      }
    }

    if (t < laws_.size() && laws_[t] != nullptr) {
      ContactBatch batch;
      batch.count = nc;
      batch.dt = dt;
      batch.particle = particle_.data();
      batch.mass = batch_mass_.data();
      batch.normal = batch_normal_.data();
      batch.normal_force = batch_fn_.data();
      batch.penetration = batch_gap_.data();
      batch.tangential_velocity = batch_vt_.data();
      batch.contact_area = batch_area_.data();
      batch.yield_stress = batch_yield_.data();
      batch.tangential_force = batch_ft_.data();
      batch.sticking = batch_stick_.data();
      laws_[t]->tangential_forces(batch);
    }

    Eigen::Vector3d reaction = Eigen::Vector3d::Zero();
    double torque = 0.0, power = 0.0;
    for (std::size_t c = 0; c < nc; ++c) {
      const std::size_t i = particle_[c];
      Eigen::Vector3d f;
      for (int d = 0; d < 3; ++d) f[d] = batch_fn_[c] * batch_normal_[3 * c + d] + batch_ft_[3 * c + d];
      for (int d = 0; d < 3; ++d) force[3 * i + d] += f[d];
      // Newton's third law: the tool receives -f; torque about the z axis (x f_y - y f_x).
      reaction -= f;
      torque -= x[3 * i] * f.y() - x[3 * i + 1] * f.x();
      power += f.dot(Eigen::Vector3d(batch_vwall_[3 * c], batch_vwall_[3 * c + 1], batch_vwall_[3 * c + 2]));
      stuck += batch_stick_[c] > 0.5 ? 1 : 0;
    }
    tool.reaction_force_N = reaction;
    tool.reaction_torque_Nm = torque;
    tool.power_W = power;
    total += nc;
  }
  sticking_fraction_ = total ? static_cast<double>(stuck) / static_cast<double>(total) : 0.0;
  return total;
}

}  // namespace sphforge
