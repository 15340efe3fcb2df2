// The Python module `tpmsfill` (issue 42): numpy arrays in, plain Python values out, the
// library's exceptions as Python exceptions of the same names. Like the CLI, it only converts:
// the work is the library's, done with the GIL released.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <memory>
#include <string>
#include <tpmsfill/check.hpp>
#include <tpmsfill/error.hpp>
#include <tpmsfill/fill.hpp>
#include <tpmsfill/recipe.hpp>
#include <tpmsfill/report.hpp>
#include <tpmsfill/types.hpp>
#include <utility>

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
      [](const py::array_t<double, py::array::c_style | py::array::forcecast>& vertices,
         const py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>& faces,
         const py::object& recipe, const py::kwargs& options) {
        // One recipe: the dict given, its top-level keys replaced by the keyword arguments.
        py::dict merged;
        if (!recipe.is_none())  // a copy: the caller's dict stays as it was
          merged = py::module_::import("builtins").attr("dict")(recipe).cast<py::dict>();
        for (const auto& [key, value] : options) merged[key] = value;
        const std::string text =
            py::module_::import("json").attr("dumps")(merged).cast<std::string>();
        const tpmsfill::TriangleSoup soup = soup_from(vertices, faces);
        const tpmsfill::FillOptions o = tpmsfill::read_recipe(text, "fill()");
        tpmsfill::FillResult result;
        {
          py::gil_scoped_release release;
          result = tpmsfill::fill(soup, o);
        }
        const std::string report = tpmsfill::to_json(result.report);
        py::tuple mesh = arrays_of(std::move(result.mesh));
        return py::make_tuple(mesh[0], mesh[1], from_json(report));
      },
      py::arg("vertices"), py::arg("faces"), py::arg("recipe") = py::none(),
      "Fills a closed mesh with a TPMS lattice clipped to it: (vertices, faces, report).\n\n"
      "The job is a recipe (docs/recipes.md): a dict, its top-level keys given or replaced as "
      "keyword arguments, e.g. fill(v, f, voxel=0.1, lattice={'type': 'gyroid', 'cell': 2}). "
      "The output is validated (closed, 2-manifold, outward, no self-intersections) before it "
      "is returned; vertices (n, 3) float64 and faces (m, 3) uint32 share its memory. Raises "
      "tpmsfill.InputError for a bad recipe (a key it does not know, a value out of range) or "
      "a model that cannot hold the lattice asked.");
}
