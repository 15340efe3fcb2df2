// The as-rigid-as-possible layout (arap.hpp), with Eigen.
#define EIGEN_NO_DEBUG 1  // Eigen's checks abort() rather than throw: leave them out
#include "surface/internal/arap.hpp"

#include <algorithm>
#include <cmath>

#include "tpmsfill/error.hpp"

#if defined(CGAL_EIGEN3_ENABLED)
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#endif

namespace tpmsfill::detail {

#if defined(CGAL_EIGEN3_ENABLED)

namespace {

// A triangle in its own plane, (0,0), (|e1|,0), (x2,y2): per corner k the edge opposite it,
// x_{k+1} − x_{k+2}, and that edge's cotangent weight (clamped: a sliver's huge weight would
// swamp the system, and negative weights of obtuse corners would leave it indefinite).
struct FlatTriangle {
  std::array<std::array<double, 2>, 3> edge;
  std::array<double, 3> weight;
};

FlatTriangle flatten(Vec3 a, Vec3 b, Vec3 c) {
  const Vec3 e1 = b - a, e2 = c - a;
  const double l1 = norm(e1);
  FlatTriangle f;
  std::array<std::array<double, 2>, 3> x;
  x[0] = {0, 0};
  x[1] = {l1, 0};
  x[2] = l1 > 0 ? std::array<double, 2>{dot(e2, e1) / l1, norm(cross(e1, e2)) / l1}
                : std::array<double, 2>{0, 0};
  for (int k = 0; k < 3; ++k) {
    const auto& p = x[k];
    const auto& q = x[(k + 1) % 3];
    const auto& r = x[(k + 2) % 3];
    const double ux = q[0] - p[0], uy = q[1] - p[1], vx = r[0] - p[0], vy = r[1] - p[1];
    const double area2 = std::fabs(ux * vy - uy * vx);
    const double cot = area2 > 0 ? (ux * vx + uy * vy) / area2 : 1e3;
    f.weight[k] = std::clamp(cot, 1e-3, 1e3);
    f.edge[k] = {q[0] - r[0], q[1] - r[1]};
  }
  return f;
}

}  // namespace

ArapLayout arap_layout(const TriangleSoup& mesh, const std::vector<std::array<double, 2>>& start,
                       const std::vector<std::pair<std::uint32_t, std::uint32_t>>& seam,
                       int iterations) {
  const std::size_t n = mesh.points.size();
  // Unknowns: one per point that is not a seam copy, then the period (a tube's).
  std::vector<std::uint32_t> rep(n);
  std::vector<double> shift(n, 0.0);  // how many periods a point sits from its unknown
  for (std::uint32_t i = 0; i < n; ++i) rep[i] = i;
  for (const auto& [original, copy] : seam) rep[copy] = original, shift[copy] = 1;
  std::vector<std::int64_t> column(n, -1);
  std::int64_t unknowns = 0;
  for (std::uint32_t i = 0; i < n; ++i)
    if (rep[i] == i) column[i] = unknowns++;
  const bool tube = !seam.empty();
  const std::int64_t period = tube ? unknowns++ : -1;

  std::vector<FlatTriangle> flat(mesh.triangles.size());
  for (std::size_t t = 0; t < flat.size(); ++t) {
    const Triangle& tri = mesh.triangles[t];
    flat[t] = flatten(mesh.points[tri[0]], mesh.points[tri[1]], mesh.points[tri[2]]);
  }
  // Each edge (i, j) of a triangle adds w |X_i − X_j + (s_i − s_j) P − r|², r its rotated
  // flat edge: the rows a = e_i − e_j + (s_i − s_j) e_P.
  using Entry = Eigen::Triplet<double>;
  std::vector<Entry> entries;
  auto edge_row = [&](std::uint32_t i, std::uint32_t j, auto&& emit) {
    emit(column[rep[i]], 1.0);
    emit(column[rep[j]], -1.0);
    if (tube && shift[i] != shift[j]) emit(period, shift[i] - shift[j]);
  };
  double total_weight = 0;
  for (std::size_t t = 0; t < flat.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t i = mesh.triangles[t][(k + 1) % 3], j = mesh.triangles[t][(k + 2) % 3];
      const double w = flat[t].weight[k];
      total_weight += w;
      std::array<std::pair<std::int64_t, double>, 3> a{};
      int m = 0;
      edge_row(i, j, [&](std::int64_t c, double v) { a[m++] = {c, v}; });
      for (int p = 0; p < m; ++p)
        for (int q = 0; q < m; ++q)
          entries.emplace_back(a[p].first, a[q].first, w * a[p].second * a[q].second);
    }
  // The energy does not see translations: a soft anchor holds the first point where it was.
  const double anchor = total_weight / double(std::max<std::size_t>(1, flat.size()));
  entries.emplace_back(0, 0, anchor);
  Eigen::SparseMatrix<double> A(unknowns, unknowns);
  A.setFromTriplets(entries.begin(), entries.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(A);
  if (solver.info() != Eigen::Success)
    throw InputError(
        "the surface cannot be laid out freely: its system is singular (degenerate "
        "triangles?)");

  ArapLayout out;
  out.xy = start;
  if (tube) {
    // The start's period: the mean step from each original to its copy.
    for (const auto& [original, copy] : seam)
      for (int a = 0; a < 2; ++a) out.period[a] += start[copy][a] - start[original][a];
    for (int a = 0; a < 2; ++a) out.period[a] /= double(seam.size());
  }
  const std::array<double, 2> pinned = start[0];
  double previous = -1;
  std::vector<std::array<double, 4>> rotation(flat.size());
  for (int round = 0; round < iterations; ++round) {
    // Local: per triangle the rotation R maximising tr(Rᵀ S), S = Σ w (u_i − u_j)(x_i − x_j)ᵀ.
    double energy = 0;
    for (std::size_t t = 0; t < flat.size(); ++t) {
      const Triangle& tri = mesh.triangles[t];
      double s00 = 0, s01 = 0, s10 = 0, s11 = 0;
      for (int k = 0; k < 3; ++k) {
        const int i = (k + 1) % 3, j = (k + 2) % 3;
        const double w = flat[t].weight[k];
        const double du = out.xy[tri[i]][0] - out.xy[tri[j]][0],
                     dv = out.xy[tri[i]][1] - out.xy[tri[j]][1];
        const auto [dx, dy] = flat[t].edge[k];
        s00 += w * du * dx, s01 += w * du * dy, s10 += w * dv * dx, s11 += w * dv * dy;
      }
      const double angle = std::atan2(s10 - s01, s00 + s11);
      const double c = std::cos(angle), s = std::sin(angle);
      rotation[t] = {c, -s, s, c};
      for (int k = 0; k < 3; ++k) {
        const int i = (k + 1) % 3, j = (k + 2) % 3;
        const auto [dx, dy] = flat[t].edge[k];
        const double ru = c * dx - s * dy, rv = s * dx + c * dy;
        const double du = out.xy[tri[i]][0] - out.xy[tri[j]][0] - ru,
                     dv = out.xy[tri[i]][1] - out.xy[tri[j]][1] - rv;
        energy += flat[t].weight[k] * (du * du + dv * dv);
      }
    }
    if (previous >= 0 && std::fabs(previous - energy) <= 1e-6 * previous) break;
    previous = energy;
    // Global: the points that best carry every rotated edge, both coordinates at once.
    Eigen::MatrixXd b = Eigen::MatrixXd::Zero(unknowns, 2);
    for (std::size_t t = 0; t < flat.size(); ++t) {
      const Triangle& tri = mesh.triangles[t];
      const auto& R = rotation[t];
      for (int k = 0; k < 3; ++k) {
        const int i = (k + 1) % 3, j = (k + 2) % 3;
        const double w = flat[t].weight[k];
        const auto [dx, dy] = flat[t].edge[k];
        const double ru = R[0] * dx + R[1] * dy, rv = R[2] * dx + R[3] * dy;
        edge_row(tri[i], tri[j], [&](std::int64_t c, double v) {
          b(c, 0) += w * v * ru;
          b(c, 1) += w * v * rv;
        });
      }
    }
    b(0, 0) += anchor * pinned[0];
    b(0, 1) += anchor * pinned[1];
    const Eigen::MatrixXd x = solver.solve(b);
    if (solver.info() != Eigen::Success || !x.allFinite())
      throw InputError("the surface cannot be laid out freely: its solve failed");
    ArapLayout target = out;
    if (tube) target.period = {x(period, 0), x(period, 1)};
    for (std::uint32_t i = 0; i < n; ++i)
      for (int a = 0; a < 2; ++a)
        target.xy[i][a] = x(column[rep[i]], a) + shift[i] * target.period[a];
    // No triangle may turn over: the step goes as far towards the solve as keeps every one
    // the right way round (halved up to 10 times: the start has none turned, so short steps do).
    bool taken = false;
    for (double step = 1; step >= 1.0 / 1024 && !taken; step /= 2) {
      ArapLayout next = out;
      for (std::uint32_t i = 0; i < n; ++i)
        for (int a = 0; a < 2; ++a) next.xy[i][a] += step * (target.xy[i][a] - out.xy[i][a]);
      for (int a = 0; a < 2; ++a) next.period[a] += step * (target.period[a] - out.period[a]);
      if (std::all_of(mesh.triangles.begin(), mesh.triangles.end(), [&](const Triangle& t) {
            const auto &a = next.xy[t[0]], &b = next.xy[t[1]], &c = next.xy[t[2]];
            return (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]) > 0;
          })) {
        next.iterations = round + 1;
        next.short_steps += step < 1;
        out = std::move(next);
        taken = true;
      }
    }
    if (!taken) break;
  }
  return out;
}

#else

ArapLayout arap_layout(const TriangleSoup&, const std::vector<std::array<double, 2>>&,
                       const std::vector<std::pair<std::uint32_t, std::uint32_t>>&, int) {
  throw InputError("tpmsfill was built without Eigen: surfaces cannot be laid out freely");
}

#endif

}  // namespace tpmsfill::detail
