// FBX, OBJ, 3DS, PLY and Collada through Assimp (mesh_assimp.h). Passes:
//   1. a PLY header check (element counts the file cannot hold are refused before Assimp
//      reserves memory for them);
//   2. Assimp reads the bytes through AssimpFiles; n-gons are counted, then post-processed;
//   3. the unit and up axis from the FBX metadata;
//   4. materials and their textures;
//   5. the node tree walked from the root (or options.node), each mesh's triangles transformed.
#include "stages/import/mesh_assimp.h"

#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cmath>
#include <cstring>
#include <map>

#include "stages/import/mesh_assimp_io.h"
#include "stages/import/mesh_checks.h"

namespace sylva::import {

namespace {

std::string mime_of(const std::string& bytes) {
  if (bytes.size() >= 8 && std::memcmp(bytes.data(), "\x89PNG\r\n\x1a\n", 8) == 0) return "image/png";
  if (bytes.size() >= 3 && std::memcmp(bytes.data(), "\xFF\xD8\xFF", 3) == 0) return "image/jpeg";
  return {};
}

// A PNG whose IHDR colour type has an alpha channel (4: grey + alpha, 6: RGBA).
bool png_with_alpha(const std::string& bytes) {
  return bytes.size() > 25 && mime_of(bytes) == "image/png" && (bytes[25] == 4 || bytes[25] == 6);
}

// 1. A PLY header Assimp 5.2 reads without spinning or over-allocating (its reader loops on a
// header line it does not expect): printable ASCII; "ply"; then only "format <ascii|binary_*>
// 1.0", "comment ...", "obj_info ...", "element <name> <count>", "property <type> <name>" and
// "property list <type> <type> <name>" lines, up to a line that is exactly "end_header"; element
// counts the file's bytes can hold (at least one byte each).
std::vector<std::string> words(const std::string& line) {
  std::vector<std::string> out;
  std::size_t at = 0;
  while (at < line.size()) {
    const std::size_t sp = line.find(' ', at);
    const std::size_t end = sp == std::string::npos ? line.size() : sp;
    if (end > at) out.push_back(line.substr(at, end - at));
    at = end + 1;
  }
  return out;
}

bool ply_type(const std::string& t) {
  static const char* const kTypes[] = {"char",  "uchar",  "short",   "ushort", "int",   "uint",
                                       "float", "double", "int8",    "uint8",  "int16", "uint16",
                                       "int32", "uint32", "float32", "float64"};
  return std::find(std::begin(kTypes), std::end(kTypes), t) != std::end(kTypes);
}

void check_ply_header(const std::string& bytes, std::string_view source) {
  std::size_t at = 0;
  for (int number = 1;; ++number) {
    const std::size_t nl = bytes.find('\n', at);
    if (nl == std::string::npos || number > 10000) throw MeshError(source, "PLY header: no end_header line");
    std::string line = bytes.substr(at, nl - at);
    at = nl + 1;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const auto bad = [&](const std::string& why) {
      return MeshError(source, "PLY header line " + std::to_string(number) + ": " + why);
    };
    if (std::any_of(line.begin(), line.end(), [](char c) { return c < 32 || c > 126; }))
      throw bad("a byte that is not printable ASCII");
    const std::vector<std::string> w = words(line);
    if (number == 1) {
      if (line != "ply") throw bad("not 'ply'");
      continue;
    }
    if (line == "end_header") return;
    const std::string keyword = w.empty() ? "" : w[0];
    if (keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "format") {
      if (w.size() != 3 || (w[1] != "ascii" && w[1] != "binary_little_endian" && w[1] != "binary_big_endian"))
        throw bad("'" + line + "' is not a PLY format");
    } else if (keyword == "property") {
      const bool scalar = w.size() == 3 && ply_type(w[1]);
      const bool list = w.size() == 5 && w[1] == "list" && ply_type(w[2]) && ply_type(w[3]);
      if (!scalar && !list) throw bad("'" + line + "' is not a PLY property");
    } else if (keyword == "element") {
      char* stop = nullptr;
      const double count = w.size() == 3 ? std::strtod(w[2].c_str(), &stop) : -1;
      if (w.size() != 3 || *stop != '\0' || !(count >= 0)) throw bad("'" + line + "' is not a PLY element");
      if (count > double(bytes.size()))
        throw MeshError(source, "PLY header: '" + line + "' declares more elements than the file's " +
                                    std::to_string(bytes.size()) + " bytes can hold");
    } else {
      throw bad("unknown keyword '" + keyword + "'");
    }
  }
}

std::string str(const aiString& s) { return std::string(s.C_Str(), s.length); }

class Reader {
 public:
  Reader(const aiScene& scene, std::string_view source, const SidecarFiles& files, const MeshOptions& options,
         MeshImport& out)
      : s_(scene), source_(source), files_(files), options_(options), out_(out) {}

