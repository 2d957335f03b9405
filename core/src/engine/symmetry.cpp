// Mirror planes and rotationally periodic sectors (docs/theory.md section 11, eqs. 28-32).
#include "engine/symmetry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "engine/neighbours.hpp"
#include "sphforge/fields.hpp"

namespace sphforge {

namespace {

using Vec = Eigen::Vector3d;
using Mat = Eigen::Matrix3d;

Mat unpack_symmetric(const double* s) {
  Mat S;
  S << s[0], s[3], s[5], s[3], s[1], s[4], s[5], s[4], s[2];
  return S;
}

/// Distance from y to the half-plane {s e + z ez : s >= 0} bounded by the z axis, e = (cos phi, sin phi, 0).
double half_plane_distance(const Vec& y, double phi) {
  const double c = std::cos(phi), s = std::sin(phi);
  const double along = c * y[0] + s * y[1], across = -s * y[0] + c * y[1];
  return along >= 0.0 ? std::abs(across) : std::hypot(y[0], y[1]);
}

}  // namespace

Symmetry::Symmetry(const SymmetrySettings& settings) : settings_(settings) {
  const auto& planes = settings_.mirror_planes;
  if (planes.size() > 3) throw std::invalid_argument("at most three mirror planes (pairwise orthogonal)");
  for (auto& p : settings_.mirror_planes) {
    const double norm = p.normal.norm();
    if (!(norm > 0.0)) throw std::invalid_argument("a mirror plane's normal must not be zero");
    p.normal /= norm;
  }
  for (std::size_t a = 0; a < planes.size(); ++a)
    for (std::size_t b = a + 1; b < planes.size(); ++b)
      if (std::abs(planes[a].normal.dot(planes[b].normal)) > 1e-9)
        throw std::invalid_argument("mirror planes must be pairwise orthogonal (then their reflections commute and "
                                    "generate a finite group)");
  if (settings_.sector_angle_rad > 0.0) {
    const double turns = 2.0 * std::numbers::pi / settings_.sector_angle_rad;
    sectors_ = static_cast<int>(std::lround(turns));
    if (sectors_ < 2 || std::abs(turns - sectors_) > 1e-9 * turns)
      throw std::invalid_argument("the sector angle must be 360 deg / N with an integer N >= 2");
    settings_.sector_angle_rad = 2.0 * std::numbers::pi / sectors_;
    for (const auto& p : planes)
      if (std::abs(std::abs(p.normal[2]) - 1.0) > 1e-9)
        throw std::invalid_argument("with a sector, mirror planes must be normal to the sector's axis (z)");
  }
  // The group: R^k M_S for k = 0 .. N-1 and every subset S of the planes (eq. 29).
  const std::size_t subsets = std::size_t(1) << planes.size();
  for (int k = 0; k < sectors_; ++k) {
    const double phi = k * settings_.sector_angle_rad;
    Mat R = Mat::Identity();
    R(0, 0) = std::cos(phi), R(0, 1) = -std::sin(phi), R(1, 0) = std::sin(phi), R(1, 1) = std::cos(phi);
    for (std::size_t mask = 0; mask < subsets; ++mask) {
      if (k == 0 && mask == 0) continue;  // the identity
      SymmetryImage g;
      for (std::size_t p = 0; p < planes.size(); ++p) {
        if (!(mask & (std::size_t(1) << p))) continue;
        const Vec& n = settings_.mirror_planes[p].normal;
        const Mat P = Mat::Identity() - 2.0 * n * n.transpose();  // eq. 28
        // x -> P (x - p) + p composed after g: Q' = P Q, t' = P t + 2 (n . p) n.
        g.Q = P * g.Q;
        g.t = P * g.t + 2.0 * n.dot(settings_.mirror_planes[p].point) * n;
      }
      g.Q = R * g.Q;
      g.t = R * g.t;
      images_.push_back(g);
    }
  }
  if (images_.size() > std::numeric_limits<std::uint16_t>::max()) throw std::invalid_argument("too many sectors");
}

bool Symmetry::inside(const Vec& x) const {
  for (const auto& p : settings_.mirror_planes)
    if (p.normal.dot(x - p.point) < 0.0) return false;
  if (settings_.sector_angle_rad > 0.0 && (x[0] != 0.0 || x[1] != 0.0)) {
    double theta = std::atan2(x[1], x[0]);
    if (theta < 0.0) theta += 2.0 * std::numbers::pi;
    if (!(theta < settings_.sector_angle_rad)) return false;
  }
  return true;
}

double Symmetry::distance_bound(const Vec& y) const {
  // The region is the intersection of convex sets (half-spaces, a wedge of at most 180 deg): the
  // largest distance to one of them bounds the distance to the intersection from below.
  double d = 0.0;
  for (const auto& p : settings_.mirror_planes) d = std::max(d, -p.normal.dot(y - p.point));
  if (settings_.sector_angle_rad > 0.0 && (y[0] != 0.0 || y[1] != 0.0)) {
    double theta = std::atan2(y[1], y[0]);
    if (theta < 0.0) theta += 2.0 * std::numbers::pi;
    if (!(theta < settings_.sector_angle_rad))
      d = std::max(d, std::min(half_plane_distance(y, 0.0), half_plane_distance(y, settings_.sector_angle_rad)));
  }
  return d;
}

void Symmetry::transform_vector(const Mat& Q, const double* in, double* out) {
  const Vec r = Q * Vec(in[0], in[1], in[2]);
  out[0] = r[0], out[1] = r[1], out[2] = r[2];
}

void Symmetry::transform_symmetric(const Mat& Q, const double* in, double* out) {
  const Mat S = Q * unpack_symmetric(in) * Q.transpose();
  out[0] = S(0, 0), out[1] = S(1, 1), out[2] = S(2, 2), out[3] = S(0, 1), out[4] = S(1, 2), out[5] = S(0, 2);
}

void Symmetry::transform_tensor(const Mat& Q, const double* in, double* out) {
  Mat A;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) A(r, c) = in[3 * r + c];
  const Mat B = Q * A * Q.transpose();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out[3 * r + c] = B(r, c);
}

