// glTF JSON numbers as short as their float: every client reads glTF's non-integer numbers
// (material factors, node TRS, accessor min/max, KHR_texture_transform) as 32-bit floats, so
// printing the 17 digits of a float widened to double (0.800000011920929) carries nothing a
// client uses. docs/gltf.md "meshopt" says where the writer applies it.
#pragma once

#include <nlohmann/json.hpp>

namespace sylva::gltf {

// The double nearest the shortest decimal that reads back as float(v) (std::to_chars of the
// float, then std::strtod): a writer printing doubles shortest (nlohmann::json does) prints
// that decimal, 0.8 for 0.8f. float(float_json(v)) == float(v) for every finite v; non-finite
// values are returned unchanged.
double float_json(double v);

// Rewrites a glTF document's numbers in place: outside `extras` (the producer's own data, kept
// as written), every non-integer number becomes float_json of it and every integral one an
// integer (1.0 -> 1: the same JSON number). Float accessors' min/max still bound their data
// exactly as floats (glTF-Validator compares them in single precision). Also drops each mesh
// primitive's "mode": 4 (triangles, the schema's default). Deterministic.
void compact_gltf_numbers(nlohmann::json& gltf);

}  // namespace sylva::gltf
