#pragma once
// The files of `skelgrasp run`.
#include <nlohmann/json.hpp>

#include <functional>
#include <string>

#include "skelgrasp/common/atomic_file.h"

#include "skelgrasp/grasping/hand/hand_model.h"
#include "skelgrasp/perception/scan.h"
#include "skelgrasp/pipeline/run_pipeline.h"
#include "skelgrasp/pipeline/run_scene.h"

namespace skelgrasp::pipeline {

// The grasps.json document of a run (schema skelgrasp.run/4, docs/pipeline.md), as
// writeRunOutputs writes it (the Python module's to_dict()).
nlohmann::json runToJson(const RunResult& result, const grasping::HandModel& hand,
                         const perception::Scan& scan, const std::string& input_name);

// More files of a run written with the others (the exports of `run --export`): staged in
// `outputs` from the grasps.json document, before grasps.json itself.
using ExtraRunOutputs =
    std::function<void(OutputTransaction& outputs, const nlohmann::json& grasps_document)>;

// Writes DIR/grasps.json (the plan schema plus scene fields), object.ply (with observed flags),
// skeleton.json, segmentation.ply, scene.bt and report.html with its PNG pictures, and `extra`'s
// files. All of them appear together at the end (atomic_file.h, OutputTransaction), grasps.json
// last; on an error none is written and DIR is not created. They replace the files a previous run
// wrote in DIR (OutputTransaction::replacePreviousOutputsIn): a run never leaves another run's
// object_3.ply beside its own grasps.json.
void writeRunOutputs(const std::string& dir, const RunResult& result,
                     const grasping::HandModel& hand, const perception::Scan& scan,
                     const std::string& input_name, const ExtraRunOutputs& extra = {});

// The grasps.json document of a scene run (schema skelgrasp.run/4 with every object), as
// writeSceneRunOutputs writes it (the Python module's to_dict()).
nlohmann::json sceneRunToJson(const SceneRunResult& result, const grasping::HandModel& hand,
                              const perception::Scan& scan, const std::string& input_name);

// The files of a scene run (`run --object all`, docs/pipeline.md): DIR/grasps.json with every
// object, object_<id>.ply and skeleton_<id>.json per meshed object, scene.bt, report.html with
// the scene overview and a section per object, with its PNG pictures. Same all-or-nothing
// guarantee, `extra` and replacement of a previous run's files as writeRunOutputs.
void writeSceneRunOutputs(const std::string& dir, const SceneRunResult& result,
                          const grasping::HandModel& hand, const perception::Scan& scan,
                          const std::string& input_name, const ExtraRunOutputs& extra = {});

}  // namespace skelgrasp::pipeline
