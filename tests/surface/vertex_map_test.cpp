// Seed 004's vertex map: the slab's mesh carried onto a surface vertex by vertex.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <tpmsfill/check.hpp>
#include <tpmsfill/conformal.hpp>
#include <tpmsfill/error.hpp>
#include <tpmsfill/fill.hpp>
#include <tpmsfill/surface/parameterize.hpp>

#include "test_util.hpp"

using namespace tpmsfill;
using namespace tpmsfill::test;

TEST(VertexMap, AFlatPlateMapsTheSlabOntoItself) {
  const SurfaceParameterization layout =
      parameterize_surface(make_height_field(8, 20, [](double, double) { return 0.0; }));
  ConformalOptions layer;
  layer.height = 2;
  const TriangleSoup slab = make_box({0, 0, 0}, {20, 20, 2});
  VertexMapReport r;
  const TriangleSoup mapped = map_slab_vertices(slab, layout, {20, 20}, layer, {}, &r);
  EXPECT_EQ(r.split_edges, 0u);  // nothing bends: no chord strays
  EXPECT_EQ(r.clamped, 0u);
  // The plate's layout is a rotation of (x, y)/20: the box comes back as a box.
  const Box3 b = bounding_box(mapped);
  EXPECT_NEAR(b.min.x, 0, 1e-9);
  EXPECT_NEAR(b.max.x, 20, 1e-9);
  EXPECT_NEAR(b.min.z, 0, 1e-9);
  EXPECT_NEAR(b.max.z, 2, 1e-9);
  const MeshCheck c = check_mesh(mapped);
  EXPECT_TRUE(c.valid()) << testing::PrintToString(c.problems());
  ASSERT_TRUE(c.volume.has_value());
  EXPECT_NEAR(*c.volume, 800, 1e-6);
}

TEST(VertexMap, ALatticeOnASphericalCapIsValidAndFollowsTheSurface) {
  const double R = 20;
  const TriangleSoup cap = make_spherical_cap(R, 0.6, 16, 48);
  const SurfaceParameterization layout =
      parameterize_surface(cap, {.method = LayoutMethod::Square});
  ConformalOptions layer;
  layer.height = 2;
  FillOptions f;
  f.design.cell = {4, 4, 4};
  f.grid.voxel_size = 0.25;
  const std::array<double, 2> lengths = slab_lengths(layout, f.design, layer);
  const TriangleSoup slab =
      fill(make_box({0, 0, 0}, {lengths[0], lengths[1], layer.height}), f).mesh;
  VertexMapReport r;
  const TriangleSoup mapped = map_slab_vertices(slab, layout, lengths, layer, {}, &r);
  EXPECT_GT(r.split_edges, 0u);  // the slab's long flat faces are bent onto the cap
  EXPECT_LE(r.chord_error, layer.height / 50 + 1e-12);
  const MeshCheck c = check_mesh(mapped);
  EXPECT_TRUE(c.valid()) << testing::PrintToString(c.problems());
  // Lifted onto a sphere's polyhedron (chords inside it) and offset by 0..2 mm along the normals.
  for (const Vec3& p : mapped.points) {
    ASSERT_GE(norm(p), R * std::cos(std::numbers::pi / 48) - 0.05);
    ASSERT_LE(norm(p), R + 2 + 1e-6);
  }
  // Inward: mirrored, so reversed to stay outward.
  layer.side = SurfaceSide::In;
  const MeshCheck in = check_mesh(map_slab_vertices(slab, layout, lengths, layer));
  EXPECT_TRUE(in.valid()) << testing::PrintToString(in.problems());
  // A free layout does not fill the slab's box: refused.
  EXPECT_THROW(map_slab_vertices(slab, parameterize_surface(cap, {.method = LayoutMethod::Free}),
                                 lengths, layer),
               InputError);
}

TEST(VertexMap, RefusesATube) {
  const TriangleSoup tube = make_open_cylinder(5, 6, 16, 2);
  const SurfaceParameterization layout = parameterize_surface(tube);
  ConformalOptions layer;
  layer.height = 1;
  EXPECT_THROW(map_slab_vertices(make_box({0, 0, 0}, {30, 6, 1}), layout, {30, 6}, layer),
               InputError);
}

TEST(VertexMap, ConformalFillOffersItAndRefusesWhatItCannotDo) {
  ConformalJobOptions o;
  o.map = SlabMap::Vertex;
  o.layer.height = 2;
  o.design.cell = {4, 4, 4};
  o.grid.voxel_size = 0.25;
  const TriangleSoup surface = make_spherical_cap(20, 0.6, 16, 48);
  const ConformalResult r = conformal_fill(surface, o);
  EXPECT_TRUE(r.fill.validation.valid());
  EXPECT_TRUE(check_mesh(r.mesh).valid());
  EXPECT_EQ(r.report.map, SlabMap::Vertex);
  EXPECT_GT(r.report.vertex_map.split_edges, 0u);
  // Heights measured through the closest-point map: the lift lies on the surface's chords and
  // the offset runs along interpolated normals, so within a fraction of a millimetre of 0..H.
  EXPECT_GT(r.report.height_min, -0.1);
  EXPECT_LT(r.report.height_max, 2.1);
  EXPECT_GT(r.report.height_max, 1.9);
  // Skins are made in the flat slab and lifted with it: a channel closed on both sides, valid,
  // whose solid grows by the void the skins fill: about half of their volume (the gyroid at
  // C = 0 is half solid; two skins of area × 0.3 mm, the cap's area 2πR²(1 − cos 0.6) ≈ 438
  // mm²), certainly more than a quarter and less than all of it.
  const double open = *check_mesh(r.mesh).volume;
  o.layer.skin_surface = 0.3, o.layer.skin_top = 0.3;
  const ConformalResult channel = conformal_fill(surface, o);
  const MeshCheck closed = check_mesh(channel.mesh);
  EXPECT_TRUE(closed.valid()) << testing::PrintToString(closed.problems());
  const double area = 2 * std::numbers::pi * 400 * (1 - std::cos(0.6));
  EXPECT_GT(*closed.volume - open, 0.25 * 2 * 0.3 * area);
  EXPECT_LT(*closed.volume - open, 2 * 0.3 * area);
  EXPECT_EQ(channel.report.map, SlabMap::Vertex);
  EXPECT_GT(channel.report.height_min, -0.1);
  EXPECT_LT(channel.report.height_max, 2.1);
  EXPECT_EQ(slab_map_from_name("vertex"), SlabMap::Vertex);
  EXPECT_THROW(slab_map_from_name("normal"), InputError);
}
