#pragma once
// One entry point for every input the CLI accepts: a PCD/PLY cloud, a capture description
// (.json) or a YCB raw capture folder.
#include <string>

#include "skelgrasp/datasets/ycb_raw.h"
#include "skelgrasp/perception/cloud_io.h"
#include "skelgrasp/perception/scan.h"

namespace skelgrasp::datasets {

enum class InputKind { kCloud, kCapture, kYcbRaw };
const char* toString(InputKind kind);  // "cloud", "capture", "ycb_raw"

struct InputOptions {
  perception::CloudLoadOptions units;
  YcbRawParams ycb;
};

// Decides by what `path` is (.pcd/.ply file, .json file, folder with calibration.h5) and loads it.
// Throws IoError("<path>: <problem>") for anything unreadable or unrecognised.
perception::Scan loadInput(const std::string& path, const InputOptions& options = {},
                           InputKind* kind = nullptr);

}  // namespace skelgrasp::datasets
