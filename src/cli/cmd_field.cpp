// `tpmsfill field fit|info|mesh`: seed 003's porous structures. A scanned distance field (or
// CT) is fitted by an implicit B-spline and stored with its structure as a compact ITDF file,
// described, or meshed. This file only parses, calls the library and prints.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <tpmsfill/error.hpp>
#include <tpmsfill/fill.hpp>
#include <tpmsfill/io.hpp>
#include <tpmsfill/io/volume.hpp>
#include <tpmsfill/lattice/design.hpp>
#include <tpmsfill/scan/itdf.hpp>
#include <tpmsfill/scan/scanned_field.hpp>
#include <vector>

#include "cli/commands.hpp"
#include "cli/job_files.hpp"
#include "cli/printable.hpp"
#include "cli/ramp_along.hpp"
#include "cli/terminal_progress.hpp"
#include "cli/validators.hpp"
#include "core/names.hpp"
#include "io/file_bytes.hpp"

namespace tpmsfill::cli {
namespace {

// The structure flags fit and mesh share: --solid T1 T2 | --surface T0, --thickness, --porosity.
struct StructureArgs {
  std::vector<std::string> solid, threshold_file, threshold_ramp;
  int threshold_coefficients = 6;
  std::optional<double> surface, thickness, porosity;
  std::vector<double> size;
  bool tile = false, stretch = false;
};

struct FieldArgs {
  std::string input, output, report;
  StructureArgs structure;
  std::vector<int> coefficients;
  std::string method = "direct", coefficient_type = "float32";
  std::optional<std::string> sign;
  std::optional<double> iso, voxel;
  int degree = 3, max_iterations = 200;
  double smoothing = FitOptions{}.smoothing;
  bool quiet = false, keep_islands = false, below = false;
  int padding = 2;
};

double threshold_number(const std::string& text) {
  if (text == "inf" || text == "+inf") return INFINITY;
  if (text == "-inf") return -INFINITY;
  std::size_t used = 0;
  double v = NAN;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
  }
  if (used != text.size() || !std::isfinite(v))
    throw InputError("--solid: '" + text + "' is not a number, inf or -inf");
  return v;
}

std::array<double, 3> box_size(const std::vector<double>& v) {
  return {v[0], v[1], v[2]};
}

// What a structure's unit cube spans when its porosity or ramps are measured: its size, or the
// unit cube itself when it has none.
std::array<double, 3> extent_of(const PorousStructure& s) {
  return s.size[0] > 0 ? s.size : std::array<double, 3>{1, 1, 1};
}

constexpr tpmsfill::detail::Named<CoefficientType> kCoefficientTypes[] = {
    {CoefficientType::Float32, "float32"},
    {CoefficientType::Float64, "float64"},
    {CoefficientType::Int16, "int16"}};

// The flags over `s` (a fresh fit's defaults, or what a file stores).
void apply_structure(const StructureArgs& a, PorousStructure& s) {
  if (!a.solid.empty() && a.surface) throw InputError("give --solid or --surface, not both");
  if (!a.solid.empty()) {
    s.type = StructureType::Solid;
    s.t1 = {threshold_number(a.solid[0])};
    s.t2 = {threshold_number(a.solid[1])};
  }
  if (a.surface) {
    s.type = StructureType::Surface;
    s.t0 = {*a.surface};
  }
  if (a.thickness) {
    if (s.type != StructureType::Surface)
      throw InputError("--thickness is the sheet thickness of a --surface structure");
    s.sheet_thickness = *a.thickness;
  }
  if (!a.size.empty()) s.size = box_size(a.size);
  if (a.tile && a.stretch) throw InputError("give --tile or --stretch, not both");
  if (a.tile) s.placement = Placement::Tile;
  if (a.stretch) s.placement = Placement::Stretch;
  // Thresholds of their own: a discrete grid (seed claim 6) or a ramp, each fitted small.
  auto slot = [&](const std::string& name, const char* flag) -> Threshold& {
    if (name == "t0" || name == "t1" || name == "t2")
      return name == "t0" ? s.t0 : name == "t1" ? s.t1 : s.t2;
    throw InputError(std::string(flag) + ": '" + name + "' is not t0, t1 or t2");
  };
  const int n = a.threshold_coefficients;
  for (std::size_t i = 0; i + 1 < a.threshold_file.size(); i += 2)
    slot(a.threshold_file[i], "--threshold-file") =
        fitted_threshold(read_volume_file(a.threshold_file[i + 1]).volume, {n, n, n});
  for (std::size_t i = 0; i + 3 < a.threshold_ramp.size(); i += 4) {
    Ramp ramp = ramp_along(a.threshold_ramp[i + 3], "--threshold-ramp");
    try {
      ramp.start = std::stod(a.threshold_ramp[i + 1]);
      ramp.end = std::stod(a.threshold_ramp[i + 2]);
    } catch (const std::exception&) {
      throw InputError("--threshold-ramp " + a.threshold_ramp[i] + ": '" + a.threshold_ramp[i + 1] +
                       " " + a.threshold_ramp[i + 2] + "' are not two numbers");
    }
    slot(a.threshold_ramp[i], "--threshold-ramp") = ramp_threshold(ramp, extent_of(s), n);
  }
  require_valid(s);
}

std::string kib(std::uint64_t bytes) {
  char b[32];
  std::snprintf(b, sizeof b, bytes < 10 << 20 ? "%.1f KiB" : "%.1f MiB",
                bytes < 10 << 20 ? bytes / 1024.0 : bytes / 1048576.0);
  return b;
}

// "12.3x smaller" or "1.8x larger": `ours` beside `theirs`, said the way round it is.
std::string size_ratio(std::uint64_t ours, std::uint64_t theirs) {
  char b[48];
  const double o = std::max<double>(ours, 1), t = std::max<double>(theirs, 1);
  std::snprintf(b, sizeof b, o <= t ? "%.1fx smaller" : "%.1fx larger", o <= t ? t / o : o / t);
  return b;
}

// The iso-value whose side changes the fit's report counts: --iso, else the structure's first
// finite threshold.
double report_iso(const FieldArgs& a, const PorousStructure& s) {
  if (a.iso) return *a.iso;
  if (s.type == StructureType::Surface) return s.t0.constant;
  return std::isfinite(s.t2.constant)   ? s.t2.constant
         : std::isfinite(s.t1.constant) ? s.t1.constant
                                        : 0;
}

int run_fit(const FieldArgs& a) {
  if (a.output.empty()) throw InputError("field fit needs IN and OUT.itdf");
  if (tpmsfill::detail::lower_extension(a.output) != ".itdf")
    throw InputError(a.output +
                     ": field fit writes an ITDF file, named .itdf (to mesh it, run "
                     "`tpmsfill field mesh OUT.itdf MESH.stl` after the fit)");
  if (a.coefficients.size() == 2)
    throw InputError("--coefficients takes one count, or three (NX NY NZ), not two");
  require_writable_outputs({a.input}, {{"OUT", a.output}});
  const auto t0 = std::chrono::steady_clock::now();
  const VolumeFile in = read_volume_file(a.input);
  print_warnings(in.warnings);
  const ScalarVolume& v = in.volume;
  std::array<int, 3> counts{};
  for (int ax = 0; ax < 3; ++ax)
    counts[ax] = a.coefficients.empty()       ? 0
                 : a.coefficients.size() == 1 ? a.coefficients[0]
                                              : a.coefficients[ax];
  FitOptions fo;
  fo.method = a.method == "lspia" ? FitMethod::Lspia : FitMethod::Direct;
  fo.degree = a.degree;
  fo.smoothing = a.smoothing;
  fo.max_iterations = a.max_iterations;
  ItdfFile file = fit_field(v, counts, fo);
  for (int ax = 0; ax < 3; ++ax) counts[ax] = file.structure.field.counts[ax];
  PorousStructure& s = file.structure;
  if (a.sign) s.sign = field_sign_from_name(*a.sign);
  const StructureArgs& st = a.structure;
  if (st.solid.empty() && !st.surface && s.sign != FieldSign::Signed)
    throw InputError("an " + std::string(field_sign_name(s.sign)) +
                     " field needs a structure: --solid T1 T2 (e.g. --solid 0 0.5 thickens a "
                     "scanned surface; --solid 2.9 inf keeps CT values above 2.9) or --surface T0");
  apply_structure(st, s);
  if (st.porosity) s = with_porosity(s, *st.porosity, extent_of(s));

  const auto [lo, hi] = std::minmax_element(v.values.begin(), v.values.end());
  const double iso = report_iso(a, s);
  const std::vector<double> c = evaluate_bspline_grid(s.field, v.dims);
  std::size_t flips = 0;
  for (std::size_t n = 0; n < c.size(); ++n) flips += (c[n] >= iso) != (v.values[n] >= iso);
  file.fit->iso = iso;
  file.fit->flipped = double(flips) / double(c.size());
  const FitRecord& fit = *file.fit;
  const double fit_seconds = fit.seconds;
  file.encoding[0].type =
      tpmsfill::detail::from_name(kCoefficientTypes, a.coefficient_type, "coefficient type");
  file.provenance = "tpmsfill " TPMSFILL_VERSION " field fit of " + a.input + " (sha256 " +
                    sha256_of_file(a.input) + ")";
  const std::string bytes = itdf_bytes(file);
  write_file_atomically(a.output, bytes);

  if (!a.quiet) {
    const double range = std::max(*hi - *lo, 1e-300);
    std::printf("%s -> %s\n", a.input.c_str(), a.output.c_str());
    std::printf("grid         %d x %d x %d %s (%s), %s\n", v.dims[0], v.dims[1], v.dims[2],
                in.element_type.c_str(), std::string(volume_format_name(in.format)).c_str(),
                std::string(field_sign_name(s.sign)).c_str());
    std::printf("spline       %d x %d x %d coefficients, degree %d (%s, %.3g s%s)\n", counts[0],
                counts[1], counts[2], a.degree, a.method.c_str(), fit_seconds,
                fo.method == FitMethod::Lspia
                    ? (", " + std::to_string(fit.iterations) + " iterations").c_str()
                    : "");
    std::printf("error        RMS %.4g (%.2f %% of the range %.4g), max %.4g\n", fit.rms,
                100 * fit.rms / range, *hi - *lo, fit.max_error);
    std::printf("iso %-8.4g %.3f %% of the cells changed side (%zu)\n", iso,
                100 * file.fit->flipped, flips);
    std::printf("structure    %s\n", structure_label(s).c_str());
    std::printf("size         %s (the grid as float32: %s, %s)\n", kib(bytes.size()).c_str(),
                kib(4 * v.count()).c_str(), size_ratio(bytes.size(), 4 * v.count()).c_str());
    std::printf("time         %.2f s\n",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  if (fit.rms > 0.05 * (*hi - *lo))
    std::fprintf(stderr,
                 "tpmsfill: warning: the fit's RMS error is %.1f %% of the value range: the "
                 "structure will not follow the scan closely; use more --coefficients\n",
                 100 * fit.rms / (*hi - *lo));
  return kOk;
}

bool structure_flags_given(const StructureArgs& a) {
  return !a.solid.empty() || a.surface || a.thickness || a.porosity || !a.size.empty() || a.tile ||
         a.stretch || !a.threshold_file.empty() || !a.threshold_ramp.empty();
}

// Seed 003's "edit further, then print": a stored structure's thresholds, porosity, size,
// placement or coefficient type changed without refitting C, the fit's record kept and the
// provenance extended by what changed.
int run_edit(const FieldArgs& a, bool coefficient_type_given) {
  if (!structure_flags_given(a.structure) && !coefficient_type_given)
    throw InputError(
        "field edit: nothing to change; give --solid, --surface, --thickness, --porosity, "
        "--size, --tile, --stretch, --threshold-file, --threshold-ramp or --coefficient-type");
  const std::string output = a.output.empty() ? a.input : a.output;
  if (tpmsfill::detail::lower_extension(output) != ".itdf")
    throw InputError(output + ": field edit writes an ITDF file, named .itdf");
  if (!a.output.empty()) require_writable_outputs({a.input}, {{"OUT", a.output}});
  ItdfFile file = read_itdf(a.input);
  PorousStructure& s = file.structure;
  const PorousStructure before = s;
  const double porosity_before = 1 - porous_solid_share(before, extent_of(before));
  apply_structure(a.structure, s);
  if (a.structure.porosity) s = with_porosity(s, *a.structure.porosity, extent_of(s));
  std::vector<std::string> changes;
  if (structure_label(s) != structure_label(before))
    changes.push_back("structure " + structure_label(before) + " -> " + structure_label(s));
  if (s.size != before.size) {
    char b[96];
    std::snprintf(b, sizeof b, "size %g x %g x %g mm", s.size[0], s.size[1], s.size[2]);
    changes.push_back(b);
  }
  if (s.placement != before.placement)
    changes.push_back("placement " + std::string(placement_name(s.placement)));
  if (coefficient_type_given) {
    const CoefficientType type =
        tpmsfill::detail::from_name(kCoefficientTypes, a.coefficient_type, "coefficient type");
    if (type != file.encoding[0].type)
      changes.push_back(
          "coefficients " +
          std::string(tpmsfill::detail::name_of(kCoefficientTypes, file.encoding[0].type)) +
          " -> " + std::string(tpmsfill::detail::name_of(kCoefficientTypes, type)));
    for (CoefficientEncoding& e : file.encoding) e = {type, 0, 0};  // int16: scale from the values
  }
  std::string what;
  for (const std::string& c : changes) what += (what.empty() ? "" : ", ") + c;
  if (what.empty()) what = "nothing changed";
  file.provenance += (file.provenance.empty() ? "" : "; then ") +
                     std::string("tpmsfill " TPMSFILL_VERSION " field edit: ") + what;
  const std::string bytes = itdf_bytes(file);
  // As written: int16 coefficients move C by up to half a quantum.
  const PorousStructure written = parse_itdf(bytes, output).structure;
  const double porosity_after = 1 - porous_solid_share(written, extent_of(written));
  write_file_atomically(output, bytes);
  if (!a.quiet) {
    std::printf("%s -> %s\n", a.input.c_str(), output.c_str());
    std::printf("edited       %s\n", what.c_str());
    std::printf("porosity     %.4f -> %.4f of the unit cube\n", porosity_before, porosity_after);
  }
  if (changes.empty())
    std::fprintf(stderr, "tpmsfill: warning: field edit: the flags leave %s as it was\n",
                 a.input.c_str());
  return kOk;
}

int run_info(const FieldArgs& a) {
  std::FILE* f = std::fopen(a.input.c_str(), "rb");
  if (!f) throw IoError("cannot open " + a.input);
  char magic[4] = {};
  const std::size_t got = std::fread(magic, 1, 4, f);
  std::fclose(f);
  if (looks_like_itdf(std::string_view(magic, got))) {
    const ItdfFile file = read_itdf(a.input);
    const PorousStructure& s = file.structure;
    const auto& n = s.field.counts;
    std::printf("%s: ITDF version 1\n", a.input.c_str());
    std::printf("structure    %s\n", structure_label(s).c_str());
    std::printf("sign         %s\n", std::string(field_sign_name(s.sign)).c_str());
    std::printf("C            %d x %d x %d coefficients, degree %d\n", n[0], n[1], n[2],
                s.field.degree);
    if (s.size[0] > 0)
      std::printf("size         %g x %g x %g mm, %s\n", s.size[0], s.size[1], s.size[2],
                  std::string(placement_name(s.placement)).c_str());
    else
      std::printf("size         none (stretched over the model)\n");
    if (file.fit)
      std::printf(
          "fit          of %d x %d x %d cells (%s): RMS %.4g, max %.4g, %.3f %% changed side of "
          "%g\n",
          file.fit->source_dims[0], file.fit->source_dims[1], file.fit->source_dims[2],
          file.fit->lspia ? "lspia" : "direct", file.fit->rms, file.fit->max_error,
          100 * file.fit->flipped, file.fit->iso);
    std::printf("porosity     %.4f of the unit cube\n", 1 - porous_solid_share(s, extent_of(s)));
    if (!file.provenance.empty())
      std::printf("provenance   %s\n", printable(file.provenance).c_str());
    return kOk;
  }
  const VolumeFile file = read_volume_file(a.input);
  const ScalarVolume& v = file.volume;
  const auto [lo, hi] = std::minmax_element(v.values.begin(), v.values.end());
  std::printf("%s: %s field, %d x %d x %d %s%s\n", a.input.c_str(),
              std::string(volume_format_name(file.format)).c_str(), v.dims[0], v.dims[1], v.dims[2],
              file.element_type.c_str(), file.compressed ? " (compressed)" : "");
  if (v.has_physical_size())
    std::printf("voxel        %g x %g x %g mm, first centre at (%g, %g, %g)\n", v.spacing[0],
                v.spacing[1], v.spacing[2], v.origin.x, v.origin.y, v.origin.z);
  else
    std::printf("voxel        none (the unit cube)\n");
  std::printf("values       %.6g to %.6g, %s\n", *lo, *hi,
              std::string(field_sign_name(v.sign)).c_str());
  print_warnings(file.warnings);
  return kOk;
}

int run_mesh(const FieldArgs& a) {
  if (a.output.empty()) throw InputError("field mesh needs IN.itdf and OUT");
  if (format_from_extension(a.output) == MeshFormat::Auto)
    throw InputError(unknown_mesh_extension(a.output));
  if (!a.voxel) throw InputError("field mesh needs --voxel (the grid spacing, mm)");
  require_writable_outputs({a.input}, {{"OUT", a.output}});
  const ItdfFile file = read_structure(a.input);
  PorousStructure s = file.structure;
  apply_structure(a.structure, s);
  if (!(s.size[0] > 0))
    throw InputError(a.input + " has no physical size: give --size X Y Z in mm");
  const std::array<double, 3> size = s.size;
  if (s.type == StructureType::Surface && s.sheet_thickness == 0) {
    if (a.structure.porosity) throw InputError("an open surface has no porosity: give --thickness");
    const OpenSurface open =
        porous_surface_mesh(s, Box3{{0, 0, 0}, {size[0], size[1], size[2]}}, *a.voxel);
    write_mesh(a.output, open.mesh);
    if (!a.quiet)
      std::printf(
          "%s -> %s\nopen surface %zu triangles, %llu components, %llu border edges, area %.4g "
          "mm^2\n",
          a.input.c_str(), a.output.c_str(), open.mesh.triangles.size(),
          static_cast<unsigned long long>(open.components),
          static_cast<unsigned long long>(open.border_edges), open.area);
    return kOk;
  }
  FillOptions o;
  o.grid.voxel_size = *a.voxel;
  o.design.structure = s;
  o.design.structure_file = a.input;
  if (a.structure.porosity) o.design.porosity = a.structure.porosity;
  o.measure = false;
  o.keep_islands = a.keep_islands;
  // Validate what the file will hold: a 3MF keeps lib3mf's micrometres, not floats.
  if (rounding_for(format_from_extension(a.output)) == CoordinateRounding::ThreeMf)
    o.rounding = CoordinateRounding::ThreeMf;
  std::unique_ptr<TerminalProgress> progress;
  if (progress_wanted(a.quiet)) progress = std::make_unique<TerminalProgress>();
  o.progress = progress.get();
  FillResult r = fill_box(Box3{{0, 0, 0}, {size[0], size[1], size[2]}}, o);
  if (progress) progress->clear();
  write_mesh(a.output, r.mesh);
  if (!a.quiet) {
    const std::uint64_t itdf = std::filesystem::file_size(a.input),
                        stl = 84 + 50 * r.mesh.triangles.size();
    std::printf("%s -> %s\n%s", a.input.c_str(), a.output.c_str(), to_text(r.report).c_str());
    std::printf("storage      ITDF %s, binary STL %s: %s\n", kib(itdf).c_str(), kib(stl).c_str(),
                size_ratio(itdf, stl).c_str());
  }
  print_warnings(r.report.warnings);
  return kOk;
}

// from-mesh, from-points, from-ct: a field file from data a user has.
int run_from(const FieldArgs& a, const std::string& kind) {
  if (const VolumeFormat f = volume_format_from_extension(a.output);
      f == VolumeFormat::Auto || f == VolumeFormat::MetaImage || f == VolumeFormat::Inr)
    throw InputError(a.output + ": fields are written as .tdf (text), .tdfb (binary) or .nrrd");
  require_writable_outputs({a.input}, {{"OUT", a.output}});
  const auto t0 = std::chrono::steady_clock::now();
  std::unique_ptr<TerminalProgress> progress;
  if (progress_wanted(a.quiet)) progress = std::make_unique<TerminalProgress>();
  const ScannedFieldOptions o{
      .voxel = a.voxel.value_or(0), .padding = a.padding, .progress = progress.get()};
  ScalarVolume v;
  std::string what;
  if (kind == "from-mesh") {
    const MeshFile mesh = read_mesh_file(a.input);
    v = field_from_mesh(mesh.soup, o);
    what = std::to_string(mesh.soup.triangles.size()) + " triangles";
  } else if (kind == "from-points") {
    const std::vector<Vec3> points = read_points(a.input);
    v = field_from_points(points, o);
    what = std::to_string(points.size()) + " points";
  } else {
    if (!a.iso) throw InputError("field from-ct needs --iso (the value at the solid's surface)");
    const VolumeFile ct = read_volume_file(a.input);
    v = field_from_ct(ct.volume, *a.iso, a.below);
    what = "a " + std::to_string(ct.volume.dims[0]) + " x " + std::to_string(ct.volume.dims[1]) +
           " x " + std::to_string(ct.volume.dims[2]) + " CT";
  }
  if (progress) progress->clear();
  write_volume(a.output, v);
  if (!a.quiet) {
    const auto [lo, hi] = std::minmax_element(v.values.begin(), v.values.end());
    std::printf("%s -> %s\n", a.input.c_str(), a.output.c_str());
    std::printf("field        %d x %d x %d cells of %g x %g x %g mm from %s, %s\n", v.dims[0],
                v.dims[1], v.dims[2], v.spacing[0], v.spacing[1], v.spacing[2], what.c_str(),
                std::string(field_sign_name(v.sign)).c_str());
    std::printf("values       %.4g to %.4g mm\n", *lo, *hi);
    std::printf("time         %.2f s\n",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return kOk;
}

void add_structure_flags(CLI::App* sub, StructureArgs& s) {
  sub->add_option("--solid", s.solid,
                  "Solid type t1 <= C <= t2: T1 T2 (inf and -inf open a side, e.g. --solid -inf "
                  "0 is the inside of a signed field, --solid 0 0.3 a scanned surface thickened)")
      ->expected(2);
  sub->add_option("--surface", s.surface,
                  "Surface type C = T0 (an open surface, or a sheet with --thickness)");
  sub->add_option("--thickness", s.thickness, "Sheet thickness of the surface type, mm")
      ->check(positive());
  sub->add_option("--porosity", s.porosity,
                  "Void fraction to reach (0 to 1): shifts the solid's thresholds or sets the "
                  "sheet's thickness")
      ->check(between(1e-6, 1 - 1e-6, "between 0 and 1"));
  sub->add_option("--size", s.size, "Physical size of the unit cube X Y Z, mm")
      ->expected(3)
      ->check(positive());
  sub->add_flag("--tile", s.tile,
                "Tile the structure with --size as its cell instead of stretching it");
  sub->add_flag("--stretch", s.stretch,
                "Stretch the structure over the model's box (the default; undoes a stored "
                "--tile)");
  sub->add_option("--threshold-file", s.threshold_file,
                  "NAME FILE: threshold t0, t1 or t2 from its own field file (any grid of the "
                  "unit cube), fitted with --threshold-coefficients (repeatable)")
      ->expected(2)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  sub->add_option("--threshold-ramp", s.threshold_ramp,
                  "NAME FROM TO WHERE: threshold t0, t1 or t2 going from FROM to TO across the "
                  "cube along x, y, z, radial or radial-x/-y/-z (repeatable), e.g. "
                  "--threshold-ramp t1 -0.1 0.3 z for pores that grow upward")
      ->expected(4)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  sub->add_option("--threshold-coefficients", s.threshold_coefficients,
                  "Coefficients per axis of a threshold's spline (default 6)")
      ->check(between(2, 16, "2 to 16"));
}

}  // namespace

Command add_field_command(CLI::App& app) {
  auto a = std::make_shared<FieldArgs>();
  CLI::App* field = app.add_subcommand(
      "field",
      "Porous structures from a scanned distance field (fit, edit, info, mesh, from-mesh, "
      "from-points, from-ct)");
  field->require_subcommand(1);
  field->footer(
      "Seed 003: a discrete field (a scanned porous sample's distance field, a CT) is fitted by "
      "a trivariate implicit B-spline C, and the structure t1 <= C <= t2 (solid) or C = t0 "
      "(surface) is stored as a compact ITDF file, which `fill --field` and `field mesh` use.\n\n"
      "Examples:\n"
      "  tpmsfill field from-mesh femur.stl femur.tdfb --voxel 0.5\n"
      "  tpmsfill field from-ct skull_2.9.inr skull-distance.nrrd --iso 2.9\n"
      "  tpmsfill field fit skull_2.9.inr bone.itdf --coefficients 32 --solid 2.9 inf\n"
      "  tpmsfill field info bone.itdf\n"
      "  tpmsfill field edit bone.itdf --porosity 0.75\n"
      "  tpmsfill field mesh bone.itdf bone.stl --voxel 1 --porosity 0.7\n"
      "  tpmsfill fill femur.stl femur-bone.stl --field bone.itdf --cell 20 --voxel 0.2");

  CLI::App* fit =
      field->add_subcommand("fit", "Fit a B-spline to a field file and store the structure (ITDF)");
  fit->add_option(
         "IN", a->input,
         "Field: .tdf/.tdfb (the seed's forms), .nrrd/.nhdr, .mha/.mhd, .inr (gzip allowed)")
      ->required();
  fit->add_option("OUT", a->output, "The ITDF file to write")->required();
  fit->add_option("--coefficients", a->coefficients,
                  "Coefficients per axis: N, or NX NY NZ (default: half the grid's cells)")
      ->expected(1, 3);
  fit->add_option("--method", a->method,
                  "direct (exact least squares, default) or lspia (the seed's iteration)")
      ->check(CLI::IsMember({"direct", "lspia"}));
  fit->add_option("--degree", a->degree, "B-spline degree (default 3)")
      ->check(between(1, 7, "1 to 7"));
  fit->add_option("--smoothing", a->smoothing,
                  "Second-difference penalty of the direct solve (default 1e-6)")
      ->check(between(0, 1, "0 to 1"));
  fit->add_option("--max-iterations", a->max_iterations, "LSPIA's iteration limit (default 200)")
      ->check(between(1, 100000, "1 to 100000"));
  fit->add_option("--sign", a->sign,
                  "What the values are: signed (negative in the solid), unsigned or unknown "
                  "(default: the file's)")
      ->check(CLI::IsMember({"signed", "unsigned", "unknown"}));
  fit->add_option(
      "--iso", a->iso,
      "Iso-value whose side changes the report counts (default: the structure's threshold)");
  fit->add_option("--coefficient-type", a->coefficient_type, "float32 (default), float64 or int16")
      ->check(CLI::IsMember({"float32", "float64", "int16"}));
  add_structure_flags(fit, a->structure);
  fit->add_flag("--quiet", a->quiet, "Print nothing but errors and warnings");

  CLI::App* edit = field->add_subcommand(
      "edit",
      "Change a stored structure's thresholds, porosity, size, placement or coefficient type, "
      "without refitting");
  edit->add_option("IN", a->input, "ITDF file")->required()->check(existing_file());
  edit->add_option("OUT", a->output, "The ITDF file to write (default: IN, rewritten atomically)");
  CLI::Option* edit_type =
      edit->add_option("--coefficient-type", a->coefficient_type,
                       "Store C and its thresholds as float32, float64 or int16 (int16 "
                       "quantizes them: about 1/65535 of their range)")
          ->check(CLI::IsMember({"float32", "float64", "int16"}));
  add_structure_flags(edit, a->structure);
  edit->add_flag("--quiet", a->quiet, "Print nothing but errors and warnings");
  edit->footer(
      "The fitted C is kept; what it describes changes. The provenance line gains what was "
      "edited.\n\nExamples:\n"
      "  tpmsfill field edit bone.itdf --porosity 0.75\n"
      "  tpmsfill field edit bone.itdf bone-tiled.itdf --size 5 5 5 --tile\n"
      "  tpmsfill field edit bone.itdf bone-small.itdf --coefficient-type int16");

  CLI::App* info = field->add_subcommand("info", "Describe an ITDF file or a field file");
  info->add_option("FILE", a->input, "ITDF or field file")->required()->check(existing_file());

  CLI::App* mesh = field->add_subcommand(
      "mesh", "Mesh an ITDF structure (or a signed field) over its box (or --size)");
  mesh->add_option("IN", a->input,
                   "ITDF file, or a signed field file (.vdb level set, .nrrd, .tdfb, ...) fitted "
                   "on reading as field fit would")
      ->required()
      ->check(existing_file());
  mesh->add_option("OUT", a->output, "Output mesh (.stl, .obj, .ply, .off, .3mf)")->required();
  mesh->add_option("--voxel", a->voxel, "Grid spacing, mm")->required()->check(positive());
  add_structure_flags(mesh, a->structure);
  mesh->add_flag("--keep-islands", a->keep_islands,
                 "Keep pieces that touch no larger piece (removed by default, as fill does)");
  mesh->add_flag("--quiet", a->quiet, "Print nothing but errors and warnings");

  std::vector<CLI::App*> from;
  for (const char* kind : {"from-mesh", "from-points", "from-ct"}) {
    const std::string k = kind;
    CLI::App* sub = field->add_subcommand(
        kind, k == "from-mesh"     ? "A signed distance field from a mesh (messy ones too)"
              : k == "from-points" ? "An unsigned distance field from a point cloud (PLY, XYZ)"
                                   : "A signed distance field from a CT thresholded at --iso");
    sub->add_option("IN", a->input,
                    k == "from-mesh"     ? "Mesh: STL, OBJ, PLY, OFF (gzip allowed) or 3MF, mm"
                    : k == "from-points" ? "Points: PLY vertices or XYZ text (x y z per line), mm"
                                         : "CT: .nrrd/.nhdr, .mha/.mhd, .inr, .tdf/.tdfb")
        ->required()
        ->check(existing_file());
    sub->add_option("OUT", a->output, "Field file to write: .tdf (text), .tdfb (binary), .nrrd")
        ->required();
    if (k == "from-ct") {
      sub->add_option("--iso", a->iso, "The CT value at the solid's surface (required)");
      sub->add_flag("--below", a->below, "The solid is at or below --iso (default: at or above)");
    } else {
      sub->add_option("--voxel", a->voxel, "Cell size, mm")->required()->check(positive());
      sub->add_option("--padding", a->padding,
                      "Cells beyond the data's box on every side (default 2)")
          ->check(between(2, 1000, "2 to 1000"));
    }
    sub->add_flag("--quiet", a->quiet, "Print nothing but errors and warnings");
    from.push_back(sub);
  }

  return [a, fit, edit, edit_type, info, mesh, from] {
    if (fit->parsed()) return run_fit(*a);
    if (edit->parsed()) return run_edit(*a, edit_type->count() > 0);
    if (info->parsed()) return run_info(*a);
    if (mesh->parsed()) return run_mesh(*a);
    for (CLI::App* sub : from)
      if (sub->parsed()) return run_from(*a, sub->get_name());
    return int(kBadInput);
  };
}

}  // namespace tpmsfill::cli
