// Stage "cube map" (cube_map.hpp): corners, curves, mean-value patches, harmonic interior.
#define EIGEN_NO_DEBUG 1  // Eigen's checks abort() rather than throw: leave them out
#include "tpmsfill/solid/cube_map.hpp"

#if defined(CGAL_EIGEN3_ENABLED)
#include <Eigen/Dense>
#endif

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <string>
#include <unordered_map>
#include <utility>

#include "core/disjoint_sets.hpp"
#include "core/stage_progress.hpp"
#include "mesh/dirichlet.hpp"
#include "mesh/edge_key.hpp"
#include "mesh/exact_orientation.hpp"
#include "solid/internal/harmonic.hpp"
#include "solid/internal/untangle.hpp"
#include "tpmsfill/error.hpp"

namespace tpmsfill {

namespace {

using detail::edge_key;
using Uvw = std::array<double, 3>;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// with_folds_opened(): the rings around what stays folded, and the values of ε each may try.
constexpr std::array<int, 2> kOpeningRings = {2, 4};
constexpr int kOpeningRounds = 1000;

int corner_bit(int corner, int axis) {
  return (corner >> axis) & 1;
}

// The boundary's vertex graph: the neighbours of v are neighbours[offsets[v] .. offsets[v + 1]).
struct BoundaryGraph {
  std::vector<std::uint32_t> offsets, neighbours;
  bool on_boundary(std::uint32_t v) const { return offsets[v + 1] > offsets[v]; }
};

BoundaryGraph boundary_graph(std::size_t points, const std::vector<Triangle>& faces) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> directed;
  directed.reserve(faces.size() * 6);
  for (const Triangle& f : faces)
    for (int i = 0; i < 3; ++i) {
      directed.emplace_back(f[i], f[(i + 1) % 3]);
      directed.emplace_back(f[(i + 1) % 3], f[i]);
    }
  std::sort(directed.begin(), directed.end());
  directed.erase(std::unique(directed.begin(), directed.end()), directed.end());
  BoundaryGraph graph;
  graph.offsets.assign(points + 1, 0);
  for (const auto& [a, b] : directed) ++graph.offsets[a + 1];
  for (std::size_t v = 0; v < points; ++v) graph.offsets[v + 1] += graph.offsets[v];
  graph.neighbours.reserve(directed.size());
  for (const auto& [a, b] : directed) graph.neighbours.push_back(b);
  return graph;
}

using Frame = std::array<Vec3, 3>;  // orthonormal, right-handed

// The boundary vertex furthest towards each corner of the boundary's box in `frame`, each axis
// scaled by the box's size there (lowest index on ties).
std::array<std::uint32_t, 8> find_corners(const TetMesh& mesh, const BoundaryGraph& graph,
                                          const Frame& frame) {
  Vec3 lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  auto coordinates = [&](std::uint32_t v) {
    const Vec3 p = mesh.points[v];
    return Vec3{dot(p, frame[0]), dot(p, frame[1]), dot(p, frame[2])};
  };
  for (std::uint32_t v = 0; v < mesh.points.size(); ++v)
    if (graph.on_boundary(v)) {
      const Vec3 q = coordinates(v);
      lo = {std::min(lo.x, q.x), std::min(lo.y, q.y), std::min(lo.z, q.z)};
      hi = {std::max(hi.x, q.x), std::max(hi.y, q.y), std::max(hi.z, q.z)};
    }
  const Vec3 centre = 0.5 * (lo + hi), size = hi - lo;
  std::array<std::uint32_t, 8> corners{};
  for (int k = 0; k < 8; ++k) {
    double best = -std::numeric_limits<double>::infinity();
    for (std::uint32_t v = 0; v < mesh.points.size(); ++v) {
      if (!graph.on_boundary(v)) continue;
      const Vec3 q = coordinates(v);
      double reach = 0;
      for (int a = 0; a < 3; ++a)
        reach += (corner_bit(k, a) ? 1 : -1) * (q[a] - centre[a]) / (size[a] > 0 ? size[a] : 1);
      if (reach > best) {
        best = reach;
        corners[k] = v;
      }
    }
  }
  for (int a = 0; a < 8; ++a)
    for (int b = a + 1; b < 8; ++b)
      if (corners[a] == corners[b])
        throw InputError("the cube's corners " + std::to_string(a) + " and " + std::to_string(b) +
                         " were both found at vertex " + std::to_string(corners[a]) +
                         " (a thin or pointed part); give the eight corner vertices");
  return corners;
}

// The frames whose boxes give the corners to try: the axes, then the boundary's principal
// axes (longest first), which suit a long or tilted part better, then both turned.
std::vector<Frame> corner_frames(const TetMesh& mesh, const BoundaryGraph& graph) {
  std::vector<Frame> frames{Frame{Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}}};
#if defined(CGAL_EIGEN3_ENABLED)
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  double n = 0;
  for (std::uint32_t v = 0; v < mesh.points.size(); ++v)
    if (graph.on_boundary(v)) {
      mean += Eigen::Vector3d(mesh.points[v].x, mesh.points[v].y, mesh.points[v].z);
      n += 1;
    }
  mean /= std::max(n, 1.0);
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (std::uint32_t v = 0; v < mesh.points.size(); ++v)
    if (graph.on_boundary(v)) {
      const Eigen::Vector3d d =
          Eigen::Vector3d(mesh.points[v].x, mesh.points[v].y, mesh.points[v].z) - mean;
      covariance += d * d.transpose();
    }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  auto axis = [&](int column) {
    const Eigen::Vector3d e = solver.eigenvectors().col(column);
    return Vec3{e.x(), e.y(), e.z()};
  };
  const Vec3 first = axis(2), second = axis(1);
  frames.push_back({first, second, cross(first, second)});
#endif
  // Then each of those turned by ±45° about each of its axes: a box's extremes on a limbed
  // scan (triceratops: horns, tail, feet) may pick corners whose curves cannot cut its
  // boundary as the cube's edges do, while a turned box picks others that can.
  const std::size_t base = frames.size();
  for (std::size_t f = 0; f < base; ++f)
    for (int a = 0; a < 3; ++a)
      for (const double turn : {0.25, -0.25}) {
        const double angle = turn * std::acos(-1.0), c = std::cos(angle), s = std::sin(angle);
        const Vec3 u = frames[f][(a + 1) % 3], v = frames[f][(a + 2) % 3];
        Frame turned = frames[f];
        turned[(a + 1) % 3] = c * u + s * v;
        turned[(a + 2) % 3] = c * v - s * u;
        frames.push_back(turned);
      }
  return frames;
}

