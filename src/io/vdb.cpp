// OpenVDB's .vdb files in and out, through OpenVDB itself (Debian's libopenvdb-dev): the one
// source that sees OpenVDB, whose headers take a while to compile. A sparse grid comes in as the
// dense ScalarVolume every field command takes; a fill's lattice goes out as the narrow-band
// level set OpenVDB's own tools (Houdini, Blender, vdb_view) open.
// GCC 12 at -O3 warns falsely (-Wrestrict, GCC bug 105651) inside <string>; silenced before the
// first include, as in read_mesh.cpp.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wrestrict"
#endif

#include "io/vdb.hpp"

#include <cmath>
#include <cstring>
#include <new>
#include <string>

#include "io/parse_errors.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/io.hpp"

#ifdef TPMSFILL_WITH_OPENVDB
#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>

#include <mutex>
#include <sstream>
#endif

namespace tpmsfill {
namespace io {

bool looks_like_vdb(std::string_view data) {
  return data.size() >= 8 && std::memcmp(data.data(), "\x20\x42\x44\x56\0\0\0\0", 8) == 0;
}

#ifndef TPMSFILL_WITH_OPENVDB

namespace {
[[noreturn]] void no_openvdb(const std::string& what) {
  throw InputError(what +
                   ": .vdb files are read and written through OpenVDB, which this build of "
                   "tpmsfill lacks (install libopenvdb-dev and build again)");
}
}  // namespace

VolumeFile parse_vdb(std::string_view, const std::string& source, std::uint64_t) {
  no_openvdb(source);
}
std::string vdb_bytes(const ScalarVolume&) {
  no_openvdb("cannot write the field");
}

}  // namespace io

bool vdb_available() {
  return false;
}

void write_level_set(const std::filesystem::path& path, const TriangleSoup&,
                     const LevelSetOptions&) {
  io::no_openvdb("cannot write " + path.string());
}

#else

namespace {

void initialize_once() {
  static std::once_flag once;
  std::call_once(once, [] { openvdb::initialize(); });
}

constexpr std::uint64_t kMaxDim = 1u << 20;  // as the other field readers

// The bytes as a stream that throws at its end. OpenVDB's reader trusts the counts it reads: at
// the end of a truncated file it goes on reading nothing for as many entries as a garbage count
// says (31 s for the first 200 bytes of a 10 KB file). Ending the read at the first byte past
// the end bounds its work by the file's size. No copy of the bytes is made.
struct PastTheEnd {};
class ByteStream : public std::streambuf {
 public:
  explicit ByteStream(std::string_view data) {
    char* begin = const_cast<char*>(data.data());  // only ever read
    setg(begin, begin, begin + data.size());
  }

