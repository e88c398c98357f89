#pragma once
// Pictures of hands and grasps (PNG through presentation/render.h), and the hand as meshes for
// reports' 3D views.
#include <string>
#include <vector>

#include "skelgrasp/grasping/contact.h"
#include "skelgrasp/grasping/hand/hand_model.h"
#include "skelgrasp/presentation/render.h"

namespace skelgrasp::presentation {

// The hand's collision geometry at (hand_pose, q) as one mesh, coloured per finger (palm grey).
TriangleMesh handMesh(const grasping::HandModel& hand, const Pose& hand_pose,
                      const Eigen::VectorXd& q);

// One link's collision geometry in the link's own frame (empty for a link without shapes), and the
// colour handMesh gives it.
TriangleMesh linkMesh(const grasping::HandModel& hand, int link);
Rgb linkColour(const grasping::HandModel& hand, int link);

// Draws contacts as points with short normal lines.
void drawContacts(Canvas& canvas, const std::vector<grasping::Contact>& contacts,
                  double normal_length_m);

// Object plus the hand in its preshape (left) and closed (right), from two viewpoints (2 x 2).
void renderGraspPng(const std::string& path, const TriangleMesh& object,
                    const grasping::HandModel& hand, const Pose& hand_pose,
                    const Eigen::VectorXd& preshape_q, const Eigen::VectorXd& closed_q,
                    const std::vector<grasping::Contact>& contacts, int panel_size = 480);

}  // namespace skelgrasp::presentation
