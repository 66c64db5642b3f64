// The camera of the error model's checks (docs/lod-model.md): a representation valid
// from distance d is judged with the eye at distance d from the NEAREST point of the full-detail
// bounding box, so every surface is at least d away, where the bound holds. Shared by `sylva
// lodcheck` (stages/lod/check) and `sylva impostorcheck` (stages/impostor/check), so LOD levels
// and impostors are measured at the same distances.
#pragma once

#include "libs/render/camera.h"
#include "libs/render/scene.h"

namespace sylva::render {

// Looks at the box centre from azimuth `azimuth_deg` (0 = from +Z, 90 = from +X) and elevation
// `elevation_deg` (positive = from above), the eye `distance` metres (> 0) from the nearest point
// of `bounds` (an empty box is a unit box at the origin). fov_y_rad is the field of view of an
// image of `height_px` rows; with crop_px > 0 the camera keeps that pixel scale but sees only
// the central crop_px x crop_px pixels (its fov narrowed to match), so a small subject costs a
// small image. name = "az<azimuth>" (and "_el<elevation>" when the elevation is not 0).
Camera camera_at_box_distance(const Bounds& bounds, double distance, double azimuth_deg, double elevation_deg,
                              double fov_y_rad, int height_px = 0, int crop_px = 0);

}  // namespace sylva::render
