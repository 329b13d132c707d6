// The content of a ContactWorkspace (contact/contact_workspace.h).
#pragma once

#include <vector>

#include "activation_loop.h"
#include "device_pairs.h"
#include "endovascular_sim/contact/contact_workspace.h"

namespace evsim {

struct ContactWorkspace::Kept {
  pairs::PointCandidates point_candidates;   // sample-point pairs (pair_detection.cpp)
  pairs::PairCandidates element_candidates;  // element pairs (pair_detection.cpp)
  std::vector<std::vector<activation::RowPart>> row_parts;  // per device (contact_system.cpp)
  LcpWorkspace lcp;  // the status method's factor (contact_solver.cpp)
};

}  // namespace evsim
