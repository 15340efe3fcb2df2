// Recipes: FillOptions ⇄ JSON (nlohmann, kept private). Every key is checked: an unknown or
// misspelt one is an error naming its path, never silently ignored.
#include "tpmsfill/recipe.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/json_depth.hpp"
#include "io/file_bytes.hpp"
#include "io/parse_errors.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/scan/itdf.hpp"
#include "tpmsfill/solid/material_volume.hpp"

namespace tpmsfill {
namespace {

using json = nlohmann::ordered_json;

// A JSON object being read: remembers its path for messages and which keys were used.
class Reader {
 public:
  Reader(const json& value, std::string path, const std::string& source)
      : value_(value), path_(std::move(path)), source_(source) {
    if (!value_.is_object()) fail("", "must be an object");
  }

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw InputError(source_ + ": " + where(key) + ": " + what);
  }
  std::string where(const std::string& key) const {
    return path_.empty() ? (key.empty() ? "recipe" : key) : key.empty() ? path_ : path_ + "." + key;
  }
  const json* get(const std::string& key) {
    used_.push_back(key);
    auto it = value_.find(key);
    return it == value_.end() ? nullptr : &*it;
  }
  Reader object(const std::string& key, const json& value) const {
    return Reader(value, where(key), source_);
  }
  const std::string& source() const { return source_; }

  void number(const std::string& key, double& out) {
    if (const json* v = get(key)) out = as_number(key, *v);
  }
  void integer(const std::string& key, int& out) {
    if (const json* v = get(key)) {
      if (!v->is_number_integer()) fail(key, "must be an integer");
      out = v->get<int>();
    }
  }
  void boolean(const std::string& key, bool& out) {
    if (const json* v = get(key)) {
      if (!v->is_boolean()) fail(key, "must be true or false");
      out = v->get<bool>();
    }
  }
  void text(const std::string& key, std::string& out) {
    if (const json* v = get(key)) {
      if (!v->is_string()) fail(key, "must be a string");
      out = v->get<std::string>();
    }
  }
  template <class E>
  void name(const std::string& key, E& out, E (*from_name)(std::string_view)) {
    std::string s;
    text(key, s);
    if (s.empty() && !value_.contains(key)) return;
    try {
      out = from_name(s);
    } catch (const InputError& e) {
      fail(key, e.what());
    }
  }
  // [x, y, z] (or one number for all three when `scalar` is allowed).
  void vec3(const std::string& key, Vec3& out, bool scalar = false) {
    const json* v = get(key);
    if (!v) return;
    if (scalar && v->is_number()) {
      const double s = as_number(key, *v);
      out = {s, s, s};
      return;
    }
    if (!v->is_array() || v->size() != 3)
      fail(key, scalar ? "must be a number or [x, y, z]" : "must be [x, y, z]");
    out = {as_number(key, (*v)[0]), as_number(key, (*v)[1]), as_number(key, (*v)[2])};
  }
  // [[x, y], ...]: a polygon's corners.
  void points2(const std::string& key, std::vector<std::array<double, 2>>& out) {
    const json* v = get(key);
    if (!v) return;
    if (!v->is_array()) fail(key, "must be a list of [x, y] corners");
    out.clear();
    for (const json& q : *v) {
      if (!q.is_array() || q.size() != 2) fail(key, "must be a list of [x, y] corners");
      out.push_back({as_number(key, q[0]), as_number(key, q[1])});
    }
  }
  void optional_number(const std::string& key, std::optional<double>& out) {
    if (const json* v = get(key)) out = as_number(key, *v);
  }
  void optional_vec3(const std::string& key, std::optional<Vec3>& out) {
    if (!value_.contains(key)) {
      get(key);  // known here, even when absent
      return;
    }
    Vec3 v;
    vec3(key, v);
    out = v;
  }

