#pragma once
// Pictures of hands and grasps (PNG through common/render.h).
#include <string>
#include <vector>

#include "skelgrasp/common/render.h"
#include "skelgrasp/grasping/contact.h"
#include "skelgrasp/grasping/hand/hand_model.h"

namespace skelgrasp::grasping {

// The hand's collision geometry at (hand_pose, q) as one mesh, coloured per finger (palm grey).
TriangleMesh handMesh(const HandModel& hand, const Pose& hand_pose, const Eigen::VectorXd& q);

// One link's collision geometry in the link's own frame (empty for a link without shapes), and the
// colour handMesh gives it.
TriangleMesh linkMesh(const HandModel& hand, int link);
Rgb linkColour(const HandModel& hand, int link);

// Draws contacts as points with short normal lines.
void drawContacts(render::Canvas& canvas, const std::vector<Contact>& contacts,
                  double normal_length_m);

// Object plus the hand in its preshape (left) and closed (right), from two viewpoints (2 x 2).
void renderGraspPng(const std::string& path, const TriangleMesh& object, const HandModel& hand,
                    const Pose& hand_pose, const Eigen::VectorXd& preshape_q,
                    const Eigen::VectorXd& closed_q, const std::vector<Contact>& contacts,
                    int panel_size = 480);

}  // namespace skelgrasp::grasping
