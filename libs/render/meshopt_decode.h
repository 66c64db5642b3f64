// EXT_meshopt_compression in sylva's renderer: a GLB whose buffer views are meshopt-compressed
// becomes the equivalent plain GLB before tinygltf reads it (tinygltf 2.7 knows neither the
// extension nor a buffer without data). Decoded with Debian's meshoptimizer, as three.js's
// MeshoptDecoder does: ATTRIBUTES, TRIANGLES and INDICES modes; NONE, OCTAHEDRAL, QUATERNION and
// EXPONENTIAL filters (gltfpack's output reads too).
#pragma once

#include <stdexcept>
#include <string>

namespace sylva::render {

// Returns false (bytes untouched) when the GLB does not use the extension; else rewrites `bytes`
// to a GLB with every compressed view decoded into the binary chunk and the fallback buffers
// gone. Throws std::runtime_error with a one-line reason on malformed data.
bool decode_meshopt_glb(std::string& bytes);

}  // namespace sylva::render