std::size_t Symmetry::wrap(FieldRegistry& fields, std::size_t first, std::size_t last) const {
  std::vector<std::pair<std::size_t, std::size_t>> moves;  // particle, image
  return wrap_range(fields, first, last, moves);
}

std::size_t Symmetry::wrap(FieldRegistry& fields, std::size_t n,
                           std::vector<std::pair<std::size_t, std::size_t>>& moves) const {
  return wrap_range(fields, 0, n, moves);
}

std::size_t Symmetry::wrap_range(FieldRegistry& fields, std::size_t first, std::size_t last,
                                 std::vector<std::pair<std::size_t, std::size_t>>& moves) const {
  moves.clear();
  if (!active()) return 0;
  double* x = fields.f64(field::position);
  for (std::size_t i = first; i < last; ++i) {
    const Vec xi(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
    if (inside(xi)) continue;
    std::size_t best = 0;
    double best_d = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < images_.size(); ++k) {
      const double d = distance_bound(images_[k].Q * xi + images_[k].t);
      if (d < best_d) best_d = d, best = k;
      if (d == 0.0 && inside(images_[k].Q * xi + images_[k].t)) {
        best = k;
        break;
      }
    }
    moves.emplace_back(i, best);
  }
  if (moves.empty()) return 0;
  for (const std::string& name : fields.names()) {
    if (!fields.allocated(name)) continue;
    const FieldInfo& info = fields.info(name);
    if (info.type != FieldType::Float64) continue;
    double* a = fields.f64(name);
    const bool is_position = name == field::position;
    for (const auto& [i, k] : moves) {
      const SymmetryImage& g = images_[k];
      double tmp[9];
      if (info.components == 3) {
        transform_vector(g.Q, a + 3 * i, tmp);
        for (int d = 0; d < 3; ++d) a[3 * i + d] = tmp[d] + (is_position ? g.t[d] : 0.0);
      } else if (info.components == 6) {
        transform_symmetric(g.Q, a + 6 * i, tmp);
        for (int d = 0; d < 6; ++d) a[6 * i + d] = tmp[d];
      } else if (info.components == 9) {
        transform_tensor(g.Q, a + 9 * i, tmp);
        for (int d = 0; d < 9; ++d) a[9 * i + d] = tmp[d];
      }
    }
  }
  return moves.size();
}

