// The vessel wall's give (the `vessel_deformation` effect): the centreline
// skeleton that defines the convolution surface, tethered to its rest shape
// by the surrounding tissue, bending and stretching as a thin-walled tube,
// and its lumen widening under the wall's load.
//
// The model, per named vessel (WallProperties), for small displacements
// (linear in the loads):
//  - tether: every point of the skeleton is pulled back to rest by k [N/m^2]
//    per unit length and per metre of displacement (a Winkler foundation of
//    the surrounding tissue) and damped by c [N s/m^2] per unit length;
//  - the wall: a thin-walled tube of radius R whose distensibility
//    D = dA / (A dp) [1/Pa] gives its wall's E h = 2 R / D (Laplace's law);
//    hence bending EI = pi R^3 E h = 2 pi R^4 / D [N m^2] and stretch
//    EA = 2 pi R E h = 4 pi R^2 / D [N];
//  - the radius: an outward load q [N/m] per unit length of vessel, smeared
//    over the circumference as a pressure p = q / (2 pi R), widens the lumen
//    by dR = D R p / 2 = D q / (4 pi) [m].
// Discretisation: one node per centreline point, three translations each;
// the tether and damping lumped over each node's half segments; the bending
// energy EI |d|^2 / (h1 + h2) per parent-point-child triple, d the change of
// the segment direction vectors divided by their lengths (the second
// difference, exact for a cubic).
#pragma once

#include <Eigen/Sparse>
#include <vector>

#include "endovascular_sim/core/types.h"
#include "endovascular_sim/geometry/centerline.h"

namespace evsim {

/// A number no other WallShape (implicit_surface.h) has had.
long newWallShapeVersion();

/// One vessel's wall and its surroundings.
struct WallProperties {
  double distensibility{1.2e-5};  // D [1/Pa]: relative lumen area change per pressure
  double tether_stiffness{5e3};   // k [N/m^2]: restoring force per length per displacement
  double tether_damping{50.0};    // c [N s/m^2]: damping force per length per velocity
};

/// The skeleton's stiffness and damping, assembled once for a centreline.
class VesselWall {
 public:
  VesselWall() = default;
  /// per_vessel: indexed as centerline.vessel_names. Points listed in
  /// `held` stay at rest (where an introducer sheath holds the vessel).
  VesselWall(const Centerline& centerline, const std::vector<WallProperties>& per_vessel,
             const std::vector<int>& held = {});

  int numNodes() const { return static_cast<int>(length_.size()); }
  /// Length of vessel a node stands for [m] (half its segments).
  double nodeLength(int node) const { return length_[node]; }
  /// Bending stiffness EI at a node [N m^2].
  double bendingStiffness(int node) const;
  bool held(int node) const { return held_[node] != 0; }

  /// Node displacements [m] in equilibrium with nodal loads [N]: K u = f.
  std::vector<Vec3> equilibrium(const std::vector<Vec3>& loads) const;
  /// Radius change [m] of a node under an outward load per unit length
  /// q [N/m] on its wall.
  double radiusChange(int node, double load_per_length) const;

  /// One implicit Euler step of C du/dt + K u = f over dt [s]:
  /// (K + C / dt) u1 = f + C u0 / dt. The factor of K + C / dt is kept in
  /// `factor` and made anew only when dt changes.
  /// A copy starts without a factor (it is made again, to the same bits).
  struct StepFactor {
    double dt{0.0};  // [s] the factor's (0: none)
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt;
    StepFactor() = default;
    StepFactor(const StepFactor&) {}
    StepFactor& operator=(const StepFactor&) { return dt = 0.0, *this; }
  };
  void step(const std::vector<Vec3>& loads, double dt, StepFactor* factor,
            std::vector<Vec3>* displacement) const;

  const Eigen::SparseMatrix<double>& stiffness() const { return stiffness_; }

 private:
  std::vector<double> length_;          // per node [m]
  std::vector<double> distensibility_;  // per node [1/Pa]
  std::vector<double> radius_;          // per node [m]
  std::vector<double> damping_;         // c l per node [N s/m]
  std::vector<char> held_;              // per node: kept at rest
  Eigen::SparseMatrix<double> stiffness_;
};

}  // namespace evsim