  // Every key of the object must have been asked for.
  void finish() const {
    for (auto it = value_.begin(); it != value_.end(); ++it)
      if (std::find(used_.begin(), used_.end(), it.key()) == used_.end()) {
        std::string known;
        for (auto k = used_.begin(); k != used_.end(); ++k)
          if (std::find(used_.begin(), k, *k) == k) known += (known.empty() ? "" : ", ") + *k;
        fail(it.key(), "unknown key (known here: " + known + ")");
      }
  }

 private:
  double as_number(const std::string& key, const json& v) const {
    if (!v.is_number()) fail(key, "must be a number");
    const double d = v.get<double>();
    if (!std::isfinite(d)) fail(key, "must be finite");
    return d;
  }

  const json& value_;
  std::string path_;
  const std::string& source_;
  std::vector<std::string> used_;
};

// A level or thickness: mm as a number, or the seeds' raw C as {"c": value}; `raw` says which
// unit the lattice's earlier key used, so that one lattice does not mix them.
void read_level(Reader& r, const std::string& key, double& out, std::optional<LevelUnit>& unit) {
  const json* v = r.get(key);
  if (!v) return;
  LevelUnit here = LevelUnit::Millimetre;
  if (v->is_object()) {
    Reader c = r.object(key, *v);
    if (!v->contains("c")) c.fail("", "must be a number of mm or {\"c\": raw level}");
    c.number("c", out);
    c.finish();
    here = LevelUnit::Raw;
  } else {
    r.number(key, out);
  }
  if (unit && *unit != here)
    r.fail(key, "mixes mm and raw C in one lattice: give the level and thickness in one unit");
  unit = here;
}

// "terms": [{"amplitude": A, "wave": [h, k, l], "phase": P}, ...] of a fourier lattice.
bool read_terms(Reader& r, std::vector<FourierTerm>& terms) {
  const json* v = r.get("terms");
  if (!v) return false;
  if (!v->is_array()) r.fail("terms", "must be an array of {amplitude, wave, phase} objects");
  if (v->size() > kMaxFourierTerms)
    r.fail("terms", std::to_string(v->size()) + " terms: at most " +
                        std::to_string(kMaxFourierTerms) + " (the limit)");
  terms.clear();
  for (std::size_t i = 0; i < v->size(); ++i) {
    Reader t = r.object("terms[" + std::to_string(i) + "]", (*v)[i]);
    if (!(*v)[i].is_object()) t.fail("", "must be an object {amplitude, wave, phase}");
    FourierTerm term;
    t.number("amplitude", term.amplitude);
    const json* w = t.get("wave");
    if (!w || !w->is_array() || w->size() != 3)
      t.fail("wave", "must be [h, k, l]: whole periods per cell along x, y and z");
    for (int a = 0; a < 3; ++a) {
      if (!(*w)[a].is_number_integer())
        t.fail("wave", "must be whole numbers (periods per cell), so that the cell is a period");
      const auto n = (*w)[a].get<long long>();
      if (std::llabs(n) > kMaxFourierWave)
        t.fail("wave", std::to_string(n) + " periods a cell: at most " +
                           std::to_string(kMaxFourierWave) + " (the limit)");
      term.wave[a] = static_cast<int>(n);
    }
    t.number("phase", term.phase);
    t.finish();
    terms.push_back(term);
  }
  return true;
}

// A recipe's "lattice" object: one TPMS.
void read_tpms(Reader& r, TpmsOptions& o) {
  r.name("type", o.type, tpms_type_from_name);
  // A blend starts from the base's lattice: a named type there drops the base's terms.
  if (!read_terms(r, o.terms) && o.type != TpmsType::Fourier) o.terms.clear();
  r.name("style", o.style, tpms_style_from_name);
  r.vec3("cell", o.cell, true);
  std::optional<LevelUnit> unit;
  read_level(r, "level", o.level, unit);
  read_level(r, "thickness", o.thickness, unit);
  if (unit) o.unit = *unit;
  r.optional_number("porosity", o.porosity);
  r.vec3("origin", o.origin);
  Vec3 euler;
  if (const json* v = r.get("rotation"); v && !v->is_null()) {
    r.vec3("rotation", euler);
    o.rotation = rotation_from_euler(euler);
  }
  if (const json* v = r.get("rotation_matrix")) {
    if (!v->is_array() || v->size() != 9)
      r.fail("rotation_matrix", "must be 9 numbers, row by row");
    for (std::size_t i = 0; i < 9; ++i) {
      if (!(*v)[i].is_number()) r.fail("rotation_matrix", "must be 9 numbers, row by row");
      o.rotation.m[i] = (*v)[i].get<double>();
    }
  }
  r.finish();
  try {
    require_valid(o);
  } catch (const InputError& e) {
    r.fail("", e.what());
  }
}

Ramp read_ramp(Reader& r) {
  Ramp ramp;
  r.name("ramp", ramp.shape, ramp_from_name);
  r.optional_vec3("point", ramp.point);
  r.vec3("axis", ramp.axis);
  r.optional_number("from", ramp.from);
  r.optional_number("to", ramp.to);
  r.number("start", ramp.start);
  r.number("end", ramp.end);
  return ramp;
}

template <class F>
void for_each_in_array(Reader& r, const std::string& key, const F& f) {
  const json* v = r.get(key);
  if (!v) return;
  if (!v->is_array()) r.fail(key, "must be an array of objects");
  for (std::size_t i = 0; i < v->size(); ++i) {
    Reader item = r.object(key + "[" + std::to_string(i) + "]", (*v)[i]);
    f(item);
    item.finish();
  }
}

json vec(Vec3 v) {
  return json::array({v.x, v.y, v.z});
}

// `full`: every key, for blends (keys a blend leaves out would be the base TPMS's).
json tpms_json(const TpmsOptions& o, bool full) {
  json j;
  j["type"] = tpms_type_name(o.type);
  if (o.type == TpmsType::Fourier) {
    json terms = json::array();
    for (const FourierTerm& t : o.terms)
      terms.push_back({{"amplitude", t.amplitude},
                       {"wave", json::array({t.wave[0], t.wave[1], t.wave[2]})},
                       {"phase", t.phase}});
    j["terms"] = terms;
  }
  j["style"] = tpms_style_name(o.style);
  j["cell"] = o.cell.x == o.cell.y && o.cell.y == o.cell.z ? json(o.cell.x) : vec(o.cell);
  auto level = [&](double v) { return o.unit == LevelUnit::Raw ? json{{"c", v}} : json(v); };
  if (o.style == TpmsStyle::Network || o.level != 0) j["level"] = level(o.level);
  if (o.style == TpmsStyle::Sheet) j["thickness"] = level(o.thickness);
  if (o.porosity) j["porosity"] = *o.porosity;
  j["origin"] = vec(o.origin);
  if (full || !o.rotation.is_identity()) j["rotation_matrix"] = o.rotation.m;
  return j;
}

// Malformed JSON: a ParseError at the line of the byte nlohmann stopped at, as for mesh files.
// (A number too large for a double is an out_of_range error, which has no position: blame
// the end.)
[[noreturn]] void fail_json(std::string_view text, const std::string& source,
                            const json::exception& e) {
  const auto* parse = dynamic_cast<const json::parse_error*>(&e);
  const std::size_t byte = std::min(parse ? parse->byte : text.size(), text.size());
  std::uint64_t line = 1;
  for (std::size_t i = 0; i + 1 < byte; ++i) line += text[i] == '\n';
  std::string why = e.what();
  if (auto p = why.find("; "); p != std::string::npos) why = why.substr(p + 2);
  detail::fail_at_line(source, line, "not valid JSON: " + why);
}

}  // namespace

