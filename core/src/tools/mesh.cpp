// Triangle-mesh tools from STL: bounding-volume hierarchy (median split, AABB nodes) and signed
// distance with angle-weighted pseudo-normals (Baerentzen & Aanaes 2005); docs/theory.md eq. (44).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <numeric>
#include <stdexcept>

#include <Eigen/Geometry>
#include <vtkCellArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkSTLReader.h>

#include "tools/shapes.hpp"

namespace sphforge {

namespace {

using Vec = Eigen::Vector3d;

/// Which feature of a triangle holds the nearest point: the face, an edge or a vertex.
enum Feature : int { kFace = 0, kEdgeAB, kEdgeBC, kEdgeCA, kVertexA, kVertexB, kVertexC };

/// Nearest point of triangle (a, b, c) to p by Voronoi regions (Ericson, Real-Time Collision
/// Detection, sec. 5.1.5), with the feature it lies on.
Vec closest_on_triangle(const Vec& p, const Vec& a, const Vec& b, const Vec& c, int& feature) {
  const Vec ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return feature = kVertexA, a;
  const Vec bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return feature = kVertexB, b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return feature = kEdgeAB, Vec(a + d1 / (d1 - d3) * ab);
  const Vec cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return feature = kVertexC, c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return feature = kEdgeCA, Vec(a + d2 / (d2 - d6) * ac);
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0)
    return feature = kEdgeBC, Vec(b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b));
  const double denom = 1.0 / (va + vb + vc);
  feature = kFace;
  return a + ab * (vb * denom) + ac * (vc * denom);
}

double box_distance2(const Vec& p, const Vec& lo, const Vec& hi) {
  const Vec below = (lo - p).cwiseMax(0.0), above = (p - hi).cwiseMax(0.0);
  return below.squaredNorm() + above.squaredNorm();
}

class MeshShape final : public ToolShape {
 public:
  MeshShape(std::vector<Vec> points, std::vector<std::array<int, 3>> triangles)
      : point_(std::move(points)), tri_(std::move(triangles)) {
    // Drop degenerate triangles: they have no normal.
    std::erase_if(tri_, [&](const std::array<int, 3>& t) {
      return (point_[t[1]] - point_[t[0]]).cross(point_[t[2]] - point_[t[0]]).norm() <= 0.0;
    });
    if (tri_.empty()) throw std::runtime_error("the mesh holds no triangle of non-zero area");
    build_hierarchy();
    build_pseudo_normals();
  }

  const char* kind() const override { return "stl"; }

  void signed_distance(std::size_t count, const double* x, double* d, double* n) const override {
    // Consecutive points of a batch are usually neighbours (the core keeps particles in Z-order):
    // the previous point's nearest triangle gives a tight first bound, and the search prunes more.
    std::size_t hint = 0;
    for (std::size_t i = 0; i < count; ++i) {
      Vec normal;
      d[i] = query(Vec(x[3 * i], x[3 * i + 1], x[3 * i + 2]), normal, true, &hint);
      n[3 * i] = normal.x();
      n[3 * i + 1] = normal.y();
      n[3 * i + 2] = normal.z();
    }
  }

  void bounds(Vec& lo, Vec& hi) const override {
    lo = node_.front().lo;
    hi = node_.front().hi;
  }

  void surface(SurfaceMesh& mesh, int) const override {
    const auto base = static_cast<std::int64_t>(mesh.points.size());
    mesh.points.insert(mesh.points.end(), point_.begin(), point_.end());
    for (const auto& t : tri_) mesh.add_polygon({base + t[0], base + t[1], base + t[2]});
  }

