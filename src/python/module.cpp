// The Python module `tpmsfill` (issue 42): numpy arrays in, plain Python values out, the
// library's exceptions as Python exceptions of the same names. Like the CLI, it only converts:
// the work is the library's, done with the GIL released.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <exception>
#include <memory>
#include <optional>
#include <string>
#include <tpmsfill/check.hpp>
#include <tpmsfill/conformal.hpp>
#include <tpmsfill/decimate.hpp>
#include <tpmsfill/error.hpp>
#include <tpmsfill/fill.hpp>
#include <tpmsfill/io/volume.hpp>
#include <tpmsfill/progress.hpp>
#include <tpmsfill/recipe.hpp>
#include <tpmsfill/repair.hpp>
#include <tpmsfill/report.hpp>
#include <tpmsfill/scan/itdf.hpp>
#include <tpmsfill/slice.hpp>
#include <tpmsfill/surface/parameterize.hpp>
#include <tpmsfill/types.hpp>
#include <utility>
#include <vector>

namespace py = pybind11;

namespace {

// A soup from an (n, 3) float array of vertices and an (m, 3) integer array of faces; one
// sentence naming the argument where the shapes or indices are wrong.
tpmsfill::TriangleSoup soup_from(
    const py::array_t<double, py::array::c_style | py::array::forcecast>& vertices,
    const py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>& faces) {
  if (vertices.ndim() != 2 || vertices.shape(1) != 3)
    throw tpmsfill::InputError("vertices must be an (n, 3) array of coordinates");
  if (faces.ndim() != 2 || faces.shape(1) != 3)
    throw tpmsfill::InputError("faces must be an (m, 3) array of vertex indices");
  tpmsfill::TriangleSoup soup;
  const auto v = vertices.unchecked<2>();
  const auto f = faces.unchecked<2>();
  soup.points.reserve(static_cast<std::size_t>(v.shape(0)));
  for (py::ssize_t i = 0; i < v.shape(0); ++i) soup.points.push_back({v(i, 0), v(i, 1), v(i, 2)});
  soup.triangles.reserve(static_cast<std::size_t>(f.shape(0)));
  for (py::ssize_t t = 0; t < f.shape(0); ++t) {
    tpmsfill::Triangle tri{};
    for (int c = 0; c < 3; ++c) {
      const std::int64_t index = f(t, c);
      if (index < 0 || index >= v.shape(0))
        throw tpmsfill::InputError("face " + std::to_string(t) + " names vertex " +
                                   std::to_string(index) + ", not one of the " +
                                   std::to_string(v.shape(0)) + " vertices");
      tri[c] = static_cast<std::uint32_t>(index);
    }
    soup.triangles.push_back(tri);
  }
  return soup;
}

// A mesh's points and triangles as (n, 3) float64 and (m, 3) uint32 arrays over its own
// memory, without a copy: the mesh lives as long as either array.
py::tuple arrays_of(tpmsfill::TriangleSoup&& mesh) {
  static_assert(sizeof(tpmsfill::Vec3) == 3 * sizeof(double));
  auto owner = std::make_shared<tpmsfill::TriangleSoup>(std::move(mesh));
  auto* keep = new std::shared_ptr<tpmsfill::TriangleSoup>(owner);
  const py::capsule base(
      keep, [](void* p) { delete static_cast<std::shared_ptr<tpmsfill::TriangleSoup>*>(p); });
  const auto n = static_cast<py::ssize_t>(owner->points.size());
  const auto m = static_cast<py::ssize_t>(owner->triangles.size());
  py::array_t<double> points({n, py::ssize_t(3)}, reinterpret_cast<double*>(owner->points.data()),
                             base);
  py::array_t<std::uint32_t> triangles(
      {m, py::ssize_t(3)}, reinterpret_cast<std::uint32_t*>(owner->triangles.data()), base);
  return py::make_tuple(points, triangles);
}

// The library's JSON (the CLI's --json) as Python values: one description of every fact.
py::object from_json(const std::string& text) {
  return py::module_::import("json").attr("loads")(text);
}

// What every job that makes a mesh returns: (points, triangles, report).
py::tuple mesh_and_report(tpmsfill::TriangleSoup&& mesh, const std::string& report_json) {
  py::tuple arrays = arrays_of(std::move(mesh));
  return py::make_tuple(arrays[0], arrays[1], from_json(report_json));
}

using Vertices = py::array_t<double, py::array::c_style | py::array::forcecast>;
using Faces = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;

// A Python callable as the library's Progress: progress(stage, fraction) with the stage's name
// and the job's overall fraction; returning False cancels. It is called from the job's worker
// threads (serialised by the job), so it takes the GIL for each call. Ctrl-C, which Python only
// sees between bytecodes, is looked for on every report, with or without a callable: the job is
// cancelled and KeyboardInterrupt raised once it has stopped. An exception the callable raises
// cancels the job too, and is raised again in its place.
class PythonProgress : public tpmsfill::Progress {
 public:
  explicit PythonProgress(py::object callable) : callable_(std::move(callable)) {}