void check_given_corners(const std::array<std::uint32_t, 8>& corners, const BoundaryGraph& graph,
                         std::size_t points) {
  for (int k = 0; k < 8; ++k) {
    if (corners[k] >= points || !graph.on_boundary(corners[k]))
      throw InputError("corner " + std::to_string(k) + " (vertex " + std::to_string(corners[k]) +
                       ") is not a vertex of the boundary");
    for (int j = 0; j < k; ++j)
      if (corners[j] == corners[k])
        throw InputError("corners " + std::to_string(j) + " and " + std::to_string(k) +
                         " are the same vertex " + std::to_string(corners[k]));
  }
}

// Dijkstra on the boundary's edges from `from` to `to`, never entering a blocked vertex but
// `to`. Empty when `to` cannot be reached.
std::vector<std::uint32_t> shortest_path(const TetMesh& mesh, const BoundaryGraph& graph,
                                         std::uint32_t from, std::uint32_t to,
                                         const std::vector<char>& blocked) {
  const std::size_t n = mesh.points.size();
  std::vector<double> dist(n, std::numeric_limits<double>::infinity());
  std::vector<std::uint32_t> previous(n, from);
  using Item = std::pair<double, std::uint32_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
  dist[from] = 0;
  queue.emplace(0.0, from);
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > dist[v]) continue;
    if (v == to) break;
    for (std::uint32_t i = graph.offsets[v]; i < graph.offsets[v + 1]; ++i) {
      const std::uint32_t w = graph.neighbours[i];
      if (blocked[w] && w != to) continue;
      const double dw = d + norm(mesh.points[w] - mesh.points[v]);
      if (dw < dist[w]) {
        dist[w] = dw;
        previous[w] = v;
        queue.emplace(dw, w);
      }
    }
  }
  if (!std::isfinite(dist[to])) return {};
  std::vector<std::uint32_t> path{to};
  while (path.back() != from) path.push_back(previous[path.back()]);
  std::reverse(path.begin(), path.end());
  return path;
}

double path_length(const TetMesh& mesh, const std::vector<std::uint32_t>& path) {
  double length = 0;
  for (std::size_t i = 1; i < path.size(); ++i)
    length += norm(mesh.points[path[i]] - mesh.points[path[i - 1]]);
  return length;
}

