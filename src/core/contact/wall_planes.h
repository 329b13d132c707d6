// Where a point beyond the wall gets its tangent plane when projection
// cannot give one, and whether a point's path from x_t tunnelled through a
// wall (internal to the contact solver, contact_solver.cpp).
#pragma once

#include "endovascular_sim/geometry/implicit_surface.h"
#include "endovascular_sim/geometry/root_finding.h"

namespace evsim {
namespace walls {

/// Depth beyond the surface [m] (0 inside), from g / |grad g|; beyond every
/// vessel's support (a flat field) infinite.
double depthOf(const FieldSample& g);

/// Where a point's straight path p0 -> p left its lumen through a wall into
/// another lumen (hit false when it did not); see wall_planes.cpp.
SurfacePoint tunnelExit(const ImplicitSurface& surface, const Vec3& p0, const FieldSample& g0,
                        const Vec3& p, const FieldSample& g, double radius,
                        const MotionSnapshot& motion, const RootOptions& root);

/// Where the straight path p0 -> p, starting beyond the wall, leaves the
/// lumen after it first enters it (hit false when it never enters).
SurfacePoint farExit(const ImplicitSurface& surface, const Vec3& p0, const Vec3& p, double radius,
                     const MotionSnapshot& motion, const RootOptions& root);

/// The wall nearest to where the straight path p0 -> p, outside the lumen
/// throughout, leaves the vessels' support (p0's projection when it never
/// is within it).
SurfacePoint lastWallAlong(const ImplicitSurface& surface, const Vec3& p0, const Vec3& p,
                           double radius, const MotionSnapshot& motion, const RootOptions& root);

}  // namespace walls
}  // namespace evsim
