// How closely the convolution surface reproduces a centreline's radii: the
// lumen radius of the implicit surface, measured along rays perpendicular
// to the centreline from the midpoint of every segment, against the
// centreline's radius there. Segments within two radii of a junction or an
// end, or within a radius of another vessel's lumen, are reported apart:
// there the kernels of neighbouring segments blend (a bulge at a fork, a
// rounded cap at an end, two close lumens merged), by design of the surface.
#pragma once

#include "endovascular_sim/geometry/centerline.h"
#include "endovascular_sim/geometry/implicit_surface.h"

namespace evsim {

struct FidelityFigures {
  int rays{0};
  double median{0.0};  // |lumen radius / centreline radius - 1|
  double worst{0.0};
};

struct SurfaceFidelity {
  FidelityFigures along;     // away from junctions and ends
  FidelityFigures at_forks;  // near a junction, an end or another vessel's lumen
};

/// Four rays per segment midpoint (device radius 0).
SurfaceFidelity measureSurfaceFidelity(const ImplicitSurface& surface, const Centerline& c);

}  // namespace evsim
