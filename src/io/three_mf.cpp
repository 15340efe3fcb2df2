// 3MF through lib3mf 1.8 (Debian's lib3mf-dev, the 3MF Consortium's library): its C interface,
// wrapped here so that nothing else sees it. Reading walks the build as a slicer would (build
// items, their transforms, components); writing stores one object in millimetres with the
// metadata a printer's queue shows. Coordinates are rounded as lib3mf writes them
// (round_coordinates, CoordinateRounding::ThreeMf) before a mesh is validated: lib3mf prints
// micrometres through float arithmetic, so a validated double mesh would not be the mesh in
// the file.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wrestrict"  // GCC bug 105651, as in read_mesh.cpp
#endif

#include <Model/COM/NMR_DLLInterfaces.h>
#include <unistd.h>
#include <zip.h>

#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <map>
#include <memory>

#include "io/formats.hpp"
#include "io/three_mf.hpp"
#include "io/xml_text.hpp"

#ifndef TPMSFILL_VERSION
#define TPMSFILL_VERSION "unknown"
#endif

namespace tpmsfill::io {
namespace {

// lib3mf names no line or byte of a package's XML: the error says what, not where.
[[noreturn]] void fail(const std::string& source, const std::string& reason) {
  throw ParseError(source, std::nullopt, std::nullopt, reason);
}

// ---- lib3mf's C interface, owned ------------------------------------------------------------

struct Release {
  void operator()(NMR::PLib3MFBase* p) const { NMR::lib3mf_release(p); }
};
using Handle = std::unique_ptr<NMR::PLib3MFBase, Release>;

// lib3mf's last error on `instance`, as a sentence.
std::string last_error(NMR::PLib3MFBase* instance) {
  DWORD code = 0;
  LPCSTR message = nullptr;
  if (instance != nullptr && NMR::lib3mf_getlasterror(instance, &code, &message) == LIB3MF_OK &&
      message != nullptr && *message != '\0')
    return message;
  return "lib3mf error " + std::to_string(code);
}

// Calls that fail while reading are the file's fault; while writing, ours or the disk's.
struct Reading {
  const std::string& source;
  void operator()(LIB3MFRESULT r, NMR::PLib3MFBase* instance, const char* what) const {
    if (r != LIB3MF_OK)
      fail(source,
           std::string("not a readable 3MF package (") + what + ": " + last_error(instance) + ")");
  }
};
struct Writing {
  const std::filesystem::path& target;
  void operator()(LIB3MFRESULT r, NMR::PLib3MFBase* instance, const char* what) const {
    if (r != LIB3MF_OK)
      throw IoError("cannot write " + target.string() + ": lib3mf: " + what + ": " +
                    last_error(instance));
  }
};

template <class Check>
Handle new_model(const Check& check) {
  NMR::PLib3MFModel* model = nullptr;
  check(NMR::lib3mf_createmodel(&model), nullptr, "create a model");
  return Handle(model);
}

// ---- reading --------------------------------------------------------------------------------

// A 3MF transform: x' = sum_j m[i][j] x_j + m[i][3] (lib3mf's layout of the spec's matrix).
using Affine = std::array<std::array<double, 4>, 3>;
constexpr Affine kIdentity{{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}}};

// lib3mf parses "nan" and "inf" in a transform as floats: refused here, as every reader refuses
// non-finite coordinates.
Affine to_affine(const NMR::MODELTRANSFORM& t, const std::string& source, const char* whose) {
  Affine a;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) {
      if (!std::isfinite(t.m_fFields[i][j]))
        fail(source, std::string(whose) + "'s transform holds a value that is not a finite number");
      a[i][j] = t.m_fFields[i][j];
    }
  return a;
}

// outer ∘ inner: inner applied first.
Affine compose(const Affine& outer, const Affine& inner) {
  Affine a{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 4; ++j) {
      double s = j == 3 ? outer[i][3] : 0.0;
      for (int k = 0; k < 3; ++k) s += outer[i][k] * inner[k][j];
      a[i][j] = s;
    }
  }
  return a;
}

