// Scenes (glTF, FBX, COLLADA, 3DS, ...) through assimp, the only file that sees assimp. A scene
// is a tree of placed meshes; it is flattened here into one soup, every placement applied, so the
// rest of the pipeline sees what a viewer shows. Built without assimp (libassimp-dev absent), the
// same names are recognised and refused with a sentence saying why.
// GCC 12 at -O3 warns falsely (-Wrestrict, GCC bug 105651) inside <string> once ParseError's
// message is composed inline; the warning is located in the library header, so it can only be
// silenced before the first include (as in read_mesh.cpp).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wrestrict"
#endif
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "io/file_bytes.hpp"
#include "io/formats.hpp"

#ifdef TPMSFILL_WITH_ASSIMP
#include <assimp/DefaultIOSystem.h>
#include <assimp/commonMetaData.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/IOStream.hpp>
#include <assimp/IOSystem.hpp>
#include <assimp/Importer.hpp>
#endif

namespace tpmsfill::io {
namespace {

// Extensions of the formats our own readers own: never handed to assimp.
bool ours(const std::string& ext) {
  return ext == ".stl" || ext == ".obj" || ext == ".ply" || ext == ".off" || ext == ".3mf" ||
         ext == ".gz";
}

// Text that says it is a glTF or COLLADA scene within its first few kilobytes.
bool text_names_scene(std::string_view data) {
  std::string_view head = data.substr(0, 4096);
  if (head.starts_with("\xEF\xBB\xBF")) head.remove_prefix(3);
  const std::size_t start = head.find_first_not_of(" \t\r\n");
  if (start == std::string_view::npos) return false;
  if (head[start] == '{') return head.find("\"asset\"") != std::string_view::npos;  // glTF
  if (head[start] == '<') return head.find("<COLLADA") != std::string_view::npos;
  return head.substr(start).starts_with("; FBX");  // FBX as text
}

}  // namespace

bool is_scene_extension(const std::filesystem::path& path) {
  const std::string ext = detail::lower_extension(path);
  if (ext.size() < 2 || ours(ext)) return false;
#ifdef TPMSFILL_WITH_ASSIMP
  return Assimp::Importer().IsExtensionSupported(ext.c_str());
#else
  static constexpr std::string_view kCommon[] = {".gltf", ".glb",   ".fbx", ".dae", ".zae",
                                                 ".3ds",  ".blend", ".x",   ".lwo", ".ms3d",
                                                 ".ase",  ".ac",    ".ifc", ".x3d", ".amf"};
  return std::find(std::begin(kCommon), std::end(kCommon), ext) != std::end(kCommon);
#endif
}

bool looks_like_scene(std::string_view data) {
  return data.starts_with("glTF") || data.starts_with("Kaydara FBX Binary") ||
         text_names_scene(data);
}

#ifndef TPMSFILL_WITH_ASSIMP

void read_scene(std::string_view, const std::string& source, const std::filesystem::path*,
                std::uint64_t, MeshFile&) {
  throw InputError(source +
                   ": scenes (glTF, FBX, COLLADA, 3DS, ...) are read through assimp, which this "
                   "build of tpmsfill lacks (install libassimp-dev and build again)");
}

#else

namespace {

// Files a scene names beside itself (a glTF's .bin buffers): only plain files in the scene's
// own folder or below it, never one elsewhere (absolute or climbing out), so a scene handed to the
// service cannot read the server's files into a mesh. Without a folder (bytes from memory),
// nothing.
class SceneFolder : public Assimp::IOSystem {
 public:
  explicit SceneFolder(const std::filesystem::path* folder) {
    if (folder != nullptr) folder_ = std::filesystem::weakly_canonical(*folder);
  }

  bool Exists(const char* name) const override { return !resolve(name).empty(); }
  char getOsSeparator() const override { return '/'; }
  Assimp::IOStream* Open(const char* name, const char* mode) override {
    if (mode == nullptr || std::strchr(mode, 'w') != nullptr || std::strchr(mode, 'a') != nullptr)
      return nullptr;
    const std::filesystem::path file = resolve(name);
    return file.empty() ? nullptr : plain_.Open(file.c_str(), "rb");
  }
  void Close(Assimp::IOStream* stream) override { plain_.Close(stream); }

