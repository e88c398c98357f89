#pragma once
// A picture of a skeleton on its mesh (`skelgrasp skeleton --render`).
#include <string>

#include "skelgrasp/common/mesh.h"
#include "skelgrasp/skeleton/skeleton.h"

namespace skelgrasp::presentation {

// PNG with four panels: the input coloured by vertex type (Fig. 3 colours) from two sides, and the
// skeleton (red endpoints, blue branches, black edges) over the grey mesh from the same sides.
void renderSkeletonPng(const TriangleMesh& input, const skeleton::Skeleton& skeleton,
                       const std::string& path, int panel_width = 480, int panel_height = 480);

}  // namespace skelgrasp::presentation
