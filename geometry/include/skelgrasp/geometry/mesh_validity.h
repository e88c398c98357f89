#pragma once
// Whether a mesh has a surface at all, checked before any stage that needs one (the alpha wrap,
// the planners) runs on it.
#include <string>

#include "skelgrasp/common/mesh.h"

namespace skelgrasp::geometry {

// A face counts as having area when it exceeds this fraction of the squared bounding-box
// diagonal: collinear corners give a cross product of rounding size (about 1e-16 of it), which
// must not count, while any real sliver of a scan is far above it.
inline constexpr double kMinFaceAreaOfDiagonalSquared = 1e-12;

// "degenerate mesh: <why>" when no face of `mesh` has a positive area (collinear or coincident
// corners, a single point, coordinates too large for their extent to be finite), else "". CGAL's
// alpha wrap skips faces without area and crashed (SIGSEGV) on an input with none left; the
// surface planner drew samples from it until its time limit. A flat mesh with area has a
// surface: its wrap is a thin closed shell. An empty mesh is the caller's business.
std::string degenerateMeshProblem(const TriangleMesh& mesh);

}  // namespace skelgrasp::geometry