// The curve of cube edge e placed on the edge by normalised arc length.
void place_curve(const TetMesh& mesh, int e, std::vector<std::uint32_t> path, CubeMap& map) {
  const int k0 = cube_edge_corners(e)[0], axis = e / 4;
  const double length = path_length(mesh, path);
  double at = 0;
  for (std::size_t i = 0; i < path.size(); ++i) {
    if (i > 0) at += norm(mesh.points[path[i]] - mesh.points[path[i - 1]]);
    Uvw& p = map.uvw[path[i]];
    for (int a = 0; a < 3; ++a) p[a] = corner_bit(k0, a);
    p[axis] = i + 1 == path.size() ? 1.0 : (length > 0 ? at / length : 0.0);
  }
  map.curves[e] = std::move(path);
}

// Each boundary face's neighbour across its side i (from corner i to i + 1).
std::vector<std::array<std::uint32_t, 3>> face_neighbours(const std::vector<Triangle>& faces) {
  std::vector<std::pair<std::uint64_t, std::uint32_t>> sides;  // (edge, 3 · face + side)
  sides.reserve(faces.size() * 3);
  for (std::uint32_t f = 0; f < faces.size(); ++f)
    for (std::uint32_t i = 0; i < 3; ++i)
      sides.emplace_back(edge_key(faces[f][i], faces[f][(i + 1) % 3]), 3 * f + i);
  std::sort(sides.begin(), sides.end());
  std::vector<std::array<std::uint32_t, 3>> neighbours(faces.size());
  for (std::size_t i = 0; i + 1 < sides.size(); i += 2) {  // a closed 2-manifold: in pairs
    const std::uint32_t a = sides[i].second, b = sides[i + 1].second;
    neighbours[a / 3][a % 3] = b / 3;
    neighbours[b / 3][b % 3] = a / 3;
  }
  return neighbours;
}

// Traces the twelve curves so that they bound six patches as the cube's edges bound its faces,
// whatever the shape: the bottom loop (corners 0 1 3 2) first, cutting the boundary into two
// disks; the top loop (4 5 7 6) inside the disk holding the top corners, leaving an annulus
// between the loops; the four side curves across the annulus. Each curve is a shortest path
// inside its region past the curves before it.
class CurveTracer {
 public:
  CurveTracer(const TetMesh& mesh, const BoundaryGraph& graph, const std::vector<Triangle>& faces,
              CubeMap& map)
      : mesh_(mesh),
        graph_(graph),
        faces_(faces),
        neighbours_(face_neighbours(faces)),
        map_(map),
        allowed_(mesh.points.size(), 1),
        on_curve_(mesh.points.size(), 0) {}

