// The points' side of a solve, as the LM loop on the main node sees it
// (docs/design.md §4). Every rank holds a share of the points; the main node holds
// the cameras and the global RCS. One rank (LocalPointWorkers) or many (the
// MPI transport) implement the same three steps:
//
//   FormRcs      every rank linearizes and eliminates its points; the sub-RCSs
//                are aggregated into the global RCS (paper eq. 4, section 6.1)
//   EvaluateStep δc goes out; every rank back-substitutes its points (eq. 5)
//                and evaluates the model and the true cost at the step; the
//                partial sums are reduced
//   FinishStep   the accept/reject decision goes out; ranks keep or drop their
//                candidate points
//
// Thread safety: one caller (the LM loop).
#pragma once

#include <vector>

#include "dba/rcs/back_substitute.h"
#include "dba/rcs/form_rcs.h"

namespace dba {

class PointWorkers {
 public:
  virtual ~PointWorkers() = default;

  // Global RCS at the current parameters and damping λ, cameras in global
  // numbering, S undamped in the camera blocks. The system is owned by the
  // workers and stays valid until the next call.
  virtual RcsSystem& FormRcs(double lambda) = 0;

  // Back-substitution and costs at cameras + δc (global numbering).
  virtual StepEvaluation EvaluateStep(
      double lambda, const std::vector<double>& delta_c,
      const std::vector<double>& candidate_cameras) = 0;

  // Makes the candidate of the last EvaluateStep current (accept) or drops it.
  virtual void FinishStep(bool accept) = 0;
};

}  // namespace dba