Vec3 apply(const Affine& a, double x, double y, double z) {
  return {a[0][0] * x + a[0][1] * y + a[0][2] * z + a[0][3],
          a[1][0] * x + a[1][1] * y + a[1][2] * z + a[1][3],
          a[2][0] * x + a[2][1] * y + a[2][2] * z + a[2][3]};
}

double millimetres_per_unit(DWORD unit, std::string& name) {
  switch (unit) {
    case NMR::MODELUNIT_MICROMETER:
      name = "micron";
      return 0.001;
    case NMR::MODELUNIT_MILLIMETER:
      name = "millimeter";
      return 1.0;
    case NMR::MODELUNIT_CENTIMETER:
      name = "centimeter";
      return 10.0;
    case NMR::MODELUNIT_INCH:
      name = "inch";
      return 25.4;
    case NMR::MODELUNIT_FOOT:
      name = "foot";
      return 304.8;
    case NMR::MODELUNIT_METER:
      name = "meter";
      return 1000.0;
    default:
      name = "unknown";
      return 1.0;
  }
}

// The build's triangles gathered into one soup.
class BuildReader {
 public:
  BuildReader(const std::string& source, MeshFile& mesh, double scale)
      : check_{source}, source_(source), mesh_(mesh), scale_(scale) {}

  void read_build(NMR::PLib3MFModel* model) {
    NMR::PLib3MFModelBuildItemIterator* raw = nullptr;
    check_(NMR::lib3mf_model_getbuilditems(model, &raw), model, "list the build");
    const Handle items(raw);
    BOOL more = false;
    while (true) {
      check_(NMR::lib3mf_builditemiterator_movenext(raw, &more), raw, "list the build");
      if (!more) break;
      NMR::PLib3MFModelBuildItem* item_raw = nullptr;
      check_(NMR::lib3mf_builditemiterator_getcurrent(raw, &item_raw), raw, "read a build item");
      const Handle item(item_raw);
      NMR::PLib3MFModelObjectResource* object_raw = nullptr;
      check_(NMR::lib3mf_builditem_getobjectresource(item_raw, &object_raw), item_raw,
             "read a build item's object");
      const Handle object(object_raw);
      BOOL has = false;
      Affine placement = kIdentity;
      check_(NMR::lib3mf_builditem_hasobjecttransform(item_raw, &has), item_raw, "transform");
      if (has) {
        NMR::MODELTRANSFORM t;
        check_(NMR::lib3mf_builditem_getobjecttransform(item_raw, &t), item_raw, "transform");
        placement = to_affine(t, source_, "a build item");
      }
      add_object(object_raw, placement, 0);
    }
  }

  std::uint64_t skipped = 0;  // build items (or components) not of type "model"

 private:
  void add_object(NMR::PLib3MFModelObjectResource* object, const Affine& placement, int depth) {
    // lib3mf refuses cyclic components; the depth bound only guards the stack. The instance
    // bound stops components that fan out: 8 per level 12 levels deep is 8^12 instances from
    // a package of 1 KB.
    if (depth > 64) fail(source_, "components nested more than 64 deep");
    if (++instances_ > kMax3mfInstances)
      throw InputError(source_ + " places more than " + std::to_string(kMax3mfInstances) +
                       " objects through its build items and components (the limit)");
    DWORD type = 0;
    check_(NMR::lib3mf_object_gettype(object, &type), object, "read an object's type");
    if (type != NMR::MODELOBJECTTYPE_MODEL && type != NMR::MODELOBJECTTYPE_SOLIDSUPPORT) {
      ++skipped;  // supports and "other" are not part of the part
      return;
    }
    BOOL is_mesh = false, is_components = false;
    check_(NMR::lib3mf_object_ismeshobject(object, &is_mesh), object, "read an object");
    check_(NMR::lib3mf_object_iscomponentsobject(object, &is_components), object, "read an object");
    if (is_mesh) add_mesh(object, placement);
    if (is_components) add_components(object, placement, depth);
  }