  /// Traces with face `first` (2·axis + side) as the "bottom" whose loop goes first.
  /// @throws InputError  the loops do not separate the corners as the cube's faces do
  void trace(int first) {
    const int axis = first / 2, side = first % 2, b = (axis + 1) % 3, c = (axis + 2) % 3;
    // Face `first`'s corners in the order that puts its patch right of the loop seen from
    // outside (counter-clockwise seen from +axis on side 0, clockwise on side 1), and the
    // opposite face's corners in the same order (so its patch lies left of its loop).
    const int square[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    int bottom[4], top[4];
    for (int i = 0; i < 4; ++i) {
      const int* at = square[side == 0 ? i : (4 - i) % 4];
      bottom[i] = (side << axis) | (at[0] << b) | (at[1] << c);
      top[i] = bottom[i] ^ (1 << axis);
    }
    for (std::uint32_t corner : map_.corners) on_curve_[corner] = 1;
    trace_loop(bottom);
    const std::vector<char> below = region(faces_along(bottom, false));
    restrict_to(below, false);
    for (int k : top)
      if (!allowed_[map_.corners[k]])
        throw InputError("corner " + std::to_string(k) + " lies on face " + std::to_string(first) +
                         "'s side of that face's loop");
    trace_loop(top);
    // The opposite patch lies left of its loop; it must not reach the first loop.
    const std::vector<char> cap = region(faces_along(top, true));
    for (std::uint32_t f : faces_along(bottom, true))
      if (cap[f])
        throw InputError("the loop opposite face " + std::to_string(first) +
                         " turns the wrong way round");
    std::vector<char> outside(faces_.size());
    for (std::uint32_t f = 0; f < faces_.size(); ++f) outside[f] = below[f] || cap[f];
    restrict_to(outside, false);
    for (int k = 0; k < 4; ++k) trace_edge(bottom[k], top[k]);
  }

 private:
  void trace_loop(const int (&corners)[4]) {
    for (int i = 0; i < 4; ++i) trace_edge(corners[i], corners[(i + 1) % 4]);
  }

  // A shortest path from corner a to corner b through allowed vertices off the curves.
  void trace_edge(int a, int b) {
    std::vector<char> blocked(mesh_.points.size());
    for (std::size_t v = 0; v < blocked.size(); ++v) blocked[v] = on_curve_[v] || !allowed_[v];
    auto path = shortest_path(mesh_, graph_, map_.corners[a], map_.corners[b], blocked);
    if (path.empty())
      throw InputError("no boundary path joins corners " + std::to_string(a) + " and " +
                       std::to_string(b) + " past the curves traced before it");
    for (std::uint32_t v : path) on_curve_[v] = 1;
    if (a > b) std::reverse(path.begin(), path.end());
    place_curve(mesh_, edge_index(a, b), std::move(path), map_);
  }

  // The faces with a side on a loop of corners, on one side of it (left: where the faces'
  // orientation puts itself, left of the loop's directed edges seen from outside).
  std::vector<std::uint32_t> faces_along(const int (&corners)[4], bool left) const {
    std::unordered_map<std::uint64_t, char> directed;  // (from << 32 | to) along the loop
    for (int i = 0; i < 4; ++i) {
      const int a = corners[i], b = corners[(i + 1) % 4];
      const auto& curve = map_.curves[edge_index(a, b)];
      for (std::size_t j = 1; j < curve.size(); ++j) {
        const std::uint32_t from = a < b ? curve[j - 1] : curve[j],
                            to = a < b ? curve[j] : curve[j - 1];
        directed[left ? (std::uint64_t{from} << 32 | to) : (std::uint64_t{to} << 32 | from)] = 1;
      }
    }
    std::vector<std::uint32_t> found;
    for (std::uint32_t f = 0; f < faces_.size(); ++f)
      for (int i = 0; i < 3; ++i)
        if (directed.count(std::uint64_t{faces_[f][i]} << 32 | faces_[f][(i + 1) % 3])) {
          found.push_back(f);
          break;
        }
    return found;
  }

  // The faces reached from `seeds` without crossing a curve.
  std::vector<char> region(const std::vector<std::uint32_t>& seeds) const {
    std::unordered_map<std::uint64_t, char> walls;
    for (const auto& curve : map_.curves)
      for (std::size_t i = 1; i < curve.size(); ++i) walls[edge_key(curve[i - 1], curve[i])] = 1;
    std::vector<char> inside(faces_.size(), 0);
    std::vector<std::uint32_t> stack;
    for (std::uint32_t f : seeds)
      if (!inside[f]) {
        inside[f] = 1;
        stack.push_back(f);
      }
    while (!stack.empty()) {
      const std::uint32_t f = stack.back();
      stack.pop_back();
      for (int i = 0; i < 3; ++i) {
        const std::uint32_t g = neighbours_[f][i];
        if (inside[g] || walls.count(edge_key(faces_[f][i], faces_[f][(i + 1) % 3]))) continue;
        inside[g] = 1;
        stack.push_back(g);
      }
    }
    return inside;
  }

  // Later curves keep to the vertices of the faces not marked (`keep` false) or marked.
  void restrict_to(const std::vector<char>& faces, bool keep) {
    std::fill(allowed_.begin(), allowed_.end(), 0);
    for (std::uint32_t f = 0; f < faces_.size(); ++f)
      if (static_cast<bool>(faces[f]) == keep)
        for (std::uint32_t v : faces_[f]) allowed_[v] = 1;
  }

  static int edge_index(int a, int b) {
    int e = 0;
    while (cube_edge_corners(e) != std::array<int, 2>{std::min(a, b), std::max(a, b)}) ++e;
    return e;
  }

  const TetMesh& mesh_;
  const BoundaryGraph& graph_;
  const std::vector<Triangle>& faces_;
  std::vector<std::array<std::uint32_t, 3>> neighbours_;
  CubeMap& map_;
  std::vector<char> allowed_, on_curve_;
};

// The twelve curves: each cube face in turn goes first (the loops a shape allows depend on
// which), the first that works is kept.
void trace_curves(const TetMesh& mesh, const BoundaryGraph& graph,
                  const std::vector<Triangle>& faces, CubeMap& map) {
  std::string first_reason;
  for (int first : {4, 0, 2, 5, 1, 3}) {
    for (auto& curve : map.curves) curve.clear();
    try {
      CurveTracer(mesh, graph, faces, map).trace(first);
      return;
    } catch (const InputError& e) {
      if (first_reason.empty()) first_reason = e.what();
    }
  }
  throw InputError(
      "the curves between the corners cannot cut the boundary as the cube's edges cut its "
      "surface, whichever face goes first (with the bottom first: " +
      first_reason + "); give the corners (are they mirrored?), or use smaller tets");
}

// Corners from each frame in turn, until the curves between them can be traced.
void find_corners_and_curves(const TetMesh& mesh, const BoundaryGraph& graph,
                             const std::vector<Triangle>& faces, CubeMap& map) {
  std::string first_error;
  for (const Frame& frame : corner_frames(mesh, graph)) {
    try {
      map.corners = find_corners(mesh, graph, frame);
      trace_curves(mesh, graph, faces, map);
      return;
    } catch (const InputError& e) {
      if (first_error.empty()) first_error = e.what();
    }
  }
  throw InputError(first_error +
                   " (corners from the boxes along the axes and the principal axes, each also "
                   "turned by 45° about each axis, all tried)");
}

// Cube face f = 2·axis + side: the mask of its four edges.
int face_edge_mask(int face) {
  const int axis = face / 2, side = face % 2;
  int mask = 0;
  for (int e = 0; e < 12; ++e) {
    const auto [k0, k1] = cube_edge_corners(e);
    if (e / 4 != axis && corner_bit(k0, axis) == side && corner_bit(k1, axis) == side)
      mask |= 1 << e;
  }
  return mask;
}

// The boundary faces of each cube face: the curves cut the boundary into six patches, each
// bounded by one cube face's four curves.
std::array<std::vector<std::uint32_t>, 6> split_patches(const std::vector<Triangle>& faces,
                                                        const CubeMap& map) {
  std::unordered_map<std::uint64_t, int> curve_of_edge;
  for (int e = 0; e < 12; ++e)
    for (std::size_t i = 1; i < map.curves[e].size(); ++i)
      curve_of_edge[edge_key(map.curves[e][i - 1], map.curves[e][i])] = e;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> sides;
  sides.reserve(faces.size() * 3);
  for (std::uint32_t f = 0; f < faces.size(); ++f)
    for (int i = 0; i < 3; ++i) sides.emplace_back(edge_key(faces[f][i], faces[f][(i + 1) % 3]), f);
  std::sort(sides.begin(), sides.end());
  detail::DisjointSets regions(faces.size());
  std::vector<int> bounding(faces.size(), 0);  // curves on each face's sides
  for (std::size_t i = 0; i + 1 < sides.size(); ++i) {
    if (sides[i].first != sides[i + 1].first) continue;
    const auto curve = curve_of_edge.find(sides[i].first);
    if (curve == curve_of_edge.end()) {
      regions.unite(sides[i].second, sides[i + 1].second);
    } else {
      bounding[sides[i].second] |= 1 << curve->second;
      bounding[sides[i + 1].second] |= 1 << curve->second;
    }
  }
  std::unordered_map<std::uint32_t, int> mask_of_region;
  for (std::uint32_t f = 0; f < faces.size(); ++f) mask_of_region[regions.find(f)] |= bounding[f];
  if (mask_of_region.size() != 6)
    throw InputError("the twelve curves between the corners cut the boundary into " +
                     std::to_string(mask_of_region.size()) +
                     " patches, not the cube's six; give corners");
  std::unordered_map<std::uint32_t, int> face_of_region;
  int faces_seen = 0;
  for (const auto& [root, mask] : mask_of_region)
    for (int face = 0; face < 6; ++face)
      if (mask == face_edge_mask(face)) {
        face_of_region[root] = face;
        faces_seen |= 1 << face;
      }
  if (face_of_region.size() != 6 || faces_seen != 63)
    throw InputError(
        "the curves between the corners do not bound the six patches as the cube's edges bound "
        "its faces (the curves cross the corners' order); give corners");
  std::array<std::vector<std::uint32_t>, 6> patches;
  for (std::uint32_t f = 0; f < faces.size(); ++f)
    patches[face_of_region[regions.find(f)]].push_back(f);
  return patches;
}

// One patch onto its cube face by mean-value coordinates: Σ_j w_ij (f_j − f_i) = 0 at each
// vertex not on a curve, for the face's two free coordinates.
void map_patch(const TetMesh& mesh, const std::vector<Triangle>& faces,
               const std::vector<std::uint32_t>& patch, int face, const std::vector<char>& fixed,
               std::vector<Uvw>& uvw) {
  const int axis = face / 2, b = (axis + 1) % 3, c = (axis + 2) % 3;
  std::vector<double> values(2 * uvw.size());
  for (std::size_t v = 0; v < uvw.size(); ++v)
    values[2 * v] = uvw[v][b], values[2 * v + 1] = uvw[v][c];
  detail::solve_dirichlet(detail::mean_value_operator(mesh.points, faces, patch),
                          detail::Symmetry::General, fixed, 2, values,
                          "the mean-value system of cube face " + std::to_string(face) +
                              " is singular (degenerate boundary triangles?)");
  for (std::uint32_t f : patch)
    for (std::uint32_t v : faces[f])
      if (!fixed[v]) {
        Uvw& p = uvw[v];
        p[axis] = face % 2;
        p[b] = values[2 * v];
        p[c] = values[2 * v + 1];
      }
}

// A patch's image share below which its map counts as crowded (see relax_patch). Relaxing is
// not free: it evens out areas at the shapes' cost, and a 12 mm cube's 3 × 3 × 9 mm arm at
// 2·10⁻⁴ fitted its boundary 0.41 mm off relaxed against 0.26 with Floater's map
// (SolidSpline.SqueezedArmKeepsItsSectionAndSurface). Below 10⁻⁵ rounding starts to tell.
constexpr double kCrowded = 1e-5;

// The patch's mean-value map relaxed where it crowds. A convex-combination map squeezes a
// protrusion of its patch (a condyle on a femur's end, a triceratops's horn) exponentially in
// its length: the lower femur's stand-in had 202 points within 10⁻⁶ of each other on one face,
// 5 triangles flat to rounding, another face's triangles down to 3·10⁻¹⁴ of their share; the
// harmonic interior over such a face inverts its tets by the hundred. Where a triangle's image
// holds under kCrowded of its share of the face (its area over the patch's), or is turned or
// flat, the patch's free points move by Newton steps on the foldover-free energy in the plane
// (untangle.hpp; the volume term at θ = 0.5, so the areas even out): every image positive.
// The models of docs/benchmarks.md §22b keep 0.008 and more, so their maps stay Floater's.
// Returns whether the patch moved.
bool relax_patch(const TetMesh& mesh, const std::vector<Triangle>& faces,
                 const std::vector<std::uint32_t>& patch, int face, const std::vector<char>& fixed,
                 std::vector<Uvw>& uvw, const std::function<void(double)>& report) {
  const int axis = face / 2, b = (axis + 1) % 3, c = (axis + 2) % 3;
  const double mirror = face % 2 ? 1 : -1;  // so that the outward side turns counter-clockwise
  std::vector<std::array<double, 2>> uv(mesh.points.size(), {0, 0});
  std::vector<char> movable(mesh.points.size(), 0);
  std::vector<Triangle> triangles;
  std::vector<double> areas;  // twice each triangle's, in space
  triangles.reserve(patch.size());
  areas.reserve(patch.size());
  double area = 0;
  for (std::uint32_t f : patch) {
    const Triangle& t = faces[f];
    triangles.push_back(t);
    areas.push_back(
        norm(cross(mesh.points[t[1]] - mesh.points[t[0]], mesh.points[t[2]] - mesh.points[t[0]])));
    area += areas.back();
    for (std::uint32_t v : t) {
      uv[v] = {uvw[v][b], mirror * uvw[v][c]};
      movable[v] = !fixed[v];
    }
  }
  bool crowded = false;
  for (std::size_t i = 0; i < triangles.size() && !crowded; ++i) {
    const Triangle& t = triangles[i];
    const double image = 0.5 * ((uv[t[1]][0] - uv[t[0]][0]) * (uv[t[2]][1] - uv[t[0]][1]) -
                                (uv[t[1]][1] - uv[t[0]][1]) * (uv[t[2]][0] - uv[t[0]][0]));
    crowded = detail::orientation_2(uv[t[0]], uv[t[1]], uv[t[2]]) <= 0 ||
              image < kCrowded * areas[i] / area;  // the face's area is 1
  }
  if (!crowded) return false;
  detail::untangle_triangles(mesh.points, triangles, movable, 0.5, uv, report);
  for (std::size_t v = 0; v < movable.size(); ++v)
    if (movable[v]) uvw[v][b] = uv[v][0], uvw[v][c] = mirror * uv[v][1];
  return true;
}

// The interior by the P1 harmonic map, for the three coordinates.
void map_interior(const TetMesh& mesh, const std::vector<char>& fixed, CubeMap& map) {
  std::vector<double> values(mesh.points.size() * 3);
  for (std::size_t v = 0; v < mesh.points.size(); ++v)
    for (int a = 0; a < 3; ++a) values[3 * v + a] = map.uvw[v][a];  // NaN where not fixed
  map.interior_points = detail::harmonic_extension(mesh, fixed, 3, values);
  for (std::size_t v = 0; v < mesh.points.size(); ++v)
    for (int a = 0; a < 3; ++a) map.uvw[v][a] = values[3 * v + a];
}

// Tets whose image is inverted or flat (exact orientation); `inverted` counts the inverted.
std::vector<std::uint32_t> bad_tets(const TetMesh& mesh, const CubeMap& map,
                                    std::uint64_t* inverted = nullptr) {
  auto at = [&](std::uint32_t v) { return Vec3{map.uvw[v][0], map.uvw[v][1], map.uvw[v][2]}; };
  std::vector<std::uint32_t> bad;
  for (std::uint32_t t = 0; t < mesh.tets.size(); ++t) {
    const Tet& c = mesh.tets[t];
    const int sign = detail::orientation_3(at(c[0]), at(c[1]), at(c[2]), at(c[3]));
    if (sign <= 0) bad.push_back(t);
    if (inverted) *inverted += sign < 0;
  }
  return bad;
}

// `region` grown by `rings` rings of tets (all: until it stops growing), never into `fixed`.
void grow_region(const TetMesh& mesh, const std::vector<char>& fixed, int rings,
                 std::vector<char>& region) {
  for (int r = 0; r < rings; ++r) {
    std::vector<char> next = region;
    for (const Tet& t : mesh.tets)
      if (region[t[0]] || region[t[1]] || region[t[2]] || region[t[3]])
        for (std::uint32_t v : t) next[v] = !fixed[v];
    if (next == region) return;
    region.swap(next);
  }
}

// The points of `tets` not in `fixed`.
std::vector<char> free_corners(const TetMesh& mesh, const std::vector<char>& fixed,
                               const std::vector<std::uint32_t>& tets) {
  std::vector<char> corners(mesh.points.size(), 0);
  for (std::uint32_t t : tets)
    for (std::uint32_t v : mesh.tets[t]) corners[v] = !fixed[v];
  return corners;
}

// The harmonic interior's inverted and flat tets untangled (untangle.hpp): the interior points
// within two rings of them move, the rest of the map stays harmonic. Where that leaves tets
// inverted, the whole interior moves. Tets whose corners are all on the boundary cannot
// move: with_chords_split() leaves none that need to.
void untangle_interior(const TetMesh& mesh, const std::vector<char>& fixed, CubeMap& map,
                       Progress* progress) {
  std::vector<std::uint32_t> bad = bad_tets(mesh, map, &map.harmonic_inverted_tets);
  if (bad.empty()) return;
  std::vector<char> movable = free_corners(mesh, fixed, bad);
  const std::size_t harmonic_bad = bad.size();
  const std::vector<Uvw> harmonic = map.uvw;
  grow_region(mesh, fixed, 2, movable);
  constexpr int kAttempts = 2;
  for (int attempt = 0; attempt < kAttempts; ++attempt) {
    detail::untangle(mesh, movable, map.uvw, [&](double done) {
      detail::report_or_cancel(progress, 0.3 + 0.6 * (attempt + done) / kAttempts);
    });
    bad = bad_tets(mesh, map);
    if (bad.empty()) break;
    grow_region(mesh, fixed, std::numeric_limits<int>::max(), movable);
  }
  // Where the mesh leaves no fold-free map (a limb's tets all on its boundary), the schedule
  // of ε can stop with more tets inverted than it began with: then the harmonic map stays.
  if (bad.size() > harmonic_bad) {
    map.uvw = harmonic;
    movable.assign(movable.size(), 0);
  }
  map.untangled_points = static_cast<std::uint64_t>(std::count(movable.begin(), movable.end(), 1));
}

void count_flips(const TetMesh& mesh, const std::vector<Triangle>& faces,
                 const std::array<std::vector<std::uint32_t>, 6>& patches, CubeMap& map) {
  for (int face = 0; face < 6; ++face) {
    const int axis = face / 2, b = (axis + 1) % 3, c = (axis + 2) % 3;
    const int outward = face % 2 ? 1 : -1;  // (b, c) is counter-clockwise seen from +axis
    for (std::uint32_t f : patches[face]) {
      std::array<std::array<double, 2>, 3> q;
      for (int i = 0; i < 3; ++i) q[i] = {map.uvw[faces[f][i]][b], map.uvw[faces[f][i]][c]};
      if (detail::orientation_2(q[0], q[1], q[2]) != outward) ++map.flipped_boundary_faces;
    }
  }
  map.inverted_tets = 0;
  map.flat_tets = bad_tets(mesh, map, &map.inverted_tets).size();
  map.flat_tets -= map.inverted_tets;
}

}  // namespace

