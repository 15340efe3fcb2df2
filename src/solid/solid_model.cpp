// The solid spline model file, version 1 (solid_model.hpp; layout in docs/formats.md).
#include "tpmsfill/solid/solid_model.hpp"

#include <zlib.h>

#include <algorithm>
#include <cstring>
#include <string>
#include <tuple>

#include "io/binary_io.hpp"
#include "io/file_bytes.hpp"
#include "solid/internal/octree_cells.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/io.hpp"

namespace tpmsfill {
namespace {

using detail::Reader;
using detail::Writer;

constexpr char kMagic[4] = {'T', 'S', 'P', 'L'};
constexpr std::uint16_t kVersion = 1;
constexpr std::size_t kMaxProvenance = 64 * 1024;
constexpr int kMaxLevel = 16;
constexpr std::uint32_t kMaxUniform = 1024;
constexpr std::uint32_t kMaxRounds = 1000;

using detail::cell_less;
using detail::child_cell;

// One bit per octree node, pre-order from the cube: 1 split (children by octant, u fastest),
// 0 leaf.
void encode_octree(const std::vector<OctreeCell>& sorted, const OctreeCell& cell,
                   std::vector<bool>& bits) {
  if (std::binary_search(sorted.begin(), sorted.end(), cell, cell_less)) {
    bits.push_back(false);
    return;
  }
  if (cell.level >= kMaxLevel) throw InputError("the spline's elements do not form an octree");
  bits.push_back(true);
  for (int o = 0; o < 8; ++o) encode_octree(sorted, child_cell(cell, o), bits);
}

struct BitReader {
  std::string_view bytes;
  std::uint64_t count = 0, at = 0;
};

void decode_octree(Reader& r, BitReader& bits, const OctreeCell& cell,
                   std::vector<OctreeCell>& leaves, std::size_t stream_start) {
  if (bits.at >= bits.count)
    r.fail("the octree's bits end inside the octree", stream_start + bits.at / 8);
  const bool split = (static_cast<unsigned char>(bits.bytes[bits.at / 8]) >> (bits.at % 8)) & 1;
  ++bits.at;
  if (!split) {
    leaves.push_back(cell);
    return;
  }
  if (cell.level >= kMaxLevel)
    r.fail("the octree is deeper than 16 levels", stream_start + (bits.at - 1) / 8);
  for (int o = 0; o < 8; ++o) decode_octree(r, bits, child_cell(cell, o), leaves, stream_start);
}

bool is_uniform(const SplineBasis& basis) {
  return basis.spans.size() == 1 && basis.spans[0] != 1;
}

void write_round(Writer& w, const FitRound& r) {
  for (std::uint64_t n : {std::uint64_t(r.control_points), std::uint64_t(r.elements)})
    w.put<std::uint64_t>(n);
  w.put<std::int32_t>(r.geometry_iterations);
  w.put<std::int32_t>(r.material_iterations);
  for (double x : {r.geometry_rs, r.material_rs, r.geometry_rms, r.geometry_max, r.material_rms,
                   r.material_max})
    w.put<double>(x);
  for (std::uint64_t n :
       {std::uint64_t(r.folded_samples), std::uint64_t(r.samples), std::uint64_t(r.split)})
    w.put<std::uint64_t>(n);
  w.put<double>(r.seconds);
}

FitRound read_round(Reader& r) {
  FitRound f;
  f.control_points = r.get<std::uint64_t>("a round's control points");
  f.elements = r.get<std::uint64_t>("a round's elements");
  f.geometry_iterations = r.get<std::int32_t>("a round's iterations");
  f.material_iterations = r.get<std::int32_t>("a round's iterations");
  for (double* x : {&f.geometry_rs, &f.material_rs, &f.geometry_rms, &f.geometry_max,
                    &f.material_rms, &f.material_max})
    *x = r.finite("a round's figures");
  f.folded_samples = r.get<std::uint64_t>("a round's folded samples");
  f.samples = r.get<std::uint64_t>("a round's samples");
  f.split = r.get<std::uint64_t>("a round's split leaves");
  f.seconds = r.finite("a round's time");
  return f;
}

}  // namespace

std::string solid_model_bytes(const SolidModel& model) {
  const SolidSpline& s = model.fit.spline;
  const std::size_t n = s.basis.functions.size();
  if (s.geometry.size() != n || (!s.material.empty() && s.material.size() != n))
    throw InputError("the spline has " + std::to_string(s.geometry.size()) +
                     " control points for " + std::to_string(n) + " basis functions");
  if (s.basis.kind == SplineKind::tspline)
    throw InputError("a model on T-splines has no file form (material fit fits THB)");
  if (model.provenance.size() >= kMaxProvenance)
    throw InputError("the provenance line is over 64 KiB");
  Writer w;
  w.put_bytes(std::string_view(kMagic, 4));
  w.put<std::uint16_t>(kVersion);
  const bool uniform = is_uniform(s.basis);
  w.put<std::uint8_t>(uniform ? 1 : 0);
  w.put<std::uint8_t>(s.material.empty() ? 0 : 1);
  if (uniform) {
    w.put<std::uint32_t>(s.basis.spans[0] + 3);
  } else {
    std::vector<OctreeCell> sorted = s.basis.elements;
    std::sort(sorted.begin(), sorted.end(), cell_less);
    std::vector<bool> bits;
    encode_octree(sorted, {0, {0, 0, 0}}, bits);
    w.put<std::uint32_t>(static_cast<std::uint32_t>(bits.size()));
    std::string packed((bits.size() + 7) / 8, '\0');
    for (std::size_t b = 0; b < bits.size(); ++b)
      if (bits[b]) packed[b / 8] = static_cast<char>(packed[b / 8] | (1 << (b % 8)));
    w.put_bytes(packed);
  }
  w.put<std::uint32_t>(static_cast<std::uint32_t>(n));
  for (const Vec3& p : s.geometry)
    for (double x : {p.x, p.y, p.z}) w.put<double>(x);
  for (double m : s.material) w.put<double>(m);
  w.put<double>(model.fit.greville_geometry_rms);
  w.put<double>(model.fit.greville_material_rms);
  w.put<std::uint32_t>(static_cast<std::uint32_t>(model.fit.rounds.size()));
  for (const FitRound& r : model.fit.rounds) write_round(w, r);
  w.put<std::uint32_t>(static_cast<std::uint32_t>(model.provenance.size()));
  w.put_bytes(model.provenance);
  w.put_crc32();
  return w.bytes();
}

void write_solid_model(const std::filesystem::path& path, const SolidModel& model) {
  write_file_atomically(path, solid_model_bytes(model));
}

bool looks_like_solid_model(std::string_view bytes) {
  return bytes.size() >= 4 && std::memcmp(bytes.data(), kMagic, 4) == 0;
}

SolidModel parse_solid_model(std::string_view bytes, const std::string& source) {
  Reader r = detail::open_framed(bytes, source, std::string_view(kMagic, 4), "a solid spline model",
                                 "a solid spline model of", kVersion, 12);
  const auto kind = r.get<std::uint8_t>("the basis kind");
  const auto material = r.get<std::uint8_t>("the material flag");
  if (kind > 1) r.fail("unknown basis kind " + std::to_string(kind), 6);
  if (material > 1) r.fail("the material flag is " + std::to_string(material) + ", not 0 or 1", 7);
  SolidModel model;
  SolidSpline& s = model.fit.spline;
  const std::size_t basis_at = r.at();
  const auto parameter =
      r.get<std::uint32_t>(kind ? "the control points per axis" : "the octree's bit count");
  if (kind == 1) {
    if (parameter < 4 || parameter > kMaxUniform)
      r.fail("a uniform basis of " + std::to_string(parameter) + " per axis (4 to 1024)", basis_at);
    // Its control points must be in the file before the basis is built (512³ would take GBs).
    const std::uint64_t n = std::uint64_t(parameter) * parameter * parameter;
    r.need(4 + n * (material ? 32 : 24),
           "the control points of a uniform basis of " + std::to_string(parameter) + " per axis");
    s.basis = tensor_basis(static_cast<int>(parameter));
  } else {
    const std::size_t stream_at = r.at();
    BitReader bits{r.take((std::uint64_t(parameter) + 7) / 8, "the octree's bits"), parameter, 0};
    CubeOctree octree;
    decode_octree(r, bits, {0, {0, 0, 0}}, octree.leaves, stream_at);
    if (bits.at != bits.count)
      r.fail(std::to_string(bits.count - bits.at) + " octree bits left over",
             stream_at + bits.at / 8);
    for (const OctreeCell& c : octree.leaves) octree.deepest = std::max(octree.deepest, c.level);
    s.basis = thb_basis(octree);
  }
  const std::size_t count_at = r.at();
  const auto n = r.get<std::uint32_t>("the control point count");
  if (n != s.basis.functions.size())
    r.fail(std::to_string(n) + " control points for a basis of " +
               std::to_string(s.basis.functions.size()) + " functions",
           count_at);
  r.need(std::uint64_t(n) * (material ? 32 : 24), "the control points");
  s.geometry.resize(n);
  for (Vec3& p : s.geometry)
    p = {r.finite("a control point"), r.finite("a control point"), r.finite("a control point")};
  if (material) {
    s.material.resize(n);
    for (double& m : s.material) m = r.finite("a material control value");
  }
  model.fit.greville_geometry_rms = r.finite("the start's error");
  model.fit.greville_material_rms = r.finite("the start's error");
  const std::size_t rounds_at = r.at();
  const auto rounds = r.get<std::uint32_t>("the round count");
  if (rounds > kMaxRounds) r.fail(std::to_string(rounds) + " rounds (at most 1000)", rounds_at);
  for (std::uint32_t k = 0; k < rounds; ++k) model.fit.rounds.push_back(read_round(r));
  const auto length = r.get<std::uint32_t>("the provenance's length");
  if (length >= kMaxProvenance) r.fail("the provenance is over 64 KiB", r.at() - 4);
  model.provenance = std::string(r.take(length, "the provenance"));
  detail::check_crc32(r, bytes);
  return model;
}

SolidModel read_solid_model(const std::filesystem::path& path) {
  return parse_solid_model(detail::read_file_bytes(path, std::uint64_t{1} << 34), path.string());
}

}  // namespace tpmsfill