  void add_components(NMR::PLib3MFModelComponentsObject* object, const Affine& placement,
                      int depth) {
    DWORD count = 0;
    check_(NMR::lib3mf_componentsobject_getcomponentcount(object, &count), object,
           "read components");
    for (DWORD c = 0; c < count; ++c) {
      NMR::PLib3MFModelComponent* component_raw = nullptr;
      check_(NMR::lib3mf_componentsobject_getcomponent(object, c, &component_raw), object,
             "read a component");
      const Handle component(component_raw);
      NMR::PLib3MFModelObjectResource* inner_raw = nullptr;
      check_(NMR::lib3mf_component_getobjectresource(component_raw, &inner_raw), component_raw,
             "read a component's object");
      const Handle inner(inner_raw);
      BOOL has = false;
      Affine local = kIdentity;
      check_(NMR::lib3mf_component_hastransform(component_raw, &has), component_raw, "transform");
      if (has) {
        NMR::MODELTRANSFORM t;
        check_(NMR::lib3mf_component_gettransform(component_raw, &t), component_raw, "transform");
        local = to_affine(t, source_, "a component");
      }
      add_object(inner_raw, compose(placement, local), depth + 1);
    }
  }

  void add_mesh(NMR::PLib3MFModelMeshObject* object, const Affine& placement) {
    DWORD nv = 0, nt = 0;
    check_(NMR::lib3mf_meshobject_getvertexcount(object, &nv), object, "count vertices");
    check_(NMR::lib3mf_meshobject_gettrianglecount(object, &nt), object, "count triangles");
    std::vector<NMR::MODELMESHVERTEX> vertices(nv);
    std::vector<NMR::MODELMESHTRIANGLE> triangles(nt);
    DWORD got = 0;
    if (nv > 0)
      check_(NMR::lib3mf_meshobject_getvertices(object, vertices.data(), nv, &got), object,
             "read vertices");
    if (nt > 0)
      check_(NMR::lib3mf_meshobject_gettriangleindices(object, triangles.data(), nt, &got), object,
             "read triangles");
    TriangleSoup& soup = mesh_.soup;
    const std::uint64_t first = soup.points.size();
    if (!detail::fits_32bit_ids(first + nv))
      throw InputError(source_ + " has more than 2^32 - 1 vertices in its build");
    soup.points.reserve(first + nv);
    for (const NMR::MODELMESHVERTEX& v : vertices) {
      const float* p = v.m_fPosition;
      if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
        fail(source_, "vertex " + std::to_string(soup.points.size() - first) +
                          " of an object is not a finite number");
      soup.points.push_back(scale_ * apply(placement, p[0], p[1], p[2]));
    }
    soup.triangles.reserve(soup.triangles.size() + nt);
    for (DWORD t = 0; t < nt; ++t) {
      Triangle tri;
      for (int k = 0; k < 3; ++k) {
        if (triangles[t].m_nIndices[k] >= nv)
          fail(source_, "triangle " + std::to_string(t) + " of an object refers to vertex " +
                            std::to_string(triangles[t].m_nIndices[k]) + " of " +
                            std::to_string(nv));
        tri[k] = static_cast<std::uint32_t>(first + triangles[t].m_nIndices[k]);
      }
      soup.triangles.push_back(tri);
    }
    mesh_.faces_in_file += nt;
  }

  std::uint64_t instances_ = 0;
  Reading check_;
  const std::string& source_;
  MeshFile& mesh_;
  double scale_;
};

// An attribute's value in one XML start tag ("" when absent): `name` preceded by white space.
std::string_view attribute(std::string_view tag, std::string_view name) {
  for (std::size_t at = tag.find(name); at != std::string_view::npos; at = tag.find(name, at + 1)) {
    const std::size_t eq = at + name.size();
    if (at == 0 || !std::isspace(static_cast<unsigned char>(tag[at - 1])) || eq + 1 >= tag.size() ||
        tag[eq] != '=' || (tag[eq + 1] != '"' && tag[eq + 1] != '\''))
      continue;
    const std::size_t close = tag.find(tag[eq + 1], eq + 2);
    if (close == std::string_view::npos) return {};
    return tag.substr(eq + 2, close - eq - 2);
  }
  return {};
}

