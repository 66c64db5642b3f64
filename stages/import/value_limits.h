// The value ranges every importer enforces (issue 15 item 12): finite input can still break
// every later stage (a coordinate of 1.7e308 overflows the first subtraction, a radius of 1e308
// the first area). A tree is at most a few hundred metres tall, so anything beyond these bounds
// is a unit or export error, reported at its file and line.
#pragma once

namespace sylva::import {

// |x|, |y|, |z| of a node, in metres after scaling (and, for QSM tables, recentring): 100 km.
inline constexpr double kMaxCoordinateM = 1e5;
// A node's or cylinder's radius, in metres after scaling.
inline constexpr double kMaxRadiusM = 100.0;

}  // namespace sylva::import
