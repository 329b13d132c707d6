// `evsim bench accuracy`: what each accuracy knob costs in time.
//
//   SCENE   runs the scene for --duration simulated seconds once per setting
//           of one knob (solver, PGS sweeps, penetration tolerance,
//           activation-loop limit, subdivision limit, root tolerance,
//           elements per device, time step), the others at the scene's
//           values, and compares the tip with a fine reference run (time
//           step / 4, twice the elements, tight tolerances).
//   beam    the beam discretisation alone: a cantilever of the guidewire's
//           shaft under a large tip load (PL^2/EI = 5), tip error against
//           800 elements, cost = one implicit-Euler free-motion step.
//   root    the first-root search alone: random segments through the carotid
//           wall, root position error against the search at 1e-13 m.
//
// One CSV row per setting (--csv FILE, default stdout):
//   knob,setting,cost,cost_unit,error_m,max_penetration_m,max_residual,rejected
// scripts/plot_accuracy.py draws error against cost with the Pareto front.
#pragma once

#include <string>

namespace evsim {

/// The sweep of `what` (SCENE, beam or root) over `duration` simulated
/// seconds; rows to `csv` ("" stdout).
int accuracyCommand(const std::string& what, double duration, const std::string& csv);

}  // namespace evsim
