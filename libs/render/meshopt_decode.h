// EXT_meshopt_compression in sylva's renderer: a GLB whose buffer views are meshopt-compressed
// becomes the equivalent plain GLB before tinygltf reads it (tinygltf 2.7 knows neither the
// extension nor a buffer without data). Decoded with Debian's meshoptimizer, as three.js's
// MeshoptDecoder does: ATTRIBUTES, TRIANGLES and INDICES modes; NONE, OCTAHEDRAL, QUATERNION and
// EXPONENTIAL filters (gltfpack's output reads too).
#pragma once

#include <functional>
#include <optional>
#include <stdexcept>
#include <string>

namespace sylva::render {

// A .gltf (JSON text) that uses EXT_meshopt_compression over external buffers (a pack's forest
// tiles and level files, libs/gltf/meshopt_files.h): returns the same asset as a GLB whose binary
// chunk holds every buffer named by a file uri (each 4-byte aligned, views and the extension's
// sources moved with it), the fallback buffers kept, for decode_meshopt_glb to decode. nullopt
// (nothing read) when the text does not use the extension or is not a glTF JSON object.
// `read_uri(uri)` returns the bytes of a buffer's uri as written in the file (percent-encoded,
// relative to the .gltf); it throws std::runtime_error when it cannot. Throws std::runtime_error
// when a buffer's file is shorter than its byteLength.
std::optional<std::string> meshopt_gltf_as_glb(
    const std::string& json_text, const std::function<std::string(const std::string&)>& read_uri);

// Returns false (bytes untouched) when the GLB does not use the extension; else rewrites `bytes`
// to a GLB with every compressed view decoded into the binary chunk and the fallback buffers
// gone. Throws std::runtime_error with a one-line reason on malformed data.
bool decode_meshopt_glb(std::string& bytes);

}  // namespace sylva::render
