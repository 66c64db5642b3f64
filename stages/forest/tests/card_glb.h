// Test fixture shared by the forest stage's tests: impostor.glb as the impostor stage writes it
// (one unlit card of half width 1 m and height h, a 2 x 2 PNG embedded in the buffer).
#pragma once

#include <string>

namespace sylva::forest::testing {

// blend: the card's material is alphaMode BLEND (as the stage's default `glb_alpha`), else OPAQUE;
// normals: the card carries NORMAL (+Z).
std::string card_glb(double h = 2, bool blend = false, bool normals = false);

}  // namespace sylva::forest::testing