 protected:
  int_type underflow() override { throw PastTheEnd{}; }
  pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode) override {
    const off_type base = dir == std::ios_base::beg   ? 0
                          : dir == std::ios_base::cur ? gptr() - eback()
                                                      : egptr() - eback();
    return seekpos(pos_type(base + off), std::ios_base::in);
  }
  pos_type seekpos(pos_type at, std::ios_base::openmode) override {
    if (at < 0 || at > egptr() - eback()) return pos_type(off_type(-1));
    setg(eback(), eback() + static_cast<std::ptrdiff_t>(at), egptr());
    return at;
  }
};

// The grid's transform as spacing and the first active voxel's centre: only scales (positive,
// per axis) and translations; a rotation or shear is refused, as NRRD's is.
void placement(const openvdb::GridBase& grid, const openvdb::CoordBBox& box,
               const std::string& source, ScalarVolume& v) {
  const openvdb::math::Transform& t = grid.transform();
  if (!t.isLinear())
    detail::fail_at_byte(source, 0, "the grid's transform is not linear (a frustum); not read");
  const openvdb::Mat4d m = t.baseMap()->getAffineMap()->getMat4();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      if (r != c && m(r, c) != 0)
        detail::fail_at_byte(source, 0,
                             "the grid's transform rotates or shears; only scaled and moved "
                             "grids are read");
  for (int a = 0; a < 3; ++a) {
    v.spacing[static_cast<std::size_t>(a)] = m(a, a);
    if (!(m(a, a) > 0) || !std::isfinite(m(a, a)))
      detail::fail_at_byte(source, 0, "the grid's voxel size is not positive and finite");
  }
  const openvdb::Vec3d o = t.indexToWorld(box.min());
  v.origin = {o.x(), o.y(), o.z()};
}

template <class GridType>
void densify(const GridType& grid, const std::string& source, std::uint64_t max_bytes,
             VolumeFile& f) {
  const openvdb::CoordBBox box = grid.evalActiveVoxelBoundingBox();
  if (box.empty()) throw InputError(source + ": grid '" + grid.getName() + "' has no active voxel");
  ScalarVolume& v = f.volume;
  std::uint64_t count = 1;
  for (int a = 0; a < 3; ++a) {
    const std::uint64_t d = static_cast<std::uint64_t>(box.dim()[a]);
    if (d > kMaxDim)
      throw InputError(source + ": grid '" + grid.getName() + "' spans " + std::to_string(d) +
                       " voxels along an axis, more than 2^20");
    v.dims[static_cast<std::size_t>(a)] = static_cast<int>(d);
    count *= d;
  }
  if (count > max_bytes / sizeof(double))
    throw InputError(source + ": grid '" + grid.getName() + "' is " + std::to_string(v.dims[0]) +
                     " x " + std::to_string(v.dims[1]) + " x " + std::to_string(v.dims[2]) +
                     " voxels once dense, more than the size limit of " +
                     std::to_string(max_bytes) + " bytes allows");
  placement(grid, box, source, v);
  v.values.resize(count);
  auto accessor = grid.getConstAccessor();
  std::size_t n = 0;
  for (int k = box.min().z(); k <= box.max().z(); ++k)
    for (int j = box.min().y(); j <= box.max().y(); ++j)
      for (int i = box.min().x(); i <= box.max().x(); ++i) {
        const double x = accessor.getValue(openvdb::Coord(i, j, k));
        if (!std::isfinite(x))
          detail::fail_at_byte(source, 0,
                               "voxel (" + std::to_string(i) + ", " + std::to_string(j) + ", " +
                                   std::to_string(k) + ") of grid '" + grid.getName() +
                                   "' is not a finite number");
        v.values[n++] = x;
      }
  // A level set is negative inside, as tpmsfill's signed fields; a sign tpmsfill wrote wins.
  v.sign = grid.getGridClass() == openvdb::GRID_LEVEL_SET ? FieldSign::Signed : FieldSign::Unknown;
  if (const auto sign = grid.template getMetadata<openvdb::StringMetadata>("tpmsfill_sign"))
    v.sign = field_sign_from_name(sign->value());
  f.element_type = std::is_same_v<typename GridType::ValueType, float> ? "float32" : "float64";
}

}  // namespace

VolumeFile parse_vdb(std::string_view data, const std::string& source, std::uint64_t max_bytes) {
  initialize_once();
  VolumeFile f;
  f.format = VolumeFormat::Vdb;
  try {
    ByteStream bytes(data);
    std::istream in(&bytes);
    in.exceptions(std::ios::badbit);  // rethrows PastTheEnd from the buffer
    openvdb::io::Stream stream(in, /*delayLoad=*/false);
    const openvdb::GridPtrVecPtr grids = stream.getGrids();
    std::string others;
    openvdb::GridBase::ConstPtr chosen;
    int floats = 0;
    for (const openvdb::GridBase::Ptr& g : grids ? *grids : openvdb::GridPtrVec{}) {
      if (!g) continue;
      if (g->isType<openvdb::FloatGrid>() || g->isType<openvdb::DoubleGrid>()) {
        if (!chosen) chosen = g;
        ++floats;
      } else {
        others += (others.empty() ? "" : ", ") + g->getName() + " (" + g->valueType() + ")";
      }
    }
    if (!chosen)
      detail::fail_at_byte(source, 0,
                           "no float grid in the file" +
                               (others.empty() ? std::string() : " (it holds " + others + ")"));
    if (floats > 1)
      f.warnings.push_back(source + ": read grid '" + chosen->getName() + "', the first of " +
                           std::to_string(floats) + " float grids");
    if (const auto g = openvdb::GridBase::constGrid<openvdb::FloatGrid>(chosen))
      densify(*g, source, max_bytes, f);
    else
      densify(*openvdb::GridBase::constGrid<openvdb::DoubleGrid>(chosen), source, max_bytes, f);
    f.compressed = true;  // OpenVDB's own compression (Blosc or zip), unwrapped by it
  } catch (const Error&) {
    throw;
  } catch (const PastTheEnd&) {
    detail::fail_at_byte(source, data.size(),
                         "the file ends early: OpenVDB's reader asked for more (truncated?)");
  } catch (const std::bad_alloc&) {
    throw InputError(source + ": OpenVDB ran out of memory reading it");
  } catch (const std::exception& e) {
    std::string why = e.what();
    std::replace(why.begin(), why.end(), '\n', ' ');
    detail::fail_at_byte(source, 0, "OpenVDB cannot read it: " + why);
  }
  return f;
}

