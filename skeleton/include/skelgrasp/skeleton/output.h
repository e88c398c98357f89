#pragma once
// Serialisation of the skeleton stage: skeleton.json (schema in docs/skeleton.md) and coloured
// segmentation meshes (their picture: presentation/skeleton_render.h).
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

// One-line human summary.
std::string summaryLine(const SkeletonResult& result, const std::string& name);

}  // namespace skelgrasp::skeleton
