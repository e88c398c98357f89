#pragma once
// The parts of the module, one per binding file (module.cpp calls them in this order).
#include <pybind11/pybind11.h>

namespace skelgrasp::python {

void bindGeometry(pybind11::module_& m);  // Mesh, PointCloud, load_*, skeleton
void bindOptions(pybind11::module_& m);   // PlanOptions and the Params it holds
void bindGrasping(pybind11::module_& m);  // hands, plan, pictures
void bindScoring(pybind11::module_& m);   // close, score, score_grasps
void bindPhysics(pybind11::module_& m);   // simulate
void bindPipeline(pybind11::module_& m);  // reconstruct, run

}  // namespace skelgrasp::python