std::pair<std::size_t, std::size_t> Symmetry::find_coincident(const std::vector<Vec>& x, double search_radius,
                                                              double tolerance) const {
  const std::size_t n = x.size();
  // The points searched: the particles [0, n), then every image that lies within `tolerance` of the
  // region (only those can meet a particle of it), each remembering its source particle.
  std::vector<double> points;
  std::vector<std::size_t> source;
  points.reserve(3 * n);
  for (const Vec& xi : x) points.insert(points.end(), {xi[0], xi[1], xi[2]});
  for (std::size_t i = 0; i < n; ++i)
    for (const SymmetryImage& g : images_) {
      const Vec y = g.Q * x[i] + g.t;
      if (distance_bound(y) > tolerance) continue;
      points.insert(points.end(), {y[0], y[1], y[2]});
      source.push_back(i);
    }
  // The core's cell list, with lists for the particles only; a lattice has no pair closer than
  // `search_radius` (half its spacing), so the lists are nearly empty.
  NeighbourList lists;
  lists.build(points.data(), n + source.size(), search_radius, n);
  for (std::size_t i = 0; i < n; ++i) {
    std::pair<std::size_t, std::size_t> found{n, n};
    lists.for_each(i, [&](std::size_t k) {
      const Vec pk(points[3 * k], points[3 * k + 1], points[3 * k + 2]);
      if (found.first < n || (pk - x[i]).norm() >= tolerance) return;
      const std::size_t j = k < n ? k : source[k - n];
      if (j != i) found = {i, j};  // a particle on a mirror plane is its own image, not a pair
    });
    if (found.first < n) return found;
  }
  return {n, n};
}

void Symmetry::select(const double* x, std::size_t n, double range) {
  source_.clear();
  image_.clear();
  if (!active()) return;
  const double coincide = 1e-9 * range;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec xi(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
    // An image lies in the image of the region, whose interior the region's does not overlap: its
    // distance to the region is at least the source's distance to the region's boundary (the cuts).
    // Most particles are farther than `range` from every cut and need no image test.
    double to_cut = std::numeric_limits<double>::infinity();
    for (const auto& p : settings_.mirror_planes) to_cut = std::min(to_cut, std::abs(p.normal.dot(xi - p.point)));
    if (settings_.sector_angle_rad > 0.0)
      to_cut = std::min({to_cut, half_plane_distance(xi, 0.0), half_plane_distance(xi, settings_.sector_angle_rad)});
    if (!(to_cut < range)) continue;
    for (std::size_t k = 0; k < images_.size(); ++k) {
      const Vec y = images_[k].Q * xi + images_[k].t;
      if ((y - xi).norm() < coincide) continue;  // a particle on a cut is its own image
      if (distance_bound(y) < range) {
        source_.push_back(static_cast<std::uint32_t>(i));
        image_.push_back(static_cast<std::uint16_t>(k));
      }
    }
  }
}

void Symmetry::fill_positions(double* x, std::size_t n) const {
  const std::size_t g = source_.size();
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < g; ++k) {
    const SymmetryImage& im = images_[image_[k]];
    double* out = x + 3 * (n + k);
    transform_vector(im.Q, x + 3 * source_[k], out);
    for (int d = 0; d < 3; ++d) out[d] += im.t[d];
  }
}

void Symmetry::fill_vectors(double* v, std::size_t n) const {
  const std::size_t g = source_.size();
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < g; ++k) transform_vector(images_[image_[k]].Q, v + 3 * source_[k], v + 3 * (n + k));
}

void Symmetry::fill_scalars(double* s, std::size_t n) const {
  const std::size_t g = source_.size();
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < g; ++k) s[n + k] = s[source_[k]];
}

void Symmetry::fill_symmetric(double* S, std::size_t n) const {
  const std::size_t g = source_.size();
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < g; ++k) transform_symmetric(images_[image_[k]].Q, S + 6 * source_[k], S + 6 * (n + k));
}

void Symmetry::fill_tensors(double* A, std::size_t n) const {
  const std::size_t g = source_.size();
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < g; ++k) transform_tensor(images_[image_[k]].Q, A + 9 * source_[k], A + 9 * (n + k));
}

}  // namespace sphforge