  void read() {
    read_units();
    for (unsigned i = 0; i < s_.mNumMaterials; ++i) read_material(*s_.mMaterials[i], i);
    const auto [root, world] = start();
    visit(*root, world, "", 0);
  }

 private:
  void warn(const std::string& what) { out_.warnings.push_back(std::string(source_) + ": warning: " + what); }

  // ---- 3. Units and axes ---------------------------------------------------------------------

  void read_units() {
    if (s_.mMetaData == nullptr) return;
    double factor = 0;
    float f32 = 0;
    if (s_.mMetaData->Get("UnitScaleFactor", factor) ||
        (s_.mMetaData->Get("UnitScaleFactor", f32) && (factor = f32) != 0)) {
      if (std::isfinite(factor) && factor > 0) {
        out_.facts.unit_scale = factor * 0.01;  // FBX: centimetres per file unit
        out_.facts.unit = factor == 1 ? "cm" : factor == 100 ? "m" : std::to_string(factor) + " cm";
      } else {
        warn("UnitScaleFactor " + std::to_string(factor) + " is not a positive number: taken as metres");
      }
    }
    int axis = -1;
    if (out_.facts.format == "fbx" && s_.mMetaData->Get("UpAxis", axis)) {
      if (axis == 2) {
        out_.facts.up = 'z';
      } else if (axis != 1) {
        warn("UpAxis " + std::to_string(axis) + " (not Y or Z): taken as Y");
      }
    }
  }

  // ---- 4. Materials --------------------------------------------------------------------------

  int image_of(const aiString& path, const std::string& material) {
    const std::string ref = str(path);
    if (auto it = image_slot_.find(ref); it != image_slot_.end()) return it->second;
    std::string bytes, name;
    if (const aiTexture* t = s_.GetEmbeddedTexture(path.C_Str())) {
      name = ref.rfind('*', 0) == 0
                 ? std::filesystem::path(std::string(source_)).filename().string() + ".image" + ref.substr(1)
                 : ref;
      if (t->mHeight == 0) bytes.assign(reinterpret_cast<const char*>(t->pcData), t->mWidth);
    } else {
      const std::filesystem::path file = files_.resolve(ref);
      name = file.lexically_relative(files_.base_dir()).string();
      if (!files_.exists(file)) {
        warn("texture '" + ref + "' of material '" + material + "' could not be read (no file '" + name +
             "' beside the model): the material keeps its colour, without the texture");
        image_slot_.emplace(ref, -1);
        return -1;
      }
      try {
        bytes = files_.read(file);
      } catch (const fileio::FileReadError& e) {  // there, but unreadable (permissions, too large, a race)
        throw MeshError(source_, "texture '" + ref + "' of material '" + material + "': cannot read '" +
                                     name + "' (" + e.reason() + ")");
      }
    }
    int slot = -1;
    const std::string mime = mime_of(bytes);
    if (mime.empty()) {
      warn("texture '" + ref + "' of material '" + material +
           "' is neither PNG nor JPEG: the material keeps its colour, without the texture");
    } else {
      slot = int(out_.geometry.images.size());
      out_.geometry.images.push_back({name, mime, std::move(bytes)});
    }
    image_slot_.emplace(ref, slot);
    return slot;
  }

  void read_material(const aiMaterial& am, unsigned index) {
    tree::SourceMaterial mat;
    aiString name;
    mat.name = am.Get(AI_MATKEY_NAME, name) == AI_SUCCESS && name.length > 0
                   ? str(name)
                   : "material" + std::to_string(index);
    aiColor4D c;
    if (am.Get(AI_MATKEY_BASE_COLOR, c) == AI_SUCCESS || am.Get(AI_MATKEY_COLOR_DIFFUSE, c) == AI_SUCCESS)
      mat.base_color = {c.r, c.g, c.b, c.a};
    float opacity = 1;
    if (am.Get(AI_MATKEY_OPACITY, opacity) == AI_SUCCESS && opacity < 1) {
      mat.base_color[3] *= opacity;
      mat.alpha_mode = tree::AlphaMode::kBlend;
    }
    int two_sided = 0;
    if (am.Get(AI_MATKEY_TWOSIDED, two_sided) == AI_SUCCESS) mat.double_sided = two_sided != 0;
    aiString tex;
    if (am.GetTexture(aiTextureType_BASE_COLOR, 0, &tex) == AI_SUCCESS ||
        am.GetTexture(aiTextureType_DIFFUSE, 0, &tex) == AI_SUCCESS) {
      mat.base_color_image = image_of(tex, mat.name);
      if (mat.base_color_image >= 0 && mat.alpha_mode == tree::AlphaMode::kOpaque &&
          png_with_alpha(out_.geometry.images[std::size_t(mat.base_color_image)].bytes))
        mat.alpha_mode = tree::AlphaMode::kMask;
    }
    if (am.GetTextureCount(aiTextureType_OPACITY) > 0 && mat.alpha_mode == tree::AlphaMode::kOpaque)
      mat.alpha_mode = tree::AlphaMode::kMask;
    out_.geometry.materials.push_back(std::move(mat));
  }