// What a model part says of its structure: each object's components, and the build's items.
struct PartStructure {
  std::map<std::string, std::vector<std::string>, std::less<>> components;  // object -> objects
  std::vector<std::string> items;                                           // their objects
  std::string object;                                                       // the object being read
};

// One start tag, "<name ...>": objects, their components and build items noted.
void note_tag(std::string_view tag, PartStructure& p, const std::string& source) {
  const auto is = [&](std::string_view name) {
    return tag.size() > name.size() + 1 && tag.substr(1, name.size()) == name &&
           (std::isspace(static_cast<unsigned char>(tag[name.size() + 1])) ||
            tag[name.size() + 1] == '/' || tag[name.size() + 1] == '>');
  };
  if (is("object")) {
    p.object = attribute(tag, "id");
  } else if (is("component")) {
    p.components[p.object].emplace_back(attribute(tag, "objectid"));
  } else if (is("item")) {
    p.items.emplace_back(attribute(tag, "objectid"));
    if (p.items.size() > kMax3mfBuildItems)
      throw InputError(source + " holds more than " + std::to_string(kMax3mfBuildItems) +
                       " build items (the limit)");
  }
}

// Objects placed by the build, components expanded (saturating past the limit): lib3mf's
// reader walks every instance itself, before any of ours is read.
std::uint64_t placed_objects(const PartStructure& p) {
  std::map<std::string_view, std::uint64_t> memo;
  const std::function<std::uint64_t(std::string_view, int)> count = [&](std::string_view id,
                                                                        int depth) {
    const auto parts = p.components.find(id);
    if (parts == p.components.end() || depth > 64) return std::uint64_t{1};
    if (const auto known = memo.find(id); known != memo.end()) return known->second;
    memo[id] = 1;  // while it is counted: a cycle (lib3mf refuses them) counts once, not forever
    std::uint64_t n = 0;
    for (const std::string& inner : parts->second)
      n = std::min(n + count(inner, depth + 1), kMax3mfInstances + 1);
    memo[id] = n;
    return n;
  };
  std::uint64_t total = 0;
  for (const std::string& id : p.items)
    total = std::min(total + count(id, 0), kMax3mfInstances + 1);
  return total;
}

// The package's model parts read once before lib3mf reads them, for their structure: lib3mf's
// reading is quadratic in build items, walks every instance of components that fan out, and
// would keep inflating a part without end. A package libzip cannot open is left to lib3mf,
// whose sentence names what is wrong.
void prescan_package(std::string_view data, const std::string& source) {
  zip_error_t error;
  zip_error_init(&error);
  zip_source_t* buffer = zip_source_buffer_create(data.data(), data.size(), 0, &error);
  if (buffer == nullptr) return;
  zip_t* archive = zip_open_from_source(buffer, ZIP_RDONLY, &error);
  if (archive == nullptr) {
    zip_source_free(buffer);
    return;
  }
  const std::unique_ptr<zip_t, void (*)(zip_t*)> owned(archive, zip_discard);
  std::vector<char> chunk(1 << 16);
  const zip_int64_t entries = zip_get_num_entries(archive, 0);
  for (zip_int64_t i = 0; i < entries; ++i) {
    const char* name = zip_get_name(archive, static_cast<zip_uint64_t>(i), 0);
    if (name == nullptr) continue;
    const std::string_view part(name);
    if (part.size() < 6 || part.substr(part.size() - 6) != ".model") continue;
    zip_file_t* file = zip_fopen_index(archive, static_cast<zip_uint64_t>(i), 0);
    if (file == nullptr) continue;
    const std::unique_ptr<zip_file_t, int (*)(zip_file_t*)> open(file, zip_fclose);
    PartStructure structure;
    std::string text;  // a start tag cut at a chunk's end, then the next chunk
    for (;;) {
      const zip_int64_t n = zip_fread(file, chunk.data(), chunk.size());
      if (n <= 0) break;
      text.append(chunk.data(), static_cast<std::size_t>(n));
      std::size_t done = text.size();
      for (std::size_t lt = text.find('<'); lt != std::string::npos; lt = text.find('<', lt + 1)) {
        const std::size_t gt = text.find('>', lt);
        if (gt == std::string::npos) {
          done = lt;  // finished with the next chunk
          break;
        }
        const char c = lt + 1 < text.size() ? text[lt + 1] : ' ';
        if (c == 'o' || c == 'c' || c == 'i')
          note_tag(std::string_view(text).substr(lt, gt + 1 - lt), structure, source);
        lt = gt;
      }
      // A tag longer than 64 KB is no tag this scan needs: dropped.
      text.erase(0, text.size() - done > (64 << 10) ? text.size() : done);
    }
    if (placed_objects(structure) > kMax3mfInstances)
      throw InputError(source + " places more than " + std::to_string(kMax3mfInstances) +
                       " objects through its build items and components (the limit)");
  }
}