  void begin(const tpmsfill::StageInfo& stage) override {
    if (stage.step.empty()) stage_ = std::string(stage.name);
  }
  void begin(std::string_view stage) override { stage_ = std::string(stage); }
  bool report(double fraction) override { return report(fraction, fraction); }
  bool report(double, double overall) override {
    if (stopped_) return false;
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) {
      failure_ = std::make_unique<py::error_already_set>();
      return !(stopped_ = true);
    }
    if (callable_.is_none()) return true;
    try {
      const py::object answer = callable_(stage_, overall);
      if (!answer.is_none() && !answer.cast<bool>()) stopped_ = true;
    } catch (py::error_already_set& e) {
      failure_ = std::make_unique<py::error_already_set>(std::move(e));
      stopped_ = true;
    }
    return !stopped_;
  }

  /// After the job: the callable's or Ctrl-C's exception, if one stopped it, raised here.
  void raise_if_failed() {
    if (failure_) {
      std::unique_ptr<py::error_already_set> e = std::move(failure_);
      throw std::move(*e);
    }
  }

 private:
  py::object callable_;
  std::string stage_;
  bool stopped_ = false;
  std::unique_ptr<py::error_already_set> failure_;
};

// Runs `work` with the GIL released and `progress` watching it: the callable's own exception
// (or KeyboardInterrupt) in place of the library's Cancelled where one stopped it.
template <class Work>
auto watched(PythonProgress& progress, Work&& work) {
  try {
    py::gil_scoped_release release;
    return work();
  } catch (const tpmsfill::Cancelled&) {
    progress.raise_if_failed();
    throw;
  }
}

// The recipe dict given, its top-level keys replaced by the keyword arguments, as JSON (the
// caller's dict is not changed).
std::string recipe_text(const py::object& recipe, const py::dict& keys) {
  py::dict merged;
  if (!recipe.is_none())
    merged = py::module_::import("builtins").attr("dict")(recipe).cast<py::dict>();
  for (const auto& [key, value] : keys) merged[key] = value;
  return py::module_::import("json").attr("dumps")(merged).cast<std::string>();
}

// Takes `key` out of `keys` (a copy of the keyword arguments) as T, if given.
template <class T>
std::optional<T> take(py::dict& keys, const char* key) {
  if (!keys.contains(key)) return std::nullopt;
  const py::object value = keys[key];
  PyDict_DelItemString(keys.ptr(), key);
  try {
    return value.cast<T>();
  } catch (const py::cast_error&) {
    throw tpmsfill::InputError(std::string(key) + ": " + std::string(py::str(value)) + " is not " +
                               (std::is_same_v<T, std::string> ? "a name"
                                : std::is_same_v<T, bool>      ? "True or False"
                                                               : "a number"));
  }
}