std::array<int, 2> cube_edge_corners(int edge) {
  const int axis = edge / 4, rest = edge % 4;
  const int first = ((rest & 1) << ((axis + 1) % 3)) | ((rest >> 1) << ((axis + 2) % 3));
  return {first, first | (1 << axis)};
}

std::vector<std::uint32_t> folded_tets(const TetMesh& mesh, const CubeMap& map) {
  return bad_tets(mesh, map);
}

CubeMap with_folds_opened(const TetMesh& mesh, CubeMap map, Progress* progress) {
  std::vector<std::uint32_t> bad = bad_tets(mesh, map);
  if (bad.empty()) return map;
  detail::begin_stage(progress, "opening the last folds");
  std::vector<char> fixed(mesh.points.size(), 0);
  for (const Triangle& f : tet_boundary(mesh).triangles)
    for (std::uint32_t v : f) fixed[v] = 1;
  detail::FoldoverSchedule longer;
  longer.max_rounds = kOpeningRounds;
  for (std::size_t i = 0; i < kOpeningRings.size() && !bad.empty(); ++i) {
    std::vector<char> region = free_corners(mesh, fixed, bad);
    grow_region(mesh, fixed, kOpeningRings[i], region);
    std::vector<Uvw> trial = map.uvw;
    const double from = double(i) / kOpeningRings.size(), to = double(i + 1) / kOpeningRings.size();
    detail::untangle(
        mesh, region, trial,
        [&](double done) { detail::report_or_cancel(progress, from + (to - from) * done); },
        longer);
    std::swap(map.uvw, trial);
    std::vector<std::uint32_t> left = bad_tets(mesh, map);
    if (left.size() >= bad.size()) {  // no better: its points stay where they were
      std::swap(map.uvw, trial);
      continue;
    }
    bad.swap(left);
    map.opened_points += static_cast<std::uint64_t>(std::count(region.begin(), region.end(), 1));
  }
  map.inverted_tets = 0;
  map.flat_tets = bad_tets(mesh, map, &map.inverted_tets).size() - map.inverted_tets;
  detail::report_or_cancel(progress, 1.0);
  return map;
}