  /// The first name asked for that exists outside the folder (empty if none).
  const std::string& refused() const { return refused_; }

 private:
  std::filesystem::path resolve(const char* name) const {
    if (folder_.empty() || name == nullptr) return {};
    std::error_code error;  // an absolute name replaces the folder: kept only if inside it
    const std::filesystem::path file = std::filesystem::weakly_canonical(folder_ / name, error);
    if (error) return {};
    const auto [end, rest] = std::mismatch(folder_.begin(), folder_.end(), file.begin());
    if (!std::filesystem::is_regular_file(file, error)) return {};
    if (end != folder_.end()) {
      if (refused_.empty()) refused_ = name;
      return {};
    }
    return file;
  }

  std::filesystem::path folder_;
  mutable std::string refused_;
  Assimp::DefaultIOSystem plain_;
};

// Millimetres per unit of assimp's scene, from what the format states: glTF and COLLADA are in
// metres once assimp has applied a COLLADA file's <unit>; FBX states centimetres per unit; the
// others (3DS, ...) state nothing and are read as millimetres, like STL.
double millimetres_per_unit(const aiScene& scene, const std::string& importer) {
  if (importer.starts_with("glTF") || importer.starts_with("Collada")) return 1000;
  if (importer.find("FBX") != std::string::npos) {
    double centimetres = 1;
    if (scene.mMetaData != nullptr) {
      float f = 0;
      double d = 0;
      if (scene.mMetaData->Get("UnitScaleFactor", d) && d > 0 && std::isfinite(d))
        centimetres = d;
      else if (scene.mMetaData->Get("UnitScaleFactor", f) && f > 0 && std::isfinite(f))
        centimetres = f;
    }
    return 10 * centimetres;
  }
  return 1;
}

// Which of the scene's axes is up: assimp turns COLLADA, 3DS and its others to +Y up, glTF is
// +Y up by its specification; FBX states its axis (0 x, 1 y, 2 z, with a sign).
std::pair<int, int> up_axis(const aiScene& scene, const std::string& importer) {
  if (importer.find("FBX") == std::string::npos || scene.mMetaData == nullptr) return {1, 1};
  int axis = 1, sign = 1;
  scene.mMetaData->Get("UpAxis", axis);
  scene.mMetaData->Get("UpAxisSign", sign);
  if (axis < 0 || axis > 2) axis = 1;
  return {axis, sign < 0 ? -1 : 1};
}

using Matrix = std::array<double, 12>;  // rows of an affine map, 3 × 4

Matrix to_matrix(const aiMatrix4x4& m) {
  return {m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4};
}

Matrix times(const Matrix& a, const Matrix& b) {
  Matrix c{};
  for (int r = 0; r < 3; ++r) {
    for (int k = 0; k < 4; ++k) {
      double s = k == 3 ? a[r * 4 + 3] : 0;
      for (int j = 0; j < 3; ++j) s += a[r * 4 + j] * b[j * 4 + k];
      c[r * 4 + k] = s;
    }
  }
  return c;
}

double determinant(const Matrix& m) {
  return m[0] * (m[5] * m[10] - m[6] * m[9]) - m[1] * (m[4] * m[10] - m[6] * m[8]) +
         m[2] * (m[4] * m[9] - m[5] * m[8]);
}

// The map from the scene's frame to ours: its up axis turned onto +z (a rotation, so windings
// hold; +y up as Blender turns glTF: (x, y, z) -> (x, -z, y)), scaled to millimetres.
Matrix frame_to_millimetres(std::pair<int, int> up, double mm) {
  // Rows of the rotation: which scene axis, with which sign, gives our x, y and z.
  static constexpr int kRows[3][3][2] = {
      {{1, 1}, {2, 1}, {0, 1}},   // +x up
      {{0, 1}, {2, -1}, {1, 1}},  // +y up
      {{0, 1}, {1, 1}, {2, 1}},   // +z up
  };
  const auto [axis, sign] = up;
  Matrix m{};
  for (int r = 0; r < 3; ++r) {
    const int flip = r > 0 && sign < 0 ? -1 : 1;  // a downward up: a half turn about x
    m[r * 4 + kRows[axis][r][0]] = flip * kRows[axis][r][1] * mm;
  }
  return m;
}

struct Placement {
  const aiNode* node;
  Matrix to_file;  // node frame -> millimetres, z up
};

}  // namespace

void read_scene(std::string_view data, const std::string& source, const std::filesystem::path* file,
                std::uint64_t max_bytes, MeshFile& mesh) {
  Assimp::Importer importer;
  const std::filesystem::path folder =
      file == nullptr ? std::filesystem::path() : std::filesystem::absolute(*file).parent_path();
  auto* files = new SceneFolder(file == nullptr ? nullptr : &folder);
  importer.SetIOHandler(files);  // the importer owns it
  // Only positions and faces are wanted: everything else is dropped before post-processing.
  importer.SetPropertyInteger(
      AI_CONFIG_PP_RVC_FLAGS,
      aiComponent_NORMALS | aiComponent_TANGENTS_AND_BITANGENTS | aiComponent_COLORS |
          aiComponent_TEXCOORDS | aiComponent_BONEWEIGHTS | aiComponent_ANIMATIONS |
          aiComponent_TEXTURES | aiComponent_LIGHTS | aiComponent_CAMERAS | aiComponent_MATERIALS);
  std::string hint = detail::lower_extension(source);
  if (!hint.empty()) hint.erase(0, 1);
  // No joining of vertices: assimp's join compares with a tolerance; the soup keeps every corner
  // as the file places it, and exactly equal points become one later, as for STL.
  constexpr unsigned kSteps =
      aiProcess_Triangulate | aiProcess_RemoveComponent | aiProcess_ValidateDataStructure;
  // A file as it is on disk is read by name: some of assimp's readers (SMD) crawl through
  // memory (19 s against 0.04 s for a 0.9 MB file).
  const aiScene* scene =
      file != nullptr ? importer.ReadFile(std::filesystem::absolute(*file).c_str(), kSteps)
                      : importer.ReadFileFromMemory(data.data(), data.size(), kSteps, hint.c_str());
  if (scene == nullptr) {
    std::string why = importer.GetErrorString();
    while (!why.empty() && (why.back() == '\n' || why.back() == '\r' || why.back() == ' '))
      why.pop_back();
    std::replace(why.begin(), why.end(), '\n', ' ');
    if (!files->refused().empty())
      why += " (" + files->refused() +
             " is outside the scene's folder: a scene's own files are read only from its folder)";
    throw ParseError(source, std::nullopt, std::nullopt,
                     "assimp cannot read this scene: " + (why.empty() ? "no reason given" : why));
  }
  if (scene->mRootNode == nullptr)
    throw InputError(source + ": the scene places no meshes (it has no root node)");

  aiString format_name;
  std::string importer_name;
  if (scene->mMetaData != nullptr && scene->mMetaData->Get(AI_METADATA_SOURCE_FORMAT, format_name))
    importer_name = format_name.C_Str();
  const Matrix frame = frame_to_millimetres(up_axis(*scene, importer_name),
                                            millimetres_per_unit(*scene, importer_name));

  // Every placement first, to refuse a scene that multiplies out too far before allocating.
  std::vector<Placement> placed;
  std::uint64_t instances = 0, triangles = 0, points = 0;
  std::vector<Placement> stack{
      {scene->mRootNode, times(frame, to_matrix(scene->mRootNode->mTransformation))}};
  while (!stack.empty()) {
    const Placement p = stack.back();
    stack.pop_back();
    if (p.node->mNumMeshes > 0) placed.push_back(p);
    for (unsigned i = 0; i < p.node->mNumMeshes; ++i) {
      if (p.node->mMeshes[i] >= scene->mNumMeshes) continue;  // assimp's validation refuses these
      const aiMesh& m = *scene->mMeshes[p.node->mMeshes[i]];
      ++instances;
      triangles += m.mNumFaces;
      points += m.mNumVertices;
    }
    if (instances > kMaxSceneInstances)
      throw InputError(source + ": the scene places more than " +
                       std::to_string(kMaxSceneInstances) + " meshes");
    for (unsigned i = 0; i < p.node->mNumChildren; ++i) {
      const aiNode* child = p.node->mChildren[i];
      if (child != nullptr)
        stack.push_back({child, times(p.to_file, to_matrix(child->mTransformation))});
    }
  }
  // As binary STL the flattened scene would take 50 bytes a triangle: the same limit as a file.
  if (triangles > max_bytes / 50 || !detail::fits_32bit_ids(points))
    throw InputError(source + ": flattened, the scene holds " + std::to_string(triangles) +
                     " triangles in " + std::to_string(instances) +
                     " placed meshes, more than the size limit of " + std::to_string(max_bytes) +
                     " bytes allows");

  // Depth-first order reversed the file's: restore it, so the soup follows the file.
  std::reverse(placed.begin(), placed.end());
  mesh.soup.points.reserve(points);
  mesh.soup.triangles.reserve(triangles);
  std::uint64_t skipped = 0;
  for (const Placement& p : placed) {
    const bool mirrored = determinant(p.to_file) < 0;
    for (unsigned i = 0; i < p.node->mNumMeshes; ++i) {
      if (p.node->mMeshes[i] >= scene->mNumMeshes) continue;
      const unsigned mesh_id = p.node->mMeshes[i];
      const aiMesh& m = *scene->mMeshes[mesh_id];
      const auto first = static_cast<std::uint32_t>(mesh.soup.points.size());
      const Matrix& a = p.to_file;
      for (unsigned v = 0; v < m.mNumVertices; ++v) {
        const aiVector3D q = m.mVertices[v];
        const Vec3 x{a[0] * q.x + a[1] * q.y + a[2] * q.z + a[3],
                     a[4] * q.x + a[5] * q.y + a[6] * q.z + a[7],
                     a[8] * q.x + a[9] * q.y + a[10] * q.z + a[11]};
        if (!std::isfinite(x.x) || !std::isfinite(x.y) || !std::isfinite(x.z))
          throw ParseError(source, std::nullopt, std::nullopt,
                           "mesh " + std::to_string(mesh_id) + " ('" + m.mName.C_Str() +
                               "'), vertex " + std::to_string(v) +
                               ": a coordinate is not a finite number once placed");
        mesh.soup.points.push_back(x);
      }
      for (unsigned f = 0; f < m.mNumFaces; ++f) {
        const aiFace& face = m.mFaces[f];
        ++mesh.faces_in_file;
        if (face.mNumIndices != 3) {
          ++skipped;  // points and lines: no surface
          continue;
        }
        std::array<std::uint32_t, 3> t{};
        for (int k = 0; k < 3; ++k) {
          if (face.mIndices[k] >= m.mNumVertices)
            throw ParseError(source, std::nullopt, std::nullopt,
                             "mesh " + std::to_string(mesh_id) + ", face " + std::to_string(f) +
                                 ": vertex " + std::to_string(face.mIndices[k]) +
                                 " does not exist (the mesh has " + std::to_string(m.mNumVertices) +
                                 ")");
          t[k] = first + face.mIndices[k];
        }
        if (mirrored) std::swap(t[1], t[2]);
        mesh.soup.triangles.push_back({t[0], t[1], t[2]});
      }
    }
  }
  if (skipped > 0)
    mesh.warnings.push_back(std::to_string(skipped) +
                            " points and lines in the scene were left out (only faces bound a "
                            "solid)");
  mesh.format = MeshFormat::Scene;
}

#endif

}  // namespace tpmsfill::io