FillOptions read_recipe(std::string_view text, const std::string& source,
                        const FillOptions& defaults) {
  json root;
  if (const auto byte = detail::json_too_deep(text)) {
    std::uint64_t line = 1;
    for (std::size_t i = 0; i < *byte; ++i) line += text[i] == '\n';
    detail::fail_at_line(source, line,
                         "JSON nested more than " + std::to_string(detail::kMaxJsonDepth) +
                             " levels deep (the limit)");
  }
  try {
    root = json::parse(text.begin(), text.end());
  } catch (const json::exception& e) {
    fail_json(text, source, e);
  }
  FillOptions o = defaults;
  Reader r(root, "", source);
  std::string description;  // free text for people (catalogues, job sheets): read, not used
  r.text("description", description);
  r.name("units", o.units.units, units_from_name);
  r.number("scale", o.units.scale);
  r.number("voxel", o.grid.voxel_size);
  r.integer("padding", o.grid.padding);
  r.integer("band", o.band.width);
  if (!(o.band.width >= 1 && o.band.width <= 64))  // as --band
    throw InputError(source + ": band: must be 1 to 64 voxels");
  r.number("skin", o.skin);
  r.boolean("skin_windows", o.skin_windows);
  r.name("inside", o.inside, inside_from_name);
  r.boolean("full_field", o.full_field);
  r.boolean("keep_islands", o.keep_islands);
  r.boolean("measure", o.measure);
  r.number("min_wall", o.min_wall);  // printability limits, mm (0: none)
  r.number("min_pore", o.min_pore);
  r.boolean("self_intersections", o.check_self_intersections);
  r.name("validate", o.validation, validation_from_name);
  if (const json* v = r.get("custom"); v && !(v->is_boolean() && !v->get<bool>()))
    r.fail("custom", "a custom field is code: it cannot come from a recipe");
  // Files named in the recipe are relative to its folder; the job's echo holds them as found,
  // so that it finds them from anywhere.
  auto beside_recipe = [&](const std::string& name) {
    std::filesystem::path file = name;
    if (file.is_relative()) file = std::filesystem::path(source).parent_path() / file;
    return file;
  };
  // A porous structure (ITDF).
  if (r.get("field")) {
    r.text("field", o.design.structure_file);
    const std::filesystem::path file = beside_recipe(o.design.structure_file);
    o.design.structure = read_structure(file).structure;
    o.design.structure_file = file.string();
  }
  if (const json* v = r.get("lattice")) {
    Reader l = r.object("lattice", *v);
    read_tpms(l, o.design);
  }
  const TpmsOptions base = o.design;
  if (r.get("grading")) o.design.grading.clear();
  for_each_in_array(r, "grading", [&](Reader& item) {
    Grading g;
    item.name("what", g.what, graded_from_name);
    if (!item.get("what")) item.fail("what", "missing (porosity, level, thickness or cell)");
    g.ramp = read_ramp(item);
    // A volume ramp's values: a fitted model's material (.tsm) or a volume file.
    if (g.ramp.shape == RampShape::Volume) {
      item.text("volume", g.ramp.volume_file);
      if (g.ramp.volume_file.empty())
        item.fail("volume", "missing: a volume ramp names its file (.tsm, .nrrd, .mha, ...)");
      const std::filesystem::path file = beside_recipe(g.ramp.volume_file);
      g.ramp.volume = std::make_shared<const ScalarVolume>(read_grading_volume(file));
      g.ramp.volume_file = file.string();
    } else if (item.get("volume")) {
      item.fail("volume", "only a volume ramp reads a volume");
    }
    o.design.grading.push_back(g);
  });
  if (r.get("blends")) o.design.blends.clear();
  for_each_in_array(r, "blends", [&](Reader& item) {
    Blend b;
    b.tpms = base;
    if (const json* v = item.get("lattice")) {
      // A level or thickness of its own replaces an inherited porosity.
      if (v->is_object() && (v->contains("level") || v->contains("thickness")) &&
          !v->contains("porosity"))
        b.tpms.porosity.reset();
      Reader l = item.object("lattice", *v);
      read_tpms(l, b.tpms);
    }
    if (const json* v = item.get("region")) {
      Reader g = item.object("region", *v);
      g.name("shape", b.region.shape, region_from_name);
      g.vec3("point", b.region.point);
      g.vec3("axis", b.region.axis);
      g.number("size", b.region.size);
      if (b.region.shape == RegionShape::Polygon) {
        g.points2("loop", b.region.loop);
        g.vec3("u", b.region.u);
        g.vec3("v", b.region.v);
        g.number("inner", b.region.inner);
        g.number("outer", b.region.outer);
        g.name("join", b.region.join, ring_join_from_name);
      }
      g.finish();
    } else {
      item.fail("region", "missing (a half-space, slab, sphere, cylinder or polygon)");
    }
    item.number("width", b.width);
    item.name("transition", b.transition, transition_from_name);
    item.number("peak", b.peak);
    o.design.blends.push_back(b);
  });
  r.finish();
  try {
    require_valid(o.design);
  } catch (const InputError& e) {
    throw InputError(source + ": " + e.what());
  }
  return o;
}