void add_reader_warnings(NMR::PLib3MFModelReader* reader, const std::string& source,
                         MeshFile& mesh) {
  DWORD count = 0;
  if (NMR::lib3mf_reader_getwarningcount(reader, &count) != LIB3MF_OK || count == 0) return;
  std::string first;
  std::array<char, 512> text{};
  ULONG needed = 0;
  DWORD code = 0;
  if (NMR::lib3mf_reader_getwarningutf8(reader, 0, &code, text.data(), text.size(), &needed) ==
      LIB3MF_OK)
    first = text.data();
  mesh.warnings.push_back(source + ": lib3mf read around " + std::to_string(count) +
                          " problem(s) in the package" +
                          (first.empty() ? "" : ", first: " + first));
}

// ---- writing --------------------------------------------------------------------------------

// 128 bits of FNV-1a over the mesh, hashed once for the package's three UUIDs: the same mesh
// gets the same ids, so the same job writes the same bytes (lib3mf would draw random ones).
struct ContentHash {
  std::uint64_t h[2] = {0xcbf29ce484222325ULL, 0x84222325cbf29ce4ULL};
  ContentHash(std::span<const float> xyz, std::span<const std::uint32_t> ids) {
    mix(xyz.data(), xyz.size_bytes());
    mix(ids.data(), ids.size_bytes());
  }
  void mix(const void* data, std::size_t n) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) h[i & 1] = (h[i & 1] ^ bytes[i]) * 0x100000001b3ULL;
  }
  // A version-4-shaped UUID, one per `salt`.
  std::string uuid(std::uint64_t salt) const {
    const std::uint64_t a = (h[0] ^ salt) * 0x100000001b3ULL, b = h[1] + salt;
    char text[37];
    std::snprintf(text, sizeof text, "%08x-%04x-4%03x-%04x-%012llx", static_cast<unsigned>(a >> 32),
                  static_cast<unsigned>(a >> 16 & 0xffff), static_cast<unsigned>(a & 0xfff),
                  static_cast<unsigned>(0x8000 | (b >> 48 & 0x3fff)),
                  static_cast<unsigned long long>(b & 0xffffffffffffULL));
    return text;
  }
};

// lib3mf's export stream onto our temporary's descriptor (0: success, as lib3mf expects; the
// signatures of its ExportStream_WriteCallbackType and ExportStream_SeekCallbackType).
struct FileStream {
  int fd;
  std::uint64_t position = 0;
  int error = 0;
};

// A failed write is recorded and reported as success: lib3mf answers a failure by throwing, and
// its package writer's destructor then writes again, throws again and terminates the process
// (a full disk aborted fill). write_3mf throws the recorded error once lib3mf is done.
std::uint32_t write_callback(unsigned char* data, std::uint32_t bytes, void* user) {
  auto& s = *static_cast<FileStream*>(user);
  if (s.error != 0) return 0;
  std::size_t done = 0;
  while (done < bytes) {
    const ssize_t n =
        ::pwrite(s.fd, data + done, bytes - done, static_cast<off_t>(s.position + done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      s.error = n == 0 ? EIO : errno;
      return 0;
    }
    done += static_cast<std::size_t>(n);
  }
  s.position += bytes;
  return 0;
}

std::uint32_t seek_callback(std::uint64_t position, void* user) {
  static_cast<FileStream*>(user)->position = position;
  return 0;
}

}  // namespace