// Keyword arguments a function does not take: one sentence naming them.
void refuse_unknown(const py::dict& keys, const char* function) {
  if (keys.empty()) return;
  std::string names;
  for (const auto& [key, value] : keys)
    names += (names.empty() ? "" : ", ") + py::str(key).cast<std::string>();
  throw tpmsfill::InputError(std::string(function) + "() takes no argument " + names);
}

}  // namespace

PYBIND11_MODULE(_tpmsfill, m) {
  m.doc() = "tpmsfill: TPMS lattices clipped to any triangle mesh, proved closed and manifold";

  // Python exceptions of the library's names, all derived from tpmsfill.Error.
  static py::exception<tpmsfill::Error> error(m, "Error");
  static py::exception<tpmsfill::IoError> io_error(m, "IoError", error.ptr());
  static py::exception<tpmsfill::ParseError> parse_error(m, "ParseError", error.ptr());
  static py::exception<tpmsfill::InputError> input_error(m, "InputError", error.ptr());
  static py::exception<tpmsfill::ResourceError> resource_error(m, "ResourceError", error.ptr());
  static py::exception<tpmsfill::ValidationError> validation_error(m, "ValidationError",
                                                                   error.ptr());
  static py::exception<tpmsfill::Cancelled> cancelled(m, "Cancelled", error.ptr());
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const tpmsfill::IoError& e) {
      io_error(e.what());
    } catch (const tpmsfill::ParseError& e) {
      parse_error(e.what());
    } catch (const tpmsfill::InputError& e) {
      input_error(e.what());
    } catch (const tpmsfill::ResourceError& e) {
      resource_error(e.what());
    } catch (const tpmsfill::ValidationError& e) {
      validation_error(e.what());
    } catch (const tpmsfill::Cancelled& e) {
      cancelled(e.what());
    } catch (const tpmsfill::Error& e) {
      error(e.what());
    }
  });

  m.def(
      "check",
      [](const py::array_t<double, py::array::c_style | py::array::forcecast>& vertices,
         const py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>& faces,
         bool self_intersections) {
        const tpmsfill::TriangleSoup soup = soup_from(vertices, faces);
        std::string json;
        {
          py::gil_scoped_release release;
          tpmsfill::CheckOptions options;
          options.self_intersections = self_intersections;
          json = tpmsfill::to_json(tpmsfill::check_mesh(soup, options));
        }
        return from_json(json);
      },
      py::arg("vertices"), py::arg("faces"), py::arg("self_intersections") = true,
      "The facts of a triangle mesh, as `tpmsfill check --json` gives them: valid, closed, "
      "manifold, outward, genus, volume, holes, self-intersecting pairs, ... (a dict).\n\n"
      "vertices: (n, 3) coordinates in mm; faces: (m, 3) vertex indices, counter-clockwise "
      "seen from outside. Raises tpmsfill.InputError for arrays of the wrong shape or indices "
      "out of range.");

  m.def(
      "fill",
      [](const Vertices& vertices, const Faces& faces, const py::object& recipe,
         const py::object& progress, const py::kwargs& options) {
        const tpmsfill::TriangleSoup soup = soup_from(vertices, faces);
        tpmsfill::FillOptions o = tpmsfill::read_recipe(recipe_text(recipe, options), "fill()");
        PythonProgress watch(progress);
        o.progress = &watch;
        tpmsfill::FillResult result = watched(watch, [&] { return tpmsfill::fill(soup, o); });
        return mesh_and_report(std::move(result.mesh), tpmsfill::to_json(result.report));
      },
      py::arg("vertices"), py::arg("faces"), py::arg("recipe") = py::none(), py::kw_only(),
      py::arg("progress") = py::none(),
      "Fills a closed mesh with a TPMS lattice clipped to it: (vertices, faces, report).\n\n"
      "The job is a recipe (docs/recipes.md): a dict, its top-level keys given or replaced as "
      "keyword arguments, e.g. fill(v, f, voxel=0.1, lattice={'type': 'gyroid', 'cell': 2}). "
      "The output is validated (closed, 2-manifold, outward, no self-intersections) before it "
      "is returned; vertices (n, 3) float64 and faces (m, 3) uint32 share its memory. Raises "
      "tpmsfill.InputError for a bad recipe (a key it does not know, a value out of range) or "
      "a model that cannot hold the lattice asked.\n\n"
      "progress: a callable progress(stage, fraction) called as the job goes (fraction of the "
      "whole job, 0 to 1); returning False cancels it (tpmsfill.Cancelled). Ctrl-C cancels too "
      "(KeyboardInterrupt), within about a percent of a stage.");

  m.def(
      "slice",
      [](const Vertices& vertices, const Faces& faces, double layer, const py::object& recipe,
         const py::object& progress, const py::kwargs& options) {
        const tpmsfill::TriangleSoup soup = soup_from(vertices, faces);
        py::dict keys(options);
        tpmsfill::SliceOptions so;
        so.layer = layer;
        so.start = take<double>(keys, "start");
        tpmsfill::FillOptions o = tpmsfill::read_recipe(recipe_text(recipe, keys), "slice()");
        PythonProgress watch(progress);
        o.progress = &watch;
        struct Kept {  // a layer without its plane's φ, which Python is not given
          double z, area;
          std::vector<tpmsfill::Contour> contours;
        };
        std::vector<Kept> layers;
        const tpmsfill::SliceReport report = watched(watch, [&] {
          return tpmsfill::slice(soup, o, so, [&](const tpmsfill::Layer& layer) {
            layers.push_back({layer.z, layer.area, layer.contours});
          });
        });
        py::list out;
        for (const Kept& l : layers) {
          py::list contours;
          for (const tpmsfill::Contour& c : l.contours) {
            py::array_t<double> points({static_cast<py::ssize_t>(c.points.size()), py::ssize_t(2)});
            auto p = points.mutable_unchecked<2>();
            for (std::size_t i = 0; i < c.points.size(); ++i) {
              p(static_cast<py::ssize_t>(i), 0) = c.points[i].x;
              p(static_cast<py::ssize_t>(i), 1) = c.points[i].y;
            }
            contours.append(points);
          }
          py::dict d;
          d["z"] = l.z;
          d["area"] = l.area;
          d["contours"] = contours;
          out.append(d);
        }
        return py::make_tuple(out, from_json(tpmsfill::to_json(report)));
      },
      py::arg("vertices"), py::arg("faces"), py::arg("layer"), py::arg("recipe") = py::none(),
      py::kw_only(), py::arg("progress") = py::none(),
      "Slices the lattice fill() would make into printer layers: (layers, report).\n\n"
      "layers: a list of dicts, one a layer from the bottom, {'z': height of its plane in mm, "
      "'area': its solid area in mm², 'contours': [(k, 2) arrays of x, y]}, outer contours "
      "counter-clockwise and holes "
      "clockwise seen from +z, checked not to cross or touch. layer: the thickness in mm; "
      "start=: the first layer's bottom (default the model's lowest point). The job is a "
      "recipe with keyword arguments, as fill()'s; progress as fill()'s.");

  m.def(
      "decimate",
      [](const Vertices& vertices, const Faces& faces, double tolerance,
         std::uint64_t target_triangles, const py::object& progress) {
        const tpmsfill::TriangleSoup soup = soup_from(vertices, faces);
        tpmsfill::DecimateOptions o;
        o.tolerance = tolerance;
        o.target_triangles = target_triangles;
        o.rounding = tpmsfill::CoordinateRounding::None;
        PythonProgress watch(progress);
        o.progress = &watch;
        tpmsfill::DecimateResult result =
            watched(watch, [&] { return tpmsfill::decimate(soup, o); });
        return mesh_and_report(std::move(result.mesh), tpmsfill::to_json(result.report));
      },
      py::arg("vertices"), py::arg("faces"), py::arg("tolerance"), py::kw_only(),
      py::arg("target_triangles") = 0, py::arg("progress") = py::none(),
      "Fewer triangles within `tolerance` mm of the surface (both ways), still valid: "
      "(vertices, faces, report). The input must be valid (check()); target_triangles stops "
      "once that few are left.");

  m.def(
      "repair",
      [](const Vertices& vertices, const Faces& faces, const py::object& progress,
         const py::kwargs& options) {
        const tpmsfill::TriangleSoup soup = soup_from(vertices, faces);
        py::dict keys(options);
        tpmsfill::RepairOptions o;
        o.rounding = tpmsfill::CoordinateRounding::None;
        if (auto v = take<bool>(keys, "wrap")) o.wrap = *v;
        if (auto v = take<bool>(keys, "volume")) o.volume = *v;
        if (auto v = take<double>(keys, "alpha")) o.alpha = *v;
        if (auto v = take<double>(keys, "offset")) o.offset = *v;
        if (auto v = take<double>(keys, "voxel")) o.voxel = *v;
        if (auto v = take<double>(keys, "tolerance")) o.tolerance = *v;
        if (auto v = take<double>(keys, "min_component_fraction")) o.min_component_fraction = *v;
        refuse_unknown(keys, "repair");
        PythonProgress watch(progress);
        o.progress = &watch;
        tpmsfill::RepairResult result =
            watched(watch, [&] { return tpmsfill::repair_mesh(soup, o); });
        return mesh_and_report(std::move(result.mesh), tpmsfill::to_json(result.report));
      },
      py::arg("vertices"), py::arg("faces"), py::kw_only(), py::arg("progress") = py::none(),
      "A scan made a valid solid, as `tpmsfill repair`: (vertices, faces, report).\n\n"
      "Keyword arguments (as the command's flags): wrap, volume (bool), alpha, offset, voxel, "
      "tolerance (mm), min_component_fraction. The report says how far the result moved from "
      "the input and whether it is valid.");

  m.def(
      "field_fit",
      [](const py::array_t<double, py::array::c_style | py::array::forcecast>& values,
         const std::string& out, const std::vector<double>& spacing,
         const std::vector<double>& origin, const std::string& sign,
         const std::vector<int>& coefficients) {
        if (values.ndim() != 3)
          throw tpmsfill::InputError("values must be a 3-d array, indexed [z, y, x]");
        if (spacing.size() != 3 || origin.size() != 3)
          throw tpmsfill::InputError("spacing and origin take three numbers (x, y, z)");
        if (coefficients.size() != 0 && coefficients.size() != 1 && coefficients.size() != 3)
          throw tpmsfill::InputError("coefficients take none, one count, or three (x, y, z)");
        tpmsfill::ScalarVolume v;
        // numpy's C order [z, y, x] is the volume's x-fastest order.
        v.dims = {static_cast<int>(values.shape(2)), static_cast<int>(values.shape(1)),
                  static_cast<int>(values.shape(0))};
        v.values.assign(values.data(), values.data() + values.size());
        v.spacing = {spacing[0], spacing[1], spacing[2]};
        v.origin = {origin[0], origin[1], origin[2]};
        v.sign = tpmsfill::field_sign_from_name(sign);
        if (v.sign != tpmsfill::FieldSign::Signed)
          throw tpmsfill::InputError(
              "field_fit() fits a signed field (negative in the solid); fit others with "
              "`tpmsfill field fit --solid` or `--surface`");
        std::array<int, 3> counts{};
        for (int a = 0; a < 3; ++a)
          counts[a] = coefficients.empty() ? 0 : coefficients[coefficients.size() == 1 ? 0 : a];
        tpmsfill::ItdfFile file;
        {
          py::gil_scoped_release release;
          file = tpmsfill::fit_field(v, counts, {});
          file.provenance = "tpmsfill Python field_fit()";
          tpmsfill::write_itdf(out, file);
        }
        py::dict d;
        d["coefficients"] =
            py::make_tuple(file.structure.field.counts[0], file.structure.field.counts[1],
                           file.structure.field.counts[2]);
        d["rms"] = file.fit->rms;
        d["max_error"] = file.fit->max_error;
        d["flipped"] = file.fit->flipped;
        d["seconds"] = file.fit->seconds;
        return d;
      },
      py::arg("values"), py::arg("out"), py::kw_only(),
      py::arg("spacing") = std::vector<double>{1, 1, 1},
      py::arg("origin") = std::vector<double>{0, 0, 0}, py::arg("sign") = "signed",
      py::arg("coefficients") = std::vector<int>{},
      "Fits a signed distance field (a 3-d array [z, y, x], negative in the solid; spacing and "
      "origin of its first cell in mm) with a B-spline and writes the structure to `out` "
      "(.itdf), as `tpmsfill field fit`: fill(v, f, field=out) then fills a part with it. "
      "Returns the fit's figures: coefficients per axis, rms and max_error of the fit, the "
      "share of cells whose side changed, seconds.");

  m.def(
      "conformal",
      [](const Vertices& vertices, const Faces& faces, double height, const py::object& recipe,
         const py::object& progress, const py::kwargs& options) {
        const tpmsfill::TriangleSoup surface = soup_from(vertices, faces);
        py::dict keys(options);
        tpmsfill::ConformalJobOptions o;
        o.layer.height = height;
        if (auto v = take<std::string>(keys, "side"))
          o.layer.side = tpmsfill::surface_side_from_name(*v);
        if (auto v = take<double>(keys, "normal_scale")) o.layer.normal_scale = *v;
        o.layer.length_u = take<double>(keys, "length_u");
        o.layer.length_v = take<double>(keys, "length_v");
        if (auto v = take<double>(keys, "skin_surface")) o.layer.skin_surface = *v;
        if (auto v = take<double>(keys, "skin_top")) o.layer.skin_top = *v;
        if (auto v = take<std::string>(keys, "map")) o.map = tpmsfill::slab_map_from_name(*v);
        if (auto v = take<std::string>(keys, "layout"))
          o.layout.method = tpmsfill::layout_method_from_name(*v);
        if (auto v = take<bool>(keys, "allow_distortion")) o.allow_distortion = *v;
        const tpmsfill::FillOptions f =
            tpmsfill::read_recipe(recipe_text(recipe, keys), "conformal()");
        o.design = f.design;
        o.grid = f.grid;
        o.keep_islands = f.keep_islands;
        o.check_self_intersections = f.check_self_intersections;
        o.memory_budget = f.memory_budget;
        o.rounding = tpmsfill::CoordinateRounding::None;
        PythonProgress watch(progress);
        o.progress = &watch;
        tpmsfill::ConformalResult result =
            watched(watch, [&] { return tpmsfill::conformal_fill(surface, o); });
        return mesh_and_report(std::move(result.mesh), tpmsfill::to_json(result));
      },
      py::arg("vertices"), py::arg("faces"), py::arg("height"), py::arg("recipe") = py::none(),
      py::kw_only(), py::arg("progress") = py::none(),
      "A lattice layer `height` mm thick on a freeform surface (seed 004), as `tpmsfill "
      "conformal`: (vertices, faces, report). The surface is an open disk or tube; the lattice "
      "is a recipe with keyword arguments as fill()'s (in the layer's flat coordinates), and "
      "side ('out'/'in'), normal_scale, length_u, length_v, skin_surface, skin_top, map "
      "('field'/'vertex'), layout ('auto'/'square'/'free'), allow_distortion.");
}