  /// Nearest triangle through the hierarchy (use_tree) or over every triangle; the sign from the
  /// pseudo-normal of the nearest feature (eq. 44).
  double query(const Vec& p, Vec& normal, bool use_tree, std::size_t* hint = nullptr) const {
    double best_d2 = std::numeric_limits<double>::infinity();
    Vec best_point = point_[tri_[0][0]];
    std::size_t best_tri = 0;
    int best_feature = kFace;
    auto test = [&](std::size_t t) {
      int feature;
      const Vec q = closest_on_triangle(p, point_[tri_[t][0]], point_[tri_[t][1]], point_[tri_[t][2]], feature);
      const double d2 = (p - q).squaredNorm();
      if (d2 < best_d2) {
        best_d2 = d2;
        best_point = q;
        best_tri = t;
        best_feature = feature;
      }
    };
    if (hint) test(*hint);
    if (use_tree) {
      // Depth-first, nearer child first; a node farther than the best so far is skipped. A
      // median split halves the triangles per level, so 64 levels cover any mesh that fits memory.
      int stack[64];
      int top = 0;
      stack[top++] = 0;
      while (top > 0) {
        const Node& node = node_[static_cast<std::size_t>(stack[--top])];
        if (box_distance2(p, node.lo, node.hi) >= best_d2) continue;
        if (node.left < 0) {
          for (int t = node.first; t < node.first + node.count; ++t) test(static_cast<std::size_t>(t));
          continue;
        }
        const double dl = box_distance2(p, node_[node.left].lo, node_[node.left].hi);
        const double dr = box_distance2(p, node_[node.right].lo, node_[node.right].hi);
        if (dl <= dr) {
          stack[top++] = node.right;
          stack[top++] = node.left;
        } else {
          stack[top++] = node.left;
          stack[top++] = node.right;
        }
      }
    } else {
      for (std::size_t t = 0; t < tri_.size(); ++t) test(t);
    }
    if (hint) *hint = best_tri;
    const Vec& pseudo = feature_normal_[7 * best_tri + static_cast<std::size_t>(best_feature)];
    const Vec diff = p - best_point;
    const double dist = std::sqrt(best_d2);
    const double sign = diff.dot(pseudo) >= 0.0 ? 1.0 : -1.0;
    normal = dist > 1e-14 ? Vec(sign * diff / dist) : pseudo;
    return sign * dist;
  }

 private:
  struct Node {
    Vec lo, hi;
    int left = -1, right = -1;  // children (-1: leaf)
    int first = 0, count = 0;   // leaf triangles [first, first + count)
  };

  void build_hierarchy() {
    node_.reserve(2 * tri_.size());
    node_.emplace_back();
    build_node(0, 0, static_cast<int>(tri_.size()));
  }

  void build_node(std::size_t index, int first, int count) {
    Vec lo = Vec::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    Vec clo = lo, chi = hi;  // centroid bounds
    for (int t = first; t < first + count; ++t) {
      Vec centroid = Vec::Zero();
      for (int v : tri_[static_cast<std::size_t>(t)]) {
        lo = lo.cwiseMin(point_[v]);
        hi = hi.cwiseMax(point_[v]);
        centroid += point_[v] / 3.0;
      }
      clo = clo.cwiseMin(centroid);
      chi = chi.cwiseMax(centroid);
    }
    node_[index].lo = lo;
    node_[index].hi = hi;
    node_[index].first = first;
    node_[index].count = count;
    constexpr int leaf_size = 4;
    if (count <= leaf_size) return;
    // Median split along the longest axis of the centroids' box.
    int axis = 0;
    (chi - clo).maxCoeff(&axis);
    auto centre = [&](const std::array<int, 3>& t) { return point_[t[0]][axis] + point_[t[1]][axis] + point_[t[2]][axis]; };
    const int half = count / 2;
    std::nth_element(tri_.begin() + first, tri_.begin() + first + half, tri_.begin() + first + count,
                     [&](const auto& a, const auto& b) { return centre(a) < centre(b); });
    const int left = static_cast<int>(node_.size());
    node_.emplace_back();
    node_.emplace_back();
    node_[index].left = left;
    node_[index].right = left + 1;
    build_node(static_cast<std::size_t>(left), first, half);
    build_node(static_cast<std::size_t>(left + 1), first + half, count - half);
  }