  // ---- 5. Nodes ------------------------------------------------------------------------------

  static const aiNode* find(const aiNode& n, const std::string& name) {
    if (str(n.mName) == name) return &n;
    for (unsigned i = 0; i < n.mNumChildren; ++i)
      if (const aiNode* f = find(*n.mChildren[i], name)) return f;
    return nullptr;
  }

  static void names(const aiNode& n, std::vector<std::string>& out) {
    if (n.mName.length > 0) out.push_back("'" + str(n.mName) + "'");
    for (unsigned i = 0; i < n.mNumChildren; ++i) names(*n.mChildren[i], out);
  }

  std::pair<const aiNode*, aiMatrix4x4> start() const {
    if (options_.node.empty()) return {s_.mRootNode, aiMatrix4x4()};
    const aiNode* n = find(*s_.mRootNode, options_.node);
    if (n == nullptr) {
      std::vector<std::string> all;
      names(*s_.mRootNode, all);
      std::string list;
      for (std::size_t i = 0; i < all.size() && i < 20; ++i) list += (i ? ", " : "") + all[i];
      if (all.size() > 20) list += " and " + std::to_string(all.size() - 20) + " more";
      throw MeshError(source_, "no node is named '" + options_.node + "'; the nodes are " + list);
    }
    aiMatrix4x4 world;
    for (const aiNode* a = n->mParent; a != nullptr; a = a->mParent) world = a->mTransformation * world;
    return {n, world};
  }

  void visit(const aiNode& node, const aiMatrix4x4& parent, const std::string& path, std::size_t depth) {
    if (depth > 1000) throw MeshError(source_, "the node hierarchy is deeper than 1000 levels");
    const aiMatrix4x4 world = parent * node.mTransformation;
    const std::string here = path + (path.empty() ? "" : "/") + str(node.mName);
    for (unsigned i = 0; i < node.mNumMeshes; ++i) {
      if (node.mMeshes[i] >= s_.mNumMeshes)
        throw MeshError(source_, "node '" + here + "' names a mesh that does not exist");
      add_mesh(*s_.mMeshes[node.mMeshes[i]], world, here);
    }
    for (unsigned i = 0; i < node.mNumChildren; ++i) visit(*node.mChildren[i], world, here, depth + 1);
  }

  void add_mesh(const aiMesh& mesh, const aiMatrix4x4& world, const std::string& path) {
    const std::string name = path + "/" + (mesh.mName.length > 0 ? str(mesh.mName) : "mesh");
    if ((mesh.mPrimitiveTypes & aiPrimitiveType_TRIANGLE) == 0) {
      warn("mesh '" + name + "': " + std::to_string(mesh.mNumFaces) +
           " points or lines skipped: sylva imports triangles");
      return;
    }
    check_mesh_limits(source_, vertices_ + mesh.mNumVertices, triangles_ + mesh.mNumFaces, options_);
    tree::SourcePrimitive p;
    p.name = name;
    p.material = mesh.mMaterialIndex;
    if (p.material >= out_.geometry.materials.size())
      throw MeshError(source_, "mesh '" + name + "' names a material that does not exist");
    p.positions.resize(mesh.mNumVertices);
    for (unsigned i = 0; i < mesh.mNumVertices; ++i) {
      const aiVector3D v = world * mesh.mVertices[i];
      p.positions[i] = tree::Vec3f{v.x, v.y, v.z};
    }
    if (mesh.mNormals != nullptr) {
      aiMatrix3x3 nm(world);
      nm.Inverse().Transpose();
      p.normals.resize(mesh.mNumVertices);
      for (unsigned i = 0; i < mesh.mNumVertices; ++i) {
        const aiVector3D v = nm * mesh.mNormals[i];
        p.normals[i] = tree::Vec3f{v.x, v.y, v.z};
      }
    }
    if (mesh.mTextureCoords[0] != nullptr) {
      p.uvs.resize(mesh.mNumVertices);
      for (unsigned i = 0; i < mesh.mNumVertices; ++i)
        p.uvs[i] = {mesh.mTextureCoords[0][i].x, mesh.mTextureCoords[0][i].y};
    }
    const bool mirrored = aiMatrix3x3(world).Determinant() < 0;
    p.indices.reserve(std::size_t(mesh.mNumFaces) * 3);
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3) continue;  // SortByPType left points and lines in other meshes
      const unsigned a = face.mIndices[0], b = face.mIndices[mirrored ? 2 : 1],
                     c = face.mIndices[mirrored ? 1 : 2];
      if (a >= mesh.mNumVertices || b >= mesh.mNumVertices || c >= mesh.mNumVertices)
        throw MeshError(source_,
                        "mesh '" + name + "': face " + std::to_string(f) + " has an index out of range");
      p.indices.insert(p.indices.end(), {a, b, c});
    }
    vertices_ += p.positions.size();
    triangles_ += p.indices.size() / 3;
    out_.geometry.primitives.push_back(std::move(p));
  }