namespace {

std::string stream_bytes(const openvdb::GridBase::Ptr& grid) {
  std::ostringstream out(std::ios::binary);
  openvdb::io::Stream(out).write(openvdb::GridCPtrVec{grid});
  return out.str();
}

}  // namespace

std::string vdb_bytes(const ScalarVolume& v) {
  require_valid(v);
  if (!v.has_physical_size())
    throw InputError("a .vdb field needs a physical size (a voxel spacing in mm)");
  initialize_once();
  const auto grid = openvdb::FloatGrid::create(0.0f);
  grid->setName("field");
  openvdb::math::Mat4d m = openvdb::math::Mat4d::identity();
  for (int a = 0; a < 3; ++a) m(a, a) = v.spacing[static_cast<std::size_t>(a)];
  m.setTranslation(openvdb::Vec3d(v.origin.x, v.origin.y, v.origin.z));
  const auto transform = openvdb::math::Transform::createLinearTransform(m);
  grid->setTransform(transform);
  if (v.sign == FieldSign::Signed) grid->setGridClass(openvdb::GRID_LEVEL_SET);
  grid->insertMeta("tpmsfill_sign", openvdb::StringMetadata(std::string(field_sign_name(v.sign))));
  auto accessor = grid->getAccessor();
  for (int k = 0; k < v.dims[2]; ++k)
    for (int j = 0; j < v.dims[1]; ++j)
      for (int i = 0; i < v.dims[0]; ++i)
        accessor.setValueOn(openvdb::Coord(i, j, k), static_cast<float>(v.at(i, j, k)));
  return stream_bytes(grid);
}

}  // namespace io

bool vdb_available() {
  return true;
}

void write_level_set(const std::filesystem::path& path, const TriangleSoup& mesh,
                     const LevelSetOptions& o) {
  if (!(o.voxel > 0) || !std::isfinite(o.voxel))
    throw InputError("cannot write " + path.string() + ": the voxel must be above 0");
  if (!(o.half_width >= 1) || !(o.half_width <= 1000))
    throw InputError("cannot write " + path.string() + ": the half-width must be 1 to 1000 voxels");
  if (mesh.triangles.empty())
    throw InputError("cannot write " + path.string() + ": the mesh has no triangles");
  const Box3 box = bounding_box(mesh);
  for (int a = 0; a < 3; ++a)
    if (std::max(std::abs(box.min[a]), std::abs(box.max[a])) / o.voxel + o.half_width > 2e9)
      throw InputError("cannot write " + path.string() +
                       ": the mesh lies more voxels from the origin than OpenVDB's 32-bit "
                       "coordinates hold");
  io::initialize_once();
  const auto transform = openvdb::math::Transform::createLinearTransform(o.voxel);
  // OpenVDB takes its points in index space as floats: each relative to the voxel grid.
  std::vector<openvdb::Vec3s> points(mesh.points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const openvdb::Vec3d p = transform->worldToIndex(
        openvdb::Vec3d(mesh.points[i].x, mesh.points[i].y, mesh.points[i].z));
    points[i] = openvdb::Vec3s(static_cast<float>(p.x()), static_cast<float>(p.y()),
                               static_cast<float>(p.z()));
  }
  std::vector<openvdb::Vec3I> triangles(mesh.triangles.size());
  for (std::size_t i = 0; i < triangles.size(); ++i)
    triangles[i] = openvdb::Vec3I(mesh.triangles[i][0], mesh.triangles[i][1], mesh.triangles[i][2]);
  openvdb::FloatGrid::Ptr grid;
  try {
    openvdb::tools::QuadAndTriangleDataAdapter<openvdb::Vec3s, openvdb::Vec3I> adapter(points,
                                                                                       triangles);
    grid = openvdb::tools::meshToVolume<openvdb::FloatGrid>(
        adapter, *transform, static_cast<float>(o.half_width), static_cast<float>(o.half_width));
  } catch (const std::bad_alloc&) {
    throw ResourceError("cannot write " + path.string() +
                        ": the level set does not fit in memory (a larger voxel would)");
  }
  grid->setName("surface");
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  grid->insertMeta("creator", openvdb::StringMetadata("tpmsfill"));
  write_file_atomically(path, io::stream_bytes(grid));
}

#endif

}  // namespace tpmsfill
