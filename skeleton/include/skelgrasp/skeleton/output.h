#pragma once
// Serialisation of the skeleton stage: skeleton.json (schema in docs/skeleton.md) and coloured
// segmentation meshes.
#include <nlohmann/json.hpp>

#include <string>

#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/skeleton/extraction.h"

namespace skelgrasp::skeleton {

// The "skelgrasp.skeleton/1" document for a stage result on `input` loaded as `load_info`.
nlohmann::json skeletonToJson(const SkeletonResult& result, const TriangleMesh& input,
                              const MeshLoadInfo& load_info);

// Paper Fig. 3 colours per input vertex, after the type of its skeleton vertex:
// red = endpoint, yellow = connecting, blue = branch.
TriangleMesh colourByVertexType(const TriangleMesh& input, const Skeleton& skeleton);

// A distinct colour per segment; branch regions grey.
TriangleMesh colourBySegment(const TriangleMesh& input, const Skeleton& skeleton);

// PNG with four panels: the input coloured by vertex type (Fig. 3 colours) from two sides, and the
// skeleton (red endpoints, blue branches, black edges) over the grey mesh from the same sides.
void renderSkeletonPng(const TriangleMesh& input, const Skeleton& skeleton, const std::string& path,
                       int panel_width = 480, int panel_height = 480);

// One-line human summary.
std::string summaryLine(const SkeletonResult& result, const std::string& name);

}  // namespace skelgrasp::skeleton
