// ITDF version 1: writer and reader (layout in docs/formats.md, "ITDF").
#include "tpmsfill/scan/itdf.hpp"

#include <zlib.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "io/binary_io.hpp"
#include "io/file_bytes.hpp"
#include "io/parse_errors.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/io.hpp"

namespace tpmsfill {
namespace {

using detail::Reader;
using detail::Writer;

constexpr char kMagic[4] = {'I', 'T', 'D', 'F'};
constexpr std::uint16_t kVersion = 1;
constexpr std::size_t kFitRecordBytes = 76;
constexpr std::size_t kMaxProvenance = 64 * 1024;
constexpr int kMaxDegree = 7;
constexpr double kQuantMax = 32767;

void write_function(Writer& w, const Threshold& f, const CoefficientEncoding& encoding) {
  if (!f.spline) {
    w.put<std::uint8_t>(0);
    w.put<double>(f.constant);
    return;
  }
  const BSplineVolume& s = *f.spline;
  w.put<std::uint8_t>(1);
  for (int a = 0; a < 3; ++a) w.put<std::uint8_t>(static_cast<std::uint8_t>(s.degree));
  for (int a = 0; a < 3; ++a) w.put<std::uint32_t>(static_cast<std::uint32_t>(s.counts[a]));
  bool uniform = true;
  for (int a = 0; a < 3; ++a)
    uniform = uniform && s.knots[a] == clamped_uniform_knots(s.counts[a], s.degree);
  w.put<std::uint8_t>(uniform ? 0 : 1);
  if (!uniform)
    for (int a = 0; a < 3; ++a)
      for (double k : s.knots[a]) w.put<double>(k);
  w.put<std::uint8_t>(static_cast<std::uint8_t>(encoding.type));
  switch (encoding.type) {
    case CoefficientType::Float32:
      for (double c : s.coefficients) w.put<float>(static_cast<float>(c));
      break;
    case CoefficientType::Float64:
      for (double c : s.coefficients) w.put<double>(c);
      break;
    case CoefficientType::Int16: {
      double scale = encoding.scale, offset = encoding.offset;
      if (!(scale > 0)) {
        const auto [lo, hi] = std::minmax_element(s.coefficients.begin(), s.coefficients.end());
        offset = 0.5 * (*lo + *hi);
        scale = std::max(0.5 * (*hi - *lo) / kQuantMax, std::numeric_limits<double>::min());
      }
      w.put<double>(scale);
      w.put<double>(offset);
      for (double c : s.coefficients) {
        const double q = std::round((c - offset) / scale);
        if (!(std::fabs(q) <= kQuantMax))
          throw InputError("a coefficient lies outside the int16 range of its scale and offset");
        w.put<std::int16_t>(static_cast<std::int16_t>(q));
      }
      break;
    }
  }
}

void write_fit(Writer& w, const std::optional<FitRecord>& fit) {
  if (!fit) {
    w.put<std::uint32_t>(0);
    return;
  }
  w.put<std::uint32_t>(kFitRecordBytes);
  w.put<std::uint8_t>(fit->lspia ? 1 : 0);
  for (int i = 0; i < 3; ++i) w.put<std::uint8_t>(0);
  for (int a = 0; a < 3; ++a) w.put<std::uint32_t>(static_cast<std::uint32_t>(fit->source_dims[a]));
  w.put<std::uint32_t>(static_cast<std::uint32_t>(fit->iterations));
  for (double x : {fit->rms, fit->max_error, fit->value_min, fit->value_max, fit->iso, fit->flipped,
                   fit->seconds})
    w.put<double>(x);
}

std::vector<double> read_coefficients(Reader& r, std::size_t count, CoefficientEncoding& e,
                                      const std::string& what) {
  const std::size_t type_at = r.at();
  const auto type = r.get<std::uint8_t>(what + "'s coefficient type");
  if (type > 2) r.fail("unknown coefficient type " + std::to_string(type), type_at);
  e.type = static_cast<CoefficientType>(type);
  if (e.type == CoefficientType::Int16) {
    e.scale = r.finite(what + "'s int16 scale");
    e.offset = r.finite(what + "'s int16 offset");
    if (!(e.scale > 0)) r.fail(what + "'s int16 scale is not positive", r.at() - 16);
  }
  const std::size_t size = e.type == CoefficientType::Float32   ? 4
                           : e.type == CoefficientType::Float64 ? 8
                                                                : 2;
  r.need(std::uint64_t(count) * size, what + "'s " + std::to_string(count) + " coefficients");
  std::vector<double> c(count);
  for (std::size_t n = 0; n < count; ++n) {
    const std::size_t at = r.at();
    double v = 0;
    if (e.type == CoefficientType::Float32)
      v = r.get<float>("a coefficient");
    else if (e.type == CoefficientType::Float64)
      v = r.get<double>("a coefficient");
    else
      v = e.offset + e.scale * r.get<std::int16_t>("a coefficient");
    if (!std::isfinite(v))
      r.fail(what + "'s coefficient " + std::to_string(n) + " is not finite", at);
    c[n] = v;
  }
  return c;
}

Threshold read_function(Reader& r, CoefficientEncoding& e, const std::string& what) {
  const std::size_t kind_at = r.at();
  const auto kind = r.get<std::uint8_t>(what + "'s kind");
  Threshold f;
  if (kind == 0) {
    f.constant = r.get<double>(what + "'s constant");
    if (std::isnan(f.constant)) r.fail(what + "'s constant is not a number", r.at() - 8);
    return f;
  }
  if (kind != 1) r.fail(what + " has unknown kind " + std::to_string(kind), kind_at);
  BSplineVolume s;
  std::array<int, 3> degree{};
  for (int a = 0; a < 3; ++a) degree[a] = r.get<std::uint8_t>(what + "'s degrees");
  if (degree[0] != degree[1] || degree[1] != degree[2] || degree[0] < 1 || degree[0] > kMaxDegree)
    r.fail(what + " has degrees " + std::to_string(degree[0]) + ", " + std::to_string(degree[1]) +
               ", " + std::to_string(degree[2]) + ": version 1 reads one degree of 1 to 7",
           kind_at + 1);
  s.degree = degree[0];
  std::uint64_t count = 1;
  for (int a = 0; a < 3; ++a) {
    const std::size_t at = r.at();
    const auto n = r.get<std::uint32_t>(what + "'s counts");
    if (n <= std::uint32_t(s.degree) || n > (1u << 20))
      r.fail(what + " has " + std::to_string(n) + " coefficients along an axis (degree " +
                 std::to_string(s.degree) + ")",
             at);
    s.counts[a] = static_cast<int>(n);
    count *= n;
  }
  // The cheapest a coefficient can be stored is 2 bytes: refuse counts the file cannot hold.
  if (count > r.left() / 2)
    r.fail(what + " declares " + std::to_string(count) + " coefficients, more than the file holds");
  const std::size_t knots_at = r.at();
  const auto knot_kind = r.get<std::uint8_t>(what + "'s knot kind");
  for (int a = 0; a < 3; ++a) {
    if (knot_kind == 0) {
      s.knots[a] = clamped_uniform_knots(s.counts[a], s.degree);
    } else if (knot_kind == 1) {
      const std::size_t n = std::size_t(s.counts[a] + s.degree + 1);
      r.need(n * 8, what + "'s knots");
      for (std::size_t i = 0; i < n; ++i) s.knots[a].push_back(r.finite(what + "'s knot"));
    } else {
      r.fail(what + " has unknown knot kind " + std::to_string(knot_kind), knots_at);
    }
  }
  s.coefficients = read_coefficients(r, static_cast<std::size_t>(count), e, what);
  f.spline = std::move(s);
  return f;
}

std::optional<FitRecord> read_fit(Reader& r) {
  const std::size_t at = r.at();
  const auto length = r.get<std::uint32_t>("the fit record's length");
  if (length == 0) return std::nullopt;
  if (length != kFitRecordBytes)
    r.fail("the fit record has " + std::to_string(length) + " bytes, not " +
               std::to_string(kFitRecordBytes),
           at);
  r.need(length, "the fit record");
  FitRecord f;
  f.lspia = r.get<std::uint8_t>("the fit method") == 1;
  r.take(3, "the fit record");
  for (int a = 0; a < 3; ++a)
    f.source_dims[a] =
        static_cast<int>(std::min<std::uint32_t>(r.get<std::uint32_t>("dims"), 1u << 30));
  f.iterations =
      static_cast<int>(std::min<std::uint32_t>(r.get<std::uint32_t>("iterations"), 1u << 30));
  for (double* x :
       {&f.rms, &f.max_error, &f.value_min, &f.value_max, &f.iso, &f.flipped, &f.seconds})
    *x = r.finite("a fit figure");
  return f;
}

}  // namespace

bool looks_like_itdf(std::string_view bytes) {
  return bytes.size() >= 4 && std::memcmp(bytes.data(), kMagic, 4) == 0;
}

std::string itdf_bytes(const ItdfFile& file) {
  const PorousStructure& s = file.structure;
  require_valid(s);
  if (file.provenance.size() >= kMaxProvenance)
    throw InputError("the provenance line is over 64 KiB");
  Writer w;
  w.put_bytes(std::string_view(kMagic, 4));
  w.put<std::uint16_t>(kVersion);
  w.put<std::uint8_t>(s.type == StructureType::Solid ? 0 : 1);
  w.put<std::uint8_t>(s.sign == FieldSign::Unknown ? 0 : s.sign == FieldSign::Signed ? 1 : 2);
  w.put<std::uint8_t>(s.placement == Placement::Stretch ? 0 : 1);
  w.put<std::uint8_t>(s.type == StructureType::Solid ? 3 : 2);
  w.put<std::uint16_t>(0);
  for (double l : s.size) w.put<double>(l);
  w.put<double>(s.sheet_thickness);
  write_function(w, {0, s.field}, file.encoding[0]);
  if (s.type == StructureType::Solid) {
    write_function(w, s.t1, file.encoding[2]);
    write_function(w, s.t2, file.encoding[3]);
  } else {
    write_function(w, s.t0, file.encoding[1]);
  }
  write_fit(w, file.fit);
  w.put<std::uint32_t>(static_cast<std::uint32_t>(file.provenance.size()));
  w.put_bytes(file.provenance);
  w.put_crc32();
  return w.bytes();
}

void write_itdf(const std::filesystem::path& path, const ItdfFile& file) {
  write_file_atomically(path, itdf_bytes(file));
}

ItdfFile parse_itdf(std::string_view bytes, const std::string& source) {
  Reader r = detail::open_framed(bytes, source, std::string_view(kMagic, 4), "an ITDF file", "ITDF",
                                 kVersion, 10);
  ItdfFile file;
  PorousStructure& s = file.structure;
  const auto type = r.get<std::uint8_t>("the structure type");
  const auto sign = r.get<std::uint8_t>("the sign convention");
  const auto placement = r.get<std::uint8_t>("the placement");
  const auto functions = r.get<std::uint8_t>("the function count");
  if (type > 1) r.fail("unknown structure type " + std::to_string(type), 6);
  if (sign > 2) r.fail("unknown sign convention " + std::to_string(sign), 7);
  if (placement > 1) r.fail("unknown placement " + std::to_string(placement), 8);
  s.type = type == 0 ? StructureType::Solid : StructureType::Surface;
  s.sign = sign == 0 ? FieldSign::Unknown : sign == 1 ? FieldSign::Signed : FieldSign::Unsigned;
  s.placement = placement == 0 ? Placement::Stretch : Placement::Tile;
  if (functions != (type == 0 ? 3 : 2))
    r.fail(std::to_string(functions) + " functions for a " +
               std::string(structure_type_name(s.type)) + " structure",
           9);
  r.take(2, "the header");
  for (double& l : s.size) l = r.finite("the size");
  s.sheet_thickness = r.finite("the sheet thickness");
  const std::size_t c_at = r.at();
  Threshold c = read_function(r, file.encoding[0], "C");
  if (!c.spline) r.fail("C is a constant: it must be a B-spline", c_at);
  s.field = std::move(*c.spline);
  if (s.type == StructureType::Solid) {
    s.t1 = read_function(r, file.encoding[2], "t1");
    s.t2 = read_function(r, file.encoding[3], "t2");
  } else {
    s.t0 = read_function(r, file.encoding[1], "t0");
  }
  file.fit = read_fit(r);
  const auto length = r.get<std::uint32_t>("the provenance's length");
  if (length >= kMaxProvenance) r.fail("the provenance is over 64 KiB", r.at() - 4);
  file.provenance = std::string(r.take(length, "the provenance"));
  detail::check_crc32(r, bytes);
  try {
    require_valid(s);
  } catch (const InputError& e) {
    throw InputError(source + ": " + e.what());
  }
  return file;
}

ItdfFile read_itdf(const std::filesystem::path& path) {
  return parse_itdf(detail::read_file_bytes(path, std::uint64_t{1} << 32), path.string());
}

ItdfFile fit_field(const ScalarVolume& v, std::array<int, 3> counts, const FitOptions& options) {
  require_valid(v);
  for (int ax = 0; ax < 3; ++ax)
    if (counts[ax] == 0) counts[ax] = std::max(options.degree + 1, (v.dims[ax] + 1) / 2);
  const auto t0 = std::chrono::steady_clock::now();
  FitResult fit = fit_bspline(v.values, v.dims, counts, options);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ItdfFile file;
  PorousStructure& s = file.structure;
  s.field = std::move(fit.volume);
  s.sign = v.sign;
  if (v.has_physical_size())
    for (int ax = 0; ax < 3; ++ax) s.size[ax] = v.spacing[ax] * v.dims[ax];
  s.t2 = {0};
  const auto [lo, hi] = std::minmax_element(v.values.begin(), v.values.end());
  const std::vector<double> c = evaluate_bspline_grid(s.field, v.dims);
  std::size_t flips = 0;
  for (std::size_t n = 0; n < c.size(); ++n) flips += (c[n] >= 0) != (v.values[n] >= 0);
  file.fit = FitRecord{.lspia = options.method == FitMethod::Lspia,
                       .source_dims = v.dims,
                       .iterations = fit.report.iterations,
                       .rms = fit.report.rms,
                       .max_error = fit.report.max_error,
                       .value_min = *lo,
                       .value_max = *hi,
                       .iso = 0,
                       .flipped = double(flips) / double(c.size()),
                       .seconds = seconds};
  return file;
}

ItdfFile read_structure(const std::filesystem::path& path) {
  if (detail::lower_extension(path) == ".itdf") return read_itdf(path);
  const VolumeFile field = read_volume_file(path);
  if (field.volume.sign != FieldSign::Signed)
    throw InputError(path.string() + " holds an " +
                     std::string(field_sign_name(field.volume.sign)) +
                     " field: fit it with its structure first (tpmsfill field fit " +
                     path.string() + " OUT.itdf --solid T1 T2, or --surface T0)");
  ItdfFile file = fit_field(field.volume, {0, 0, 0}, {});
  file.provenance = "fitted on reading " + path.string();
  return file;
}

}  // namespace tpmsfill
