// Review: every layer a design can produce, checked against the model and the voxel.
#include "lattice/review.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "lattice/internal/box_samples.hpp"
#include "lattice/internal/region_distance.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/field.hpp"
#include "tpmsfill/sampling/voxel.hpp"

namespace tpmsfill {
namespace {

std::string num(double v) {
  char s[32];
  std::snprintf(s, sizeof s, "%.3g", v);
  return s;
}

std::string mm(double v) {
  return num(v) + " mm";
}

std::string percent(double fraction) {
  char s[32];
  std::snprintf(s, sizeof s, "%.1f %%", 100 * fraction);
  return s;
}

double smallest(Vec3 v) {
  return std::min({v.x, v.y, v.z});
}
double largest(Vec3 v) {
  return std::max({v.x, v.y, v.z});
}

// One TPMS the design produces somewhere, and where ("" for the base).
struct Extreme {
  TpmsOptions tpms;
  std::string where;
};

// The base at each end of each ramp (the other quantities at their base values), and each
// blend: the extremes of what the design produces.
std::vector<Extreme> extremes_of(const LatticeDesign& design) {
  std::vector<Extreme> extremes;
  const TpmsOptions& base = design;
  if (!design.custom) {
    extremes.push_back({resolve_porosity(base), ""});
    for (const Grading& g : design.grading)
      for (int end = 0; end < 2; ++end) {
        const double value = end ? g.ramp.end : g.ramp.start;
        TpmsOptions t = base;
        switch (g.what) {
          case Graded::Porosity:
            t.porosity = value;
            break;
          case Graded::Level:
            t.level = value, t.porosity.reset();
            break;
          case Graded::Thickness:
            t.thickness = value, t.porosity.reset();
            break;
          case Graded::Cell:
            t.cell = (value / base.cell.x) * base.cell;
            break;
        }
        extremes.push_back({resolve_porosity(t), " at the " + std::string(end ? "end" : "start") +
                                                     " of the " + std::string(graded_name(g.what)) +
                                                     " ramp"});
      }
  }
  for (std::size_t b = 0; b < design.blends.size(); ++b)
    extremes.push_back(
        {resolve_porosity(design.blends[b].tpms), " in blend " + std::to_string(b + 1)});
  return extremes;
}

// Refuses a model smaller than one cell along its longest side; warns under three cells.
void review_size(const std::vector<Extreme>& extremes, const Box3& model, const ReviewOptions& o,
                 std::vector<std::string>& warnings) {
  if (extremes.empty()) return;
  const Vec3 size = model.size();
  const Vec3 cell = extremes.front().tpms.cell;
  const double spans = std::max({size.x / cell.x, size.y / cell.y, size.z / cell.z});
  const std::string across = "the model is " + mm(largest(size)) + " across";
  if (spans < 1)
    throw InputError(
        across + ", smaller than one " + mm(largest(cell)) + " cell" +
        units_hint(model, o.input_units, largest(cell)) +
        (likely_units(model, o.input_units, largest(cell)) ? "" : "; use a smaller --cell"));
  if (spans < 3)
    warnings.push_back(across + ", " + num(spans) +
                       " cells: too few for a lattice to show (a smaller --cell gives more)" +
                       units_hint(model, o.input_units));
}

// Refuses a voxel coarser than half the smallest cell (the lattice cannot be sampled); warns
// over a quarter (aliased).
void review_voxel(const std::vector<Extreme>& extremes, const ReviewOptions& o,
                  std::vector<std::string>& warnings) {
  const Extreme* finest = nullptr;
  for (const Extreme& l : extremes)
    if (!finest || smallest(l.tpms.cell) < smallest(finest->tpms.cell)) finest = &l;
  if (!finest) return;
  const double cell = smallest(finest->tpms.cell);
  const std::string what = "the voxel (" + mm(o.voxel) + ") is coarser than ";
  const std::string which = " of the smallest cell (" + mm(cell) + finest->where + ")";
  if (o.voxel > cell / 2)
    throw InputError(what + "half" + which + ": the lattice cannot be sampled; use --voxel " +
                     num(cell / 4) + " or less");
  if (o.voxel > cell / 4)
    warnings.push_back(what + "a quarter" + which + ": the lattice is aliased (rough and " +
                       "off its porosity); --voxel " + mm(cell / 8) + " gives it 8 per cell");
}

// The solid fraction of a layer, over 48³ samples of its cell (±0.5 % against 96³; the
// sorted 96³ cell is built only when a sentence needs a range).
double solid_fraction(const TpmsOptions& t) {
  return tpms_solid_fraction(t, 48);
}

// A level or thickness in the layer's unit: "0.3 mm", or "0.3c" for the seeds' raw C.
std::string in_unit(const TpmsOptions& t, double v) {
  return t.unit == LevelUnit::Raw ? num(v) + "c" : mm(v);
}

std::string level_text(const TpmsOptions& t) {
  return t.style == TpmsStyle::Network ? "level " + in_unit(t, t.level)
                                       : "thickness " + in_unit(t, t.thickness);
}

// What range of the layer's level or thickness gives between 3 % and 97 % solid.
std::string fitting_range(const TpmsOptions& t) {
  const CellSamples cell = sample_cell(t);
  if (t.style == TpmsStyle::Network)
    return "levels from " + in_unit(t, level_for_porosity(cell, t.style, 0.97)) + " to " +
           in_unit(t, level_for_porosity(cell, t.style, 0.03)) + " give 3-97 % solid";
  return "thicknesses up to " + in_unit(t, level_for_porosity(cell, t.style, 0.03)) +
         " leave some void; --porosity sets it directly";
}

// Refuses a layer that leaves (almost) no solid or no void; warns under 3 % of either, and
// where its struts, walls or pores are thinner than two voxels.
void review_extremes(const std::vector<Extreme>& extremes, const ReviewOptions& o,
                     std::vector<std::string>& warnings) {
  for (const Extreme& l : extremes) {
    const double solid = solid_fraction(l.tpms);
    const std::string name = "the " + tpms_label(l.tpms) + l.where;
    const std::string what = level_text(l.tpms);
    if (solid < 0.01 || solid > 0.99)
      throw InputError(name + " with " + what + " leaves " +
                       (solid < 0.5 ? "no solid" : "no void") + " (solid " + percent(solid) +
                       "); " + fitting_range(l.tpms));
    if (solid < 0.03 || solid > 0.97) {
      warnings.push_back(name + " with " + what + " leaves almost " +
                         (solid < 0.5 ? "no solid" : "no void") + " (solid " + percent(solid) +
                         ")");
      continue;
    }
    const LayerSizes sizes = layer_sizes(l.tpms);
    const bool network = l.tpms.style == TpmsStyle::Network;
    if (sizes.solid < 2 * o.voxel)
      warnings.push_back(name + " has " + (network ? "struts" : "walls") + " at most " +
                         mm(sizes.solid) + " thick, thinner than two voxels (" + mm(2 * o.voxel) +
                         "): they come out broken and the porosity misses; " + "--voxel " +
                         num(sizes.solid / 4) + " resolves them");
    if (sizes.pore < 2 * o.voxel)
      warnings.push_back(name + " has pores at most " + mm(sizes.pore) +
                         " wide, narrower than two voxels (" + mm(2 * o.voxel) +
                         "): they close up and the porosity misses; --voxel " +
                         num(sizes.pore / 4) + " resolves them");
  }
}

using detail::for_each_box_sample;

// Refuses a blend whose region misses the model's box; warns when what it covers of the box
// holds fewer than 8 of the blended lattice's cells (2 per side: the lattice barely shows).
void review_blends(const LatticeDesign& design, const Box3& model,
                   std::vector<std::string>& warnings) {
  constexpr int n = 24;
  for (std::size_t b = 0; b < design.blends.size(); ++b) {
    const Region& r = design.blends[b].region;
    std::size_t in = 0;
    const detail::RegionDistance distance(r);
    for_each_box_sample(model, n, [&](Vec3 p) { in += distance(p) < 0; });
    const double fraction = static_cast<double>(in) / ((n + 1) * (n + 1) * (n + 1));
    const std::string what =
        "blend " + std::to_string(b + 1) + "'s " + std::string(region_name(r.shape)) + " region";
    if (in == 0)
      throw InputError(what + " lies outside the model's box: the blend would change nothing; " +
                       "move its point into the model");
    const Vec3 size = model.size(), cell = design.blends[b].tpms.cell;
    const double covered = fraction * size.x * size.y * size.z;
    if (covered < 8 * cell.x * cell.y * cell.z)
      warnings.push_back(what + " covers only " + num(covered) + " mm3 of the model's box (" +
                         percent(fraction) + "), less than 8 of its " + mm(largest(cell)) +
                         " cells: the blended lattice barely shows");
  }
}

// The ramp coordinate's range over the model's box.
std::pair<double, double> ramp_coordinates(const Ramp& ramp, const Box3& model) {
  if (ramp.shape == RampShape::Depth) return {0, smallest(model.size()) / 2};
  double lo = INFINITY, hi = -INFINITY;
  for_each_box_sample(model, 16, [&](Vec3 p) {
    const double t = ramp_coordinate(ramp, p);
    lo = std::min(lo, t), hi = std::max(hi, t);
  });
  return {lo, hi};
}

// Refuses a ramp whose range misses the model (it would be constant); warns when the model
// sees under 10 % of its change, or a radial ramp is centred outside the model's box.
void review_ramps(const LatticeDesign& design, const Box3& model,
                  std::vector<std::string>& warnings) {
  for (const Grading& g : design.grading) {
    const Ramp& r = g.ramp;
    if (!r.from || !r.to || r.start == r.end) continue;
    const auto [lo, hi] = ramp_coordinates(r, model);
    const double a = std::min(*r.from, *r.to), b = std::max(*r.from, *r.to);
    const double seen = std::max(0.0, std::min(b, hi) - std::max(a, lo)) / std::max(b - a, 1e-300);
    // A volume ramp's coordinate is the volume's own value, not a length.
    const bool volume = r.shape == RampShape::Volume;
    auto at = [&](double t) { return volume ? num(t) : mm(t); };
    const std::string what = "the " + std::string(graded_name(g.what)) + " ramp (" +
                             std::string(ramp_name(r.shape)) + ", " + at(*r.from) + " to " +
                             at(*r.to) + ")";
    const std::string span =
        volume ? "the volume's values over the model are " + at(lo) + " to " + at(hi)
               : "the model spans " + at(lo) + " to " + at(hi) + " along it";
    if (seen <= 0)
      throw InputError(what + " misses the model: " + span +
                       ", so the whole part would get one value; set --grade-range within it");
    if (seen < 0.1)
      warnings.push_back(what + ": " + span + ", so only " + percent(seen) +
                         " of the change happens in the part");
    if (volume) {
      std::size_t beyond = 0, samples = 0;
      for_each_box_sample(model, 16, [&](Vec3 p) {
        bool out = false;
        sample_volume(*r.volume, p, &out);
        beyond += out, ++samples;
      });
      const ScalarVolume& v = *r.volume;
      if ((samples - beyond) * 100 < samples) {  // under 1 % of the box: not this part's volume
        Vec3 lo = v.origin, hi = v.origin;
        for (int a = 0; a < 3; ++a)
          (&lo.x)[a] -= v.spacing[a] / 2, (&hi.x)[a] += (v.dims[a] - 0.5) * v.spacing[a];
        throw InputError(what + " barely meets the model: the volume spans (" + mm(lo.x) + ", " +
                         mm(lo.y) + ", " + mm(lo.z) + ") to (" + mm(hi.x) + ", " + mm(hi.y) + ", " +
                         mm(hi.z) + "), the model (" + mm(model.min.x) + ", " + mm(model.min.y) +
                         ", " + mm(model.min.z) + ") to (" + mm(model.max.x) + ", " +
                         mm(model.max.y) + ", " + mm(model.max.z) +
                         "); were they made in other units? (fit and fill with the same --units)");
      }
      if (beyond * 10 > samples)
        warnings.push_back(what + ": " + percent(double(beyond) / samples) +
                           " of the model's box lies beyond the volume, where its border values "
                           "are repeated");
    }
    if (r.shape == RampShape::Radial && r.point) {
      const Vec3 c = *r.point;
      if (c.x < model.min.x || c.y < model.min.y || c.z < model.min.z || c.x > model.max.x ||
          c.y > model.max.y || c.z > model.max.z)
        warnings.push_back(what + " is centred outside the model's box");
    }
  }
}

}  // namespace

LayerSizes layer_sizes(const TpmsOptions& tpms) {
  // Three periods wide, measured in the middle one, so that no distance there is cut short
  // by the sample's faces; 20 nodes per smallest cell, so diameters read within about a
  // twentieth of a cell (the threshold, two voxels, is at least a twentieth of one when the
  // voxel is a fortieth: finer voxels warn only about struts thinner than that).
  const double cmin = smallest(tpms.cell), cmax = largest(tpms.cell);
  const double h = std::max(cmin / 20, 3 * cmax / 80);
  Grid grid;
  grid.spacing = h;
  const int n = static_cast<int>(std::ceil(3 * cmax / h)) + 1;
  grid.dims = {n, n, n};
  grid.origin = tpms.origin - Vec3{1.5 * cmax, 1.5 * cmax, 1.5 * cmax};
  const Field phi = sample_field(tpms_source(tpms), grid);
  Mask solid{grid, std::vector<std::uint8_t>(phi.values.size())};
  Mask pore = solid;
  for (std::size_t i = 0; i < phi.values.size(); ++i)
    solid.values[i] = phi.values[i] < 0, pore.values[i] = phi.values[i] >= 0;
  const Field ds = distance_transform(solid, true), dp = distance_transform(pore, true);
  LayerSizes sizes;
  const int lo = static_cast<int>(std::floor(cmax / h)), hi = n - 1 - lo;
  for (int k = lo; k <= hi; ++k)
    for (int j = lo; j <= hi; ++j)
      for (int i = lo; i <= hi; ++i) {
        const std::size_t at = grid.index(i, j, k);
        sizes.solid = std::max(sizes.solid, static_cast<double>(ds.values[at]));
        sizes.pore = std::max(sizes.pore, static_cast<double>(dp.values[at]));
      }
  // Node distances reach the nearest node of the other phase, about half a voxel beyond the
  // surface on average: the sphere's diameter is twice the distance less one voxel.
  sizes.solid = std::max(0.0, 2 * sizes.solid - h);
  sizes.pore = std::max(0.0, 2 * sizes.pore - h);
  return sizes;
}

// A porous structure's finest detail is its knot span (what one coefficient shapes), in mm
// where it is placed: under two voxels, marching cubes cannot follow it.
void review_structure(const LatticeDesign& design, const Box3& model, const ReviewOptions& o,
                      std::vector<std::string>& warnings) {
  if (!design.structure) return;
  const PorousStructure& s = *design.structure;
  const UnitCubeMap map = unit_cube_map(s, model);
  double span = INFINITY;
  for (int a = 0; a < 3; ++a)
    span = std::min(span, map.extent[a] / (s.field.counts[a] - s.field.degree));
  if (o.voxel > 0.5 * span) {
    char text[256];
    std::snprintf(text, sizeof text,
                  "the structure's finest detail (a knot span of %.3g mm over the %s) is under "
                  "two voxels of %.3g mm; a voxel of %.3g mm or less follows it",
                  span, s.placement == Placement::Tile ? "tile" : "model's box", o.voxel,
                  0.5 * span);
    warnings.push_back(text);
  }
}

std::vector<std::string> review_design(const LatticeDesign& design, const Box3& model,
                                       const ReviewOptions& options) {
  std::vector<std::string> warnings;
  if (model.empty()) return warnings;
  review_structure(design, model, options, warnings);
  const std::vector<Extreme> extremes = extremes_of(design);
  review_size(extremes, model, options, warnings);
  review_voxel(extremes, options, warnings);
  review_blends(design, model, warnings);
  review_ramps(design, model, warnings);
  review_extremes(extremes, options, warnings);
  return warnings;
}

}  // namespace tpmsfill