void read_3mf(std::string_view data, const std::string& source, MeshFile& mesh) {
  mesh.format = MeshFormat::ThreeMf;
  prescan_package(data, source);
  const Reading check{source};
  const Handle model = new_model(check);
  NMR::PLib3MFModelReader* reader_raw = nullptr;
  check(NMR::lib3mf_model_queryreader(model.get(), "3mf", &reader_raw), model.get(),
        "start the reader");
  const Handle reader(reader_raw);
  // lib3mf takes a mutable buffer; it only reads it.
  std::vector<BYTE> bytes(data.begin(), data.end());
  check(NMR::lib3mf_reader_readfrombuffer(reader_raw, bytes.data(), bytes.size()), reader_raw,
        "read");
  bytes = {};
  add_reader_warnings(reader_raw, source, mesh);

  DWORD unit = NMR::MODELUNIT_MILLIMETER;
  check(NMR::lib3mf_model_getunit(model.get(), &unit), model.get(), "read the unit");
  std::string unit_name;
  const double scale = millimetres_per_unit(unit, unit_name);
  BuildReader build(source, mesh, scale);
  build.read_build(model.get());
  if (scale != 1.0)
    mesh.warnings.push_back(source + ": 3MF unit is " + unit_name + ": coordinates scaled by " +
                            std::to_string(scale) + " to millimetres");
  if (build.skipped > 0)
    mesh.warnings.push_back(source + ": skipped " + std::to_string(build.skipped) +
                            " build object(s) that are supports or of type \"other\"");
}

void write_3mf(int fd, const std::filesystem::path& target, std::span<const float> xyz,
               std::span<const std::uint32_t> ids, const MeshMetadata& metadata) {
  const Writing check{target};
  const Handle model = new_model(check);
  NMR::PLib3MFModel* m = model.get();
  check(NMR::lib3mf_model_setunit(m, NMR::MODELUNIT_MILLIMETER), m, "set the unit");
  NMR::PLib3MFModelMeshObject* object_raw = nullptr;
  check(NMR::lib3mf_model_addmeshobject(m, &object_raw), m, "add the mesh");
  const Handle object(object_raw);
  const std::string title = metadata.title.empty() ? target.stem().string() : metadata.title;
  // lib3mf 1.8 writes names and metadata into the XML as given: escaped here.
  check(NMR::lib3mf_object_setnameutf8(object_raw, detail::xml_escaped(title).c_str()), object_raw,
        "name the mesh");
  // MODELMESHVERTEX is three packed floats and MODELMESHTRIANGLE three 32-bit ids: the spans'
  // layout exactly (lib3mf copies them).
  static_assert(sizeof(NMR::MODELMESHVERTEX) == 3 * sizeof(float));
  static_assert(sizeof(NMR::MODELMESHTRIANGLE) == 3 * sizeof(std::uint32_t));
  check(NMR::lib3mf_meshobject_setgeometry(
            object_raw, reinterpret_cast<NMR::MODELMESHVERTEX*>(const_cast<float*>(xyz.data())),
            static_cast<DWORD>(xyz.size() / 3),
            reinterpret_cast<NMR::MODELMESHTRIANGLE*>(const_cast<std::uint32_t*>(ids.data())),
            static_cast<DWORD>(ids.size() / 3)),
        object_raw, "store the mesh");
  const ContentHash content(xyz, ids);
  check(NMR::lib3mf_object_setuuidutf8(object_raw, content.uuid(1).c_str()), object_raw,
        "set the object's UUID");
  NMR::PLib3MFModelBuildItem* item_raw = nullptr;
  check(NMR::lib3mf_model_addbuilditem(m, object_raw, nullptr, &item_raw), m, "add to the build");
  const Handle item(item_raw);
  check(NMR::lib3mf_builditem_setuuidutf8(item_raw, content.uuid(2).c_str()), item_raw,
        "set the build item's UUID");
  check(NMR::lib3mf_model_setbuilduuidutf8(m, content.uuid(3).c_str()), m, "set the build's UUID");

  const std::string application = "tpmsfill " TPMSFILL_VERSION;
  for (const auto& [name, value] : {std::pair<const char*, const std::string&>{"Title", title},
                                    {"Application", application},
                                    {"Description", metadata.description}})
    if (!value.empty())
      check(NMR::lib3mf_model_addmetadatautf8(m, name, detail::xml_escaped(value).c_str()), m,
            "add metadata");
  for (const auto& [path, bytes] : metadata.attachments) {
    std::string uri = "/" + path;
    std::string relationship = "http://schemas.tpmsfill.org/3mf/attachment";
    NMR::PLib3MFModelAttachment* attachment_raw = nullptr;
    check(NMR::lib3mf_model_addattachmentutf8(m, uri.data(), relationship.data(), &attachment_raw),
          m, "attach a file");
    const Handle attachment(attachment_raw);
    std::vector<BYTE> copy(bytes.begin(), bytes.end());
    check(NMR::lib3mf_attachment_readfrombuffer(attachment_raw, copy.data(), copy.size()),
          attachment_raw, "attach a file");
  }

  NMR::PLib3MFModelWriter* writer_raw = nullptr;
  check(NMR::lib3mf_model_querywriter(m, "3mf", &writer_raw), m, "start the writer");
  const Handle writer(writer_raw);
  FileStream stream{fd};
  const LIB3MFRESULT r =
      NMR::lib3mf_writer_writetocallback(writer_raw, reinterpret_cast<void*>(&write_callback),
                                         reinterpret_cast<void*>(&seek_callback), &stream);
  if (stream.error != 0) {
    errno = stream.error;
    throw IoError("cannot write " + target.string() + ": write failed: " + std::strerror(errno));
  }
  check(r, writer_raw, "write the package");
}

