// Stage "validate"'s self-intersection test for triangles that share a corner, checked against
// an independent oracle: CGAL's exact triangle-triangle intersection (Epeck, exact
// constructions), which meets the two beyond the shared corner exactly when
// PMP::self_intersections counts the pair. Small integer coordinates make coplanar, touching
// and collinear configurations common, where a shortcut would go wrong.
#include <gtest/gtest.h>

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/intersections.h>

#include <array>
#include <cstdint>
#include <random>
#include <tpmsfill/mesh/validate.hpp>
#include <variant>
#include <vector>

using namespace tpmsfill;

namespace {

using Exact = CGAL::Exact_predicates_exact_constructions_kernel;

Exact::Point_3 exact(const Vec3& p) {
  return {p.x, p.y, p.z};
}

/// Do triangles (v, a, b) and (v, c, d) meet anywhere but at v?
bool meet_beyond_corner(const Vec3& v, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const Exact::Triangle_3 h(exact(v), exact(a), exact(b)), g(exact(v), exact(c), exact(d));
  const auto meet = CGAL::intersection(h, g);
  if (!meet) return false;  // cannot happen: both hold v
  const auto* point = boost::get<Exact::Point_3>(&*meet);
  return point == nullptr || *point != exact(v);
}

bool degenerate(const Vec3& p, const Vec3& q, const Vec3& r) {
  return CGAL::collinear(exact(p), exact(q), exact(r));
}

/// Pairs of triangles sharing corner 0, each pair 10 apart along x (in its own cell of a
/// spacing-10 grid), corners drawn from {-2..2}^3.
struct CornerPairs {
  TriangleSoup soup;
  std::vector<std::array<std::uint32_t, 2>> meeting;  ///< what the oracle says, sorted
};

CornerPairs random_corner_pairs(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> coordinate(-2, 2);
  auto draw = [&] {
    return Vec3{double(coordinate(rng)), double(coordinate(rng)), double(coordinate(rng))};
  };
  CornerPairs out;
  while (static_cast<int>(out.soup.triangles.size()) < 2 * count) {
    const Vec3 v = draw(), a = draw(), b = draw(), c = draw(), d = draw();
    if (degenerate(v, a, b) || degenerate(v, c, d)) continue;
    // Sharing exactly one corner: a, b, c, d distinct points (a repeated position would be a
    // second shared corner by position, not by index).
    if (a == c || a == d || b == c || b == d) continue;
    const double x = 10.0 * static_cast<double>(out.soup.triangles.size() / 2);
    const Vec3 shift{x, 0, 0};
    const auto n = static_cast<std::uint32_t>(out.soup.points.size());
    out.soup.points.insert(out.soup.points.end(),
                           {v + shift, a + shift, b + shift, c + shift, d + shift});
    const auto t = static_cast<std::uint32_t>(out.soup.triangles.size());
    out.soup.triangles.push_back({n, n + 1, n + 2});
    out.soup.triangles.push_back({n, n + 3, n + 4});
    if (meet_beyond_corner(v, a, b, c, d)) out.meeting.push_back({t, t + 1});
  }
  return out;
}

}  // namespace

TEST(SelfIntersections, CornerSharingPairsMatchExactIntersection) {
  const int count = 20000;
  const CornerPairs pairs = random_corner_pairs(count, 16);
  // Enough of both answers to mean something.
  ASSERT_GT(pairs.meeting.size(), 1000u);
  ASSERT_LT(pairs.meeting.size(), static_cast<std::size_t>(count) - 1000u);

  ValidateOptions general;
  general.max_examples = 2 * count;
  ValidateOptions by_cells = general;
  Grid g;
  g.origin = {-5, -5, -5};
  g.spacing = 10;
  g.dims = {count + 1, 2, 2};
  by_cells.cell_grid = g;
  for (const ValidateOptions& o : {general, by_cells}) {
    const MeshValidity r = validate_mesh(pairs.soup, o);
    EXPECT_EQ(r.searched_by_cells, o.cell_grid.has_value());
    EXPECT_EQ(r.degenerate_triangles, 0u);
    EXPECT_EQ(r.self_intersecting_pairs, pairs.meeting.size());
    EXPECT_EQ(r.self_intersection_examples, pairs.meeting);
  }
}