CubeMap map_to_cube(const TetMesh& mesh, const CubeMapOptions& options) {
  detail::begin_stage(options.progress, "cube map");
  const TetMeshReport report = check_tet_mesh(mesh);
  if (const auto problem = ball_problem(report)) throw InputError(*problem);
  if (report.negative_tets > 0)
    throw InputError(
        "every tet is negative (the other orientation convention); turn them "
        "with with_positive_tets() first");
  const std::vector<Triangle> faces = tet_boundary(mesh).triangles;
  const BoundaryGraph graph = boundary_graph(mesh.points.size(), faces);

  CubeMap map;
  map.uvw.assign(mesh.points.size(), Uvw{kNaN, kNaN, kNaN});
  map.tets = mesh.tets.size();
  map.boundary_faces = faces.size();
  if (options.corners) check_given_corners(*options.corners, graph, mesh.points.size());
  if (options.corners) {
    map.corners = *options.corners;
    trace_curves(mesh, graph, faces, map);
  } else {
    find_corners_and_curves(mesh, graph, faces, map);
  }
  const auto patches = split_patches(faces, map);
  detail::report_or_cancel(options.progress, 0.1);

  std::vector<char> fixed(mesh.points.size(), 0);
  for (const auto& curve : map.curves)
    for (std::uint32_t v : curve) fixed[v] = 1;
  for (int face = 0; face < 6; ++face) {
    map.patch_faces[face] = patches[face].size();
    map_patch(mesh, faces, patches[face], face, fixed, map.uvw);
    map.relaxed_patches +=
        relax_patch(mesh, faces, patches[face], face, fixed, map.uvw, [&](double done) {
          detail::report_or_cancel(options.progress, 0.1 + 0.2 * (face + done) / 6);
        });
  }
  detail::report_or_cancel(options.progress, 0.3);
  for (const Triangle& f : faces)
    for (std::uint32_t v : f) fixed[v] = 1;
  map_interior(mesh, fixed, map);
  untangle_interior(mesh, fixed, map, options.progress);
  count_flips(mesh, faces, patches, map);
  if (2 * map.flipped_boundary_faces > map.boundary_faces)
    throw InputError(std::to_string(map.flipped_boundary_faces) + " of the " +
                     std::to_string(map.boundary_faces) +
                     " boundary faces land reversed on the cube: the corners are mirrored (corner "
                     "k goes to (k & 1, k >> 1 & 1, k >> 2 & 1))");
  detail::report_or_cancel(options.progress, 1.0);
  return map;
}

}  // namespace tpmsfill