namespace {

// lib3mf 1.8's writer prints a coordinate as the float times 10^6 in float arithmetic,
// truncated to an integer count of micrometres.
bool written_micrometres(float value, long long& micrometres) {
  const volatile float scaled = value * 1000000.0f;  // float arithmetic, as lib3mf's
  if (!(std::fabs(scaled) < 9.0e18f)) return false;  // beyond 64 bits (9000 km)
  micrometres = static_cast<long long>(scaled);
  return true;
}

// What its reader parses that text back to: the nearest float.
float parsed(long long micrometres) {
  const unsigned long long magnitude = micrometres < 0
                                           ? 0ULL - static_cast<unsigned long long>(micrometres)
                                           : static_cast<unsigned long long>(micrometres);
  char text[40];
  std::snprintf(text, sizeof text, "%s%llu.%06llu", micrometres < 0 ? "-" : "", magnitude / 1000000,
                magnitude % 1000000);
  return std::strtof(text, nullptr);
}

// Whether lib3mf writes `value` and reads back `value`.
bool stands(float value) {
  long long n = 0;
  return written_micrometres(value, n) && parsed(n) == value;
}

}  // namespace

float three_mf_rounded(float value) {
  // The nearest value that lib3mf writes and reads back as itself. Written once, a value comes
  // back as parsed(n), n its truncated micrometres; but that float times 10^6 may fall short of
  // n in float arithmetic and be written as n - 1 the next time (0.54 % of values,
  // measured; where the float's relative rounding is near 10^-6's, runs of neighbours do). The
  // micrometres around n are tried nearest first (at most 9 were needed, measured on 2 million
  // values from 1e-7 to 1e6 mm), then the fall-back repeats the round trip until it stands
  // still (truncation moves toward zero, so it ends).
  long long n = 0;
  if (!written_micrometres(value, n)) return value;  // lib3mf's own overflow: left as it is
  const long long away = value < 0 ? -1 : 1;         // truncation went toward zero
  for (long long d = 0; d < 32; ++d) {
    const long long k = n + away * (d % 2 == 0 ? d / 2 : -(d + 1) / 2);
    if (const float c = parsed(k); stands(c)) return c;
  }
  for (int step = 0; step < 64 && !stands(value); ++step) {
    written_micrometres(value, n);
    value = parsed(n);
  }
  return value;
}

}  // namespace tpmsfill::io