FillOptions read_recipe_file(const std::string& path, const FillOptions& defaults) {
  // A recipe is a page of JSON: 16 MiB is far beyond any, and a FIFO or a device is refused.
  return read_recipe(detail::read_file_bytes(path, std::uint64_t{16} << 20), path, defaults);
}

std::string recipe_json(const FillOptions& o) {
  json j;
  j["units"] = units_name(o.units.units);
  j["scale"] = o.units.scale;
  j["voxel"] = o.grid.voxel_size;
  j["padding"] = o.grid.padding;
  j["band"] = o.band.width;
  j["inside"] = inside_name(o.inside);
  j["skin"] = o.skin;
  j["skin_windows"] = o.skin_windows;
  j["full_field"] = o.full_field;
  j["keep_islands"] = o.keep_islands;
  j["measure"] = o.measure;
  j["min_wall"] = o.min_wall;
  j["min_pore"] = o.min_pore;
  j["self_intersections"] = o.check_self_intersections;
  // Only when not the default, so that echoes of recipes written before it stay the same.
  if (o.validation != FillOptions::Validation::Proof) j["validate"] = validation_name(o.validation);
  if (!o.design.structure_file.empty())
    j["field"] = o.design.structure_file;
  else if (o.design.custom)
    j["custom"] = true;
  j["lattice"] = tpms_json(o.design, false);
  json grading = json::array();
  for (const Grading& g : o.design.grading) {
    json e;
    e["what"] = graded_name(g.what);
    e["ramp"] = ramp_name(g.ramp.shape);
    if (g.ramp.point) e["point"] = vec(*g.ramp.point);
    if (g.ramp.shape == RampShape::Linear || g.ramp.shape == RampShape::Radial)
      e["axis"] = vec(g.ramp.axis);
    if (g.ramp.shape == RampShape::Volume) e["volume"] = g.ramp.volume_file;
    if (g.ramp.from) e["from"] = *g.ramp.from;
    if (g.ramp.to) e["to"] = *g.ramp.to;
    e["start"] = g.ramp.start;
    e["end"] = g.ramp.end;
    grading.push_back(e);
  }
  j["grading"] = grading;
  json blends = json::array();
  for (const Blend& b : o.design.blends) {
    json e;
    e["lattice"] = tpms_json(b.tpms, true);
    e["region"] = {{"shape", region_name(b.region.shape)},
                   {"point", vec(b.region.point)},
                   {"axis", vec(b.region.axis)},
                   {"size", b.region.size}};
    if (b.region.shape == RegionShape::Polygon) {
      json loop = json::array();
      for (const auto& q : b.region.loop) loop.push_back({q[0], q[1]});
      e["region"]["loop"] = loop;
      e["region"]["u"] = vec(b.region.u);
      e["region"]["v"] = vec(b.region.v);
      e["region"]["inner"] = b.region.inner;
      e["region"]["outer"] = b.region.outer;
      e["region"]["join"] = ring_join_name(b.region.join);
    }
    e["width"] = b.width;
    e["transition"] = transition_name(b.transition);
    if (b.transition == Transition::Beta) e["peak"] = b.peak;
    blends.push_back(e);
  }
  j["blends"] = blends;
  return j.dump(2) + "\n";
}

}  // namespace tpmsfill