  const aiScene& s_;
  std::string_view source_;
  const SidecarFiles& files_;
  const MeshOptions& options_;
  MeshImport& out_;
  std::map<std::string, int> image_slot_;  // texture reference -> SourceGeometry image (-1: none)
  std::size_t vertices_ = 0, triangles_ = 0;
};

// Quads and n-gons in the file, before Triangulate. Also sets each mesh's primitive types from
// its faces: Debian's Assimp is built with its internal assertions on, which abort the process,
// and Triangulate asserts that a mesh flagged as having polygons has one (a malformed OBJ can
// break that).
void count_polygons(const aiScene& scene, std::string_view source, std::vector<std::string>& warnings) {
  std::size_t quads = 0, ngons = 0;
  for (unsigned m = 0; m < scene.mNumMeshes; ++m) {
    aiMesh& mesh = *scene.mMeshes[m];
    unsigned types = 0;
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const unsigned n = mesh.mFaces[f].mNumIndices;
      if (n == 0)
        throw MeshError(source,
                        "mesh " + std::to_string(m) + ": face " + std::to_string(f) + " has no vertices");
      quads += n == 4;
      ngons += n > 4;
      types |= n == 1   ? aiPrimitiveType_POINT
               : n == 2 ? aiPrimitiveType_LINE
               : n == 3 ? aiPrimitiveType_TRIANGLE
                        : aiPrimitiveType_POLYGON;
    }
    mesh.mPrimitiveTypes = types;
  }
  if (quads + ngons > 0)
    warnings.push_back(std::string(source) + ": warning: " + std::to_string(quads) + " quad(s) and " +
                       std::to_string(ngons) + " polygon(s) of more than 4 sides triangulated");
}

}  // namespace

MeshImport read_assimp(const std::string& bytes, std::string_view source, std::string_view format,
                       const SidecarFiles& files, const MeshOptions& options) {
  if (bytes.size() > kMaxMeshFileBytes)
    throw MeshError(source, "file is larger than the import's limit of 256 MiB");
  if (format == "ply") check_ply_header(bytes, source);
  // Assimp picks its reader by the extension of the path it is given: always the resolved
  // format's, so the reader is the one the checks above were chosen for (a PLY body in "x.obj"
  // read as PLY has had its header checked).
  std::string stem = std::filesystem::path(std::string(source)).stem().string();
  if (stem.empty()) stem = "model";
  const std::filesystem::path name = stem + "." + std::string(format);
  const std::string model_path = (files.base_dir() / name).string();
  Assimp::Importer importer;
  importer.SetIOHandler(new AssimpFiles(model_path, bytes, files));
  importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_PRESERVE_PIVOTS, false);
  MeshImport out;
  out.facts.format = std::string(format);
  try {
    const aiScene* scene = importer.ReadFile(model_path, aiProcess_ValidateDataStructure);
    if (scene == nullptr || scene->mRootNode == nullptr) {
      std::string why = importer.GetErrorString();
      while (!why.empty() && (why.back() == '\n' || why.back() == ' ')) why.pop_back();
      throw MeshError(source, why.empty() ? std::string("Assimp read no scene") : why);
    }
    count_polygons(*scene, source, out.warnings);
    scene = importer.ApplyPostProcessing(aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                         aiProcess_SortByPType | aiProcess_FlipUVs);
    if (scene == nullptr) throw MeshError(source, importer.GetErrorString());
    Reader(*scene, source, files, options, out).read();
  } catch (const std::bad_alloc&) {
    throw MeshError(source, "out of memory while reading (corrupt counts or a very large asset)");
  }
  return out;
}

}  // namespace sylva::import
