// Where a point beyond the wall gets its tangent plane when projection cannot
// give one, and whether a point's path from x_t tunnelled through a wall
// (internal to the contact solver, contact_solver.cpp). Declared and
// documented in wall_planes.h.
#include "wall_planes.h"

#include <limits>

namespace evsim {
namespace walls {
namespace {

/// Moves a point within the tolerance band beyond the wall (g < 0) to just
/// inside, at its projection plus 0.1 um along the normal, with its field
/// sample; false when that fails (no projection). A point inside stays.
bool justInside(const ImplicitSurface& surface, double radius, const MotionSnapshot& motion,
                const RootOptions& root, Vec3* p, FieldSample* g) {
  if (g->value >= 0.0) return true;
  constexpr double kJustInside = 1e-7;  // [m], well within the 1 um contact tolerance
  const SurfacePoint wall = projectToSurfaceFrom(surface, *p, *g, radius, motion, 0.01, root);
  if (!wall.hit) return false;
  *p = wall.point + kJustInside * wall.normal;
  *g = surface.evaluate(*p, radius, motion);
  return g->value > 0.0;
}

/// Below this first-order depth [m] a point beyond the wall is within the
/// tolerance band for noTunnelPossible (justInside moves such an end by
/// about its depth).
constexpr double kBandDepth = 5e-6;
/// How deep [m] a chord from or to the band must run to count as a tunnel.
constexpr double kTissue = 1e-3;

/// True when tunnelExit cannot find a tunnel on p0 -> p, proved from the
/// field at the two ends and a bound H of the Hessian around the chord (a
/// step's chord is micrometres long, H L^2 tiny): no root when both ends are
/// inside and g stays positive along it, g >= min(g0, g) - H L^2 / 8; from
/// or to the band, no point within the band's reach of the chord deeper
/// than kTissue. Spares the two projections and root searches of every
/// point pressed against the wall at every step. False: not proved.
bool noTunnelPossible(const ImplicitSurface& surface, const Vec3& p0, const FieldSample& g0,
                      const Vec3& p, const FieldSample& g, double radius) {
  const double G0 = g0.gradient.norm(), G1 = g.gradient.norm();
  const double length = (p - p0).norm();
  if (g0.value >= 0.0 && g.value >= 0.0) {
    const double H = surface.hessianBound(p0, p, radius);
    return std::min(g0.value, g.value) - 0.125 * H * length * length > 0.0;
  }
  // An end beyond the band is not from the band: tunnelExit decides.
  const auto inBand = [](const FieldSample& s, double G) {
    return s.value >= 0.0 || (G > 0.0 && -s.value <= kBandDepth * G);
  };
  if (!inBand(g0, G0) || !inBand(g, G1)) return false;
  const double reach = 4.0 * kBandDepth;  // where justInside may move the ends
  const Vec3 pad = Vec3::Constant(reach);
  const double H = surface.hessianBound(p0.cwiseMin(p) - pad, p0.cwiseMax(p) + pad, radius);
  const double g_low = std::min(g0.value, g.value) - 0.125 * H * length * length -
                       (std::max(G0, G1) + 0.5 * H * length) * reach - 0.5 * H * reach * reach;
  const double slope_low = std::min(G0, G1) - H * (0.5 * length + reach);
  return slope_low > 0.0 && g_low >= -kTissue * slope_low;
}

}  // namespace

/// Where a point's straight path p0 -> p, from inside (or the tolerance
/// band beyond the wall) to inside (or the band), left its
/// lumen through a wall into another lumen (hit false when it did not). The
/// path counts as tunnelling, between two points inside, when the wall where
/// it re-enters faces the other way (opposite normals): a chord that grazes
/// a convex wall (a point sliding around the inner side of a bend) leaves
/// and re-enters the same wall, with nearly equal normals, and is not a
/// tunnel. From or to the band, when the chord runs more than 1 mm deep.
SurfacePoint tunnelExit(const ImplicitSurface& surface, const Vec3& p0, const FieldSample& g0,
                        const Vec3& p, const FieldSample& g, double radius,
                        const MotionSnapshot& motion, const RootOptions& root) {
  // An end within the tolerance band beyond the wall counts from just
  // inside, at its projection: else a path through the tissue from or to
  // there would never count (step 1,871 of 'tortuous' took the J-tip 12 mm
  // across a hairpin so, from the band to the band).
  if (noTunnelPossible(surface, p0, g0, p, g, radius)) return {};
  Vec3 from = p0, to = p;
  FieldSample g_from = g0, g_to = g;
  if (!justInside(surface, radius, motion, root, &from, &g_from) ||
      !justInside(surface, radius, motion, root, &to, &g_to))
    return {};
  const SurfacePoint exit = firstRootBetween(surface, from, g_from, to, g_to, radius, motion, root);
  if (!exit.hit || exit.started_outside) return {};
  const SurfacePoint entry =
      firstRootBetween(surface, to, g_to, from, g_from, radius, motion, root);
  if (!entry.hit || entry.started_outside) return {};
  // Between two points inside: a tunnel when the walls face each other.
  if (g0.value >= 0.0 && g.value >= 0.0)
    return exit.normal.dot(entry.normal) < 0.0 ? exit : SurfacePoint{};
  // From or to the band (a point pressed against a wall): when the chord
  // runs deep in the tissue, at its middle more than kTissue beyond the
  // wall (the J-tip's chord across a hairpin whose legs lie in different
  // planes: walls at an angle). Pressed coil points swinging across an
  // aneurysm's neck in the loop's iterates cut its rim by 0.3-0.5 mm
  // (chords 1-2 mm outside, walls facing each other) and come back in later
  // loops; counting them ran 'aneurysm' out of loops.
  const FieldSample middle = surface.evaluate(0.5 * (exit.point + entry.point), radius, motion);
  const double slope = middle.gradient.norm();
  const bool deep = middle.value < 0.0 && (slope == 0.0 || -middle.value / slope > kTissue);
  return deep ? exit : SurfacePoint{};
}

/// Where the straight path p0 -> p, starting beyond the wall, leaves the
/// lumen after it first enters it (hit false when it never enters), from
/// the first of 32 points along it that lies inside.
SurfacePoint farExit(const ImplicitSurface& surface, const Vec3& p0, const Vec3& p, double radius,
                     const MotionSnapshot& motion, const RootOptions& root) {
  constexpr int kProbes = 32;
  for (int i = 1; i < kProbes; ++i) {
    const Vec3 q = p0 + (static_cast<double>(i) / kProbes) * (p - p0);
    const FieldSample g = surface.evaluate(q, radius, motion);
    if (g.value > 0.0) return firstRootFrom(surface, q, g, p, radius, motion, root);
  }
  return {};
}

/// The wall nearest to where the straight path p0 -> p, outside the lumen
/// throughout, leaves the vessels' support: the projection of the last of
/// 32 points along it within the support (p0's when none is; hit false when
/// even that has no projection).
SurfacePoint lastWallAlong(const ImplicitSurface& surface, const Vec3& p0, const Vec3& p,
                           double radius, const MotionSnapshot& motion, const RootOptions& root) {
  constexpr int kProbes = 32;
  for (int i = 1; i < kProbes; ++i) {
    const Vec3 q = p + (static_cast<double>(i) / kProbes) * (p0 - p);
    if (surface.evaluate(q, radius, motion).gradient.norm() == 0.0) continue;
    const SurfacePoint wall = projectToSurface(surface, q, radius, motion, 0.01, root);
    if (wall.hit) return wall;
  }
  return projectToSurface(surface, p0, radius, motion, 0.01, root);
}

/// Depth beyond the surface [m] (0 inside), from g / |grad g|.
double depthOf(const FieldSample& g) {
  if (g.value >= 0.0) return 0.0;
  const double n = g.gradient.norm();
  // Beyond every vessel's support the field is flat (g = -T, no gradient):
  // the point lies outside all of them, as deep as it gets.
  return n > 0.0 ? -g.value / n : std::numeric_limits<double>::infinity();
}

}  // namespace walls
}  // namespace evsim