  void build_pseudo_normals() {
    // Per triangle: face normal, edge pseudo-normals (sum of the two faces' normals) and vertex
    // pseudo-normals (angle-weighted sum over the incident faces), indexed like Feature.
    const std::size_t nt = tri_.size();
    std::vector<Vec> face(nt);
    std::vector<Vec> vertex(point_.size(), Vec::Zero());
    std::map<std::pair<int, int>, Vec> edge;
    for (std::size_t t = 0; t < nt; ++t) {
      const auto& T = tri_[t];
      face[t] = (point_[T[1]] - point_[T[0]]).cross(point_[T[2]] - point_[T[0]]).normalized();
      for (int k = 0; k < 3; ++k) {
        const int a = T[k], b = T[(k + 1) % 3], c = T[(k + 2) % 3];
        // try_emplace: an Eigen vector default-constructs uninitialised.
        edge.try_emplace({std::min(a, b), std::max(a, b)}, Vec::Zero()).first->second += face[t];
        const Vec e1 = (point_[b] - point_[a]).normalized(), e2 = (point_[c] - point_[a]).normalized();
        vertex[a] += std::acos(std::clamp(e1.dot(e2), -1.0, 1.0)) * face[t];
      }
    }
    auto unit = [](const Vec& v, const Vec& fallback) { return v.norm() > 1e-12 ? Vec(v.normalized()) : fallback; };
    feature_normal_.resize(7 * nt);
    for (std::size_t t = 0; t < nt; ++t) {
      const auto& T = tri_[t];
      auto edge_normal = [&](int a, int b) { return unit(edge[{std::min(a, b), std::max(a, b)}], face[t]); };
      feature_normal_[7 * t + kFace] = face[t];
      feature_normal_[7 * t + kEdgeAB] = edge_normal(T[0], T[1]);
      feature_normal_[7 * t + kEdgeBC] = edge_normal(T[1], T[2]);
      feature_normal_[7 * t + kEdgeCA] = edge_normal(T[2], T[0]);
      feature_normal_[7 * t + kVertexA] = unit(vertex[T[0]], face[t]);
      feature_normal_[7 * t + kVertexB] = unit(vertex[T[1]], face[t]);
      feature_normal_[7 * t + kVertexC] = unit(vertex[T[2]], face[t]);
    }
  }

  std::vector<Vec> point_;
  std::vector<std::array<int, 3>> tri_;
  std::vector<Node> node_;
  std::vector<Vec> feature_normal_;  // 7 per triangle
};

}  // namespace

std::shared_ptr<const ToolShape> make_mesh_shape(std::vector<Eigen::Vector3d> points,
                                                 std::vector<std::array<int, 3>> triangles) {
  return std::make_shared<MeshShape>(std::move(points), std::move(triangles));
}

double mesh_signed_distance_brute_force(const ToolShape& mesh, const Eigen::Vector3d& x, Eigen::Vector3d& normal) {
  const auto* m = dynamic_cast<const MeshShape*>(&mesh);
  if (!m) throw std::invalid_argument("not a mesh shape");
  return m->query(x, normal, false);
}

std::shared_ptr<const ToolShape> load_stl_shape(const std::string& path, double scale) {
  if (!std::filesystem::is_regular_file(path)) throw std::runtime_error("STL file '" + path + "' not found");
  if (!(scale > 0.0)) throw std::runtime_error("STL scale must be positive");
  vtkNew<vtkSTLReader> reader;
  reader->SetFileName(path.c_str());
  reader->MergingOn();  // shared vertices and edges: the pseudo-normals need the connectivity
  reader->Update();
  vtkPolyData* poly = reader->GetOutput();
  if (reader->GetErrorCode() != 0 || poly == nullptr || poly->GetNumberOfPolys() == 0)
    throw std::runtime_error("STL file '" + path + "' could not be read or holds no triangle");
  std::vector<Eigen::Vector3d> points(static_cast<std::size_t>(poly->GetNumberOfPoints()));
  for (vtkIdType i = 0; i < poly->GetNumberOfPoints(); ++i) {
    double p[3];
    poly->GetPoint(i, p);
    points[static_cast<std::size_t>(i)] = scale * Eigen::Vector3d(p[0], p[1], p[2]);
  }
  std::vector<std::array<int, 3>> triangles;
  vtkCellArray* cells = poly->GetPolys();
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < cells->GetNumberOfCells(); ++c) {
    cells->GetCellAtId(c, ids);
    if (ids->GetNumberOfIds() != 3) continue;
    triangles.push_back({static_cast<int>(ids->GetId(0)), static_cast<int>(ids->GetId(1)), static_cast<int>(ids->GetId(2))});
  }
  try {
    return make_mesh_shape(std::move(points), std::move(triangles));
  } catch (const std::runtime_error& e) {
    throw std::runtime_error("STL file '" + path + "': " + e.what());
  }
}

}  // namespace sphforge
