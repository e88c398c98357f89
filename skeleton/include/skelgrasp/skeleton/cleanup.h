#pragma once
// Clean-up of a contracted skeleton: spurious terminal branches, vertices outside the material.
#include "skelgrasp/skeleton/extraction.h"

namespace skelgrasp::skeleton {

struct SpurPruningStats {
  std::size_t chains = 0;    // terminal chains removed
  std::size_t vertices = 0;  // skeleton vertices removed
};

// MCF contraction leaves short terminal branches where a rounded end or a junction collapses
// unevenly (a 2.5 cm radius capsule cap grew spurs of 1 and 7 mm). A terminal chain (endpoint ...
// up to the first branch vertex) is removed when its length is below radius_factor times the
// inscribed radius at that branch vertex (its distance to `closed_mesh`): it stays deep inside the
// part it hangs on. Real short parts survive: the arms of a mug body reaching past its handle are
// 0.6-1x the body radius, hence the default factor 0.5. Mesh vertices of removed skeleton vertices
// go to the branch vertex, keeping the partition exact. radius_factor <= 0 disables pruning.
SpurPruningStats pruneSpurs(Contraction& contraction, const TriangleMesh& closed_mesh,
                            double radius_factor);

}  // namespace skelgrasp::skeleton
