// gltf::Scene -> tinygltf::Model (model_builder.h) -> bytes. Everything goes into one buffer
// (external .gltf: one buffer per Scene::buffer_uris entry) in a fixed order (writer.h, "Layout"),
// so equal scenes give equal bytes. tinygltf serialises the JSON (keys in a fixed order) and
// frames the GLB, or meshopt_encode.h does; images are handed to tinygltf as buffer views with a
// mime type, which it writes as they are (it re-encodes only images given as decoded pixels).
//
// tinygltf comes from Debian's shared library (TinyGLTF::TinyGLTF), which already contains the
// implementation: no sylva translation unit defines TINYGLTF_IMPLEMENTATION.
#include "libs/gltf/writer.h"

#include <tiny_gltf.h>

#include <fstream>
#include <sstream>

#include "libs/gltf/meshopt_encode.h"
#include "libs/gltf/model_builder.h"

namespace sylva::gltf {
namespace {

void check_scene(const Scene& scene) {
  const std::vector<std::string> problems = validate_scene(scene);
  if (!problems.empty()) {
    std::string msg = "invalid glTF scene: " + problems.front();
    if (problems.size() > 1) msg += " (and " + std::to_string(problems.size() - 1) + " more problems)";
    throw GltfError(msg);
  }
}

}  // namespace

const char* extension(FileFormat format) { return format == FileFormat::kGlb ? ".glb" : ".gltf"; }

void encode_to(const Scene& scene, std::ostream& out, const WriteOptions& options) {
  if (options.format == FileFormat::kGltfExternal)
    throw GltfError("an external .gltf is several files: use encode_external()");
  check_scene(scene);
  if (options.meshopt && (options.format != FileFormat::kGlb || options.draco.enabled))
    throw GltfError("EXT_meshopt_compression is written to GLB files without Draco only");
  detail::BuiltModel built = detail::build_model(scene, options);
  tinygltf::Model& model = built.model;
  if (options.meshopt) {
    const std::string bytes =
        detail::encode_meshopt_glb(model, built.view_filters, options.meshopt_merge_views);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return;
  }
  tinygltf::TinyGLTF writer;
  const bool glb = options.format == FileFormat::kGlb;
  if (!writer.WriteGltfSceneToStream(&model, out, /*prettyPrint=*/!glb, /*writeBinary=*/glb))
    throw GltfError("tinygltf could not serialise the scene");
}

std::string encode(const Scene& scene, const WriteOptions& options) {
  std::ostringstream out(std::ios::binary);
  encode_to(scene, out, options);
  return std::move(out).str();
}

EncodedFiles encode_external(const Scene& scene, const WriteOptions& options) {
  check_scene(scene);
  WriteOptions o = options;
  o.format = FileFormat::kGltfExternal;
  detail::BuiltModel built = detail::build_model(scene, o);
  tinygltf::Model& model = built.model;
  tinygltf::TinyGLTF writer;
  std::ostringstream out(std::ios::binary);
  if (!writer.WriteGltfSceneToStream(&model, out, /*prettyPrint=*/true, /*writeBinary=*/false))
    throw GltfError("tinygltf could not serialise the scene");
  // tinygltf's stream writer embeds every buffer as a data URI (here: empty ones) and gives
  // images without a buffer view no uri; name the files instead. nlohmann keeps keys sorted, so
  // the text stays deterministic.
  nlohmann::json j = nlohmann::json::parse(std::move(out).str());
  const std::vector<std::size_t>& sizes = built.buffer_sizes;
  for (std::size_t b = 0; b < sizes.size(); ++b)
    j["buffers"][b] = {{"byteLength", sizes[b]}, {"uri", model.buffers[b].uri}};
  for (std::size_t i = 0; i < model.images.size(); ++i) {
    const tinygltf::Image& im = model.images[i];
    if (im.uri.empty()) continue;
    nlohmann::json& ji = j["images"][i];
    ji.erase("bufferView");
    ji["uri"] = im.uri;
    ji["mimeType"] = im.mimeType;
  }
  EncodedFiles files;
  files.gltf = j.dump(2) + "\n";
  files.resources = std::move(built.resources);
  return files;
}

void write_file(const Scene& scene, const std::filesystem::path& path, const WriteOptions& options) {
  const std::string bytes = encode(scene, options);
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  if (!f) throw GltfError(path.string() + ": cannot open for writing");
  f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  f.close();
  if (!f) throw GltfError(path.string() + ": write failed");
}

}  // namespace sylva::gltf
