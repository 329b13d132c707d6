// Aortic arches drawn from anatomical statistics. Declared and documented
// in endovascular_sim/geometry/arch_generator.h; the ranges and their
// sources in docs/patient_anatomy.md ("Generated arches").
#include "endovascular_sim/geometry/arch_generator.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>

namespace evsim {
namespace {

constexpr double kSpacing = 0.001;  // [m] between centreline points

/// A seeded draw: uniform and truncated normal numbers.
struct Draw {
  std::mt19937_64 rng;
  explicit Draw(std::uint64_t seed) : rng(seed) {}
  double uniform(double lo, double hi) { return std::uniform_real_distribution<>(lo, hi)(rng); }
  /// Normal (mean, sd), truncated to mean +- 2 sd.
  double normal(double mean, double sd) {
    std::normal_distribution<> n(mean, sd);
    for (;;) {
      const double v = n(rng);
      if (std::abs(v - mean) <= 2.0 * sd) return v;
    }
  }
  bool chance(double p) { return uniform(0.0, 1.0) < p; }
};

/// The arch's centreline at parameter theta in [0, pi]: from the ascending
/// aorta's top (right, anterior) over the apex to the descending aorta's
/// top (left, posterior).
Vec3 archPoint(const ArchParameters& p, double theta) {
  return {-0.5 * p.width * std::cos(theta), 0.5 * p.depth * std::cos(theta),
          p.height * std::sin(theta)};
}

/// Builds a centreline vessel by vessel.
struct Builder {
  Centerline c;
  /// Appends a vessel through `points` with radii tapering r0 -> r1, its
  /// first point's parent `parent` (-1: a root). Returns its point indices.
  std::vector<int> vessel(const std::vector<Vec3>& points, double r0, double r1, int parent,
                          const std::string& name) {
    std::vector<int> ids;
    const int v = static_cast<int>(c.vessel_names.size());
    c.vessel_names.push_back(name);
    double total = 0.0;
    for (size_t i = 1; i < points.size(); ++i) total += (points[i] - points[i - 1]).norm();
    double s = 0.0;
    for (size_t i = 0; i < points.size(); ++i) {
      if (i > 0) s += (points[i] - points[i - 1]).norm();
      c.position.push_back(points[i]);
      c.radius.push_back(r0 + (r1 - r0) * (total > 0.0 ? s / total : 0.0));
      c.parent.push_back(ids.empty() ? parent : ids.back());
      c.type.push_back(v);
      c.vessel.push_back(v);
      ids.push_back(c.numPoints() - 1);
    }
    return ids;
  }
};

/// Points every kSpacing along a straight line a -> b (a excluded); a and b
/// by value: they may be points of *out.
void appendLine(const Vec3 a, const Vec3 b, std::vector<Vec3>* out) {
  const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / kSpacing)));
  for (int i = 1; i <= n; ++i) out->push_back(a + (b - a) * (static_cast<double>(i) / n));
}

/// A branch from `origin`: straight along `takeoff` for `clear` [m] (out of
/// the parent's lumen), then turning toward `heading` over `length` [m]
/// (a quadratic Bezier), points about every kSpacing; origin excluded.
std::vector<Vec3> branchPath(const Vec3& origin, const Vec3& takeoff, const Vec3& heading,
                             double clear, double length) {
  std::vector<Vec3> out;
  const Vec3 a = origin + clear * takeoff.normalized();
  appendLine(origin, a, &out);
  const Vec3 b = a + 0.5 * length * takeoff.normalized();
  const Vec3 e = b + 0.5 * length * heading.normalized();
  const int n = std::max(2, static_cast<int>(std::ceil(length / kSpacing)));
  for (int i = 1; i <= n; ++i) {
    const double t = static_cast<double>(i) / n;
    out.push_back((1 - t) * (1 - t) * a + 2 * (1 - t) * t * b + t * t * e);
  }
  return out;
}

/// `direction` tilted by `angle` [rad] about an axis across it (the
/// horizontal one, so a tilt leans the branch left/right or forward/back).
Vec3 tilted(const Vec3& direction, double angle, double azimuth) {
  const Vec3 d = direction.normalized();
  Vec3 across = d.cross(Vec3::UnitZ());
  if (across.norm() < 1e-6) across = Vec3::UnitX();
  across = Eigen::AngleAxisd(azimuth, d) * across.normalized();
  return Eigen::AngleAxisd(angle, across) * d;
}

/// The arch parameter theta at which the arch's length from theta = 0 is s [m].
double thetaAt(const ArchParameters& p, double s) {
  double walked = 0.0, theta = 0.0;
  const double dtheta = 1e-4;
  while (theta < M_PI && walked < s) {
    walked += (archPoint(p, theta + dtheta) - archPoint(p, theta)).norm();
    theta += dtheta;
  }
  return std::min(theta, M_PI);
}

double archLengthTo(const ArchParameters& p, double theta) {
  double walked = 0.0;
  const int n = 2000;
  for (int i = 0; i < n; ++i)
    walked += (archPoint(p, theta * (i + 1) / n) - archPoint(p, theta * i / n)).norm();
  return walked;
}

}  // namespace

std::string ArchParameters::summary() const {
  std::ostringstream o;
  o << "type " << (type == ArchType::kI ? "I" : type == ArchType::kII ? "II" : "III")
    << (bovine ? ", bovine" : "") << (aberrant_rsa ? ", aberrant right subclavian" : "")
    << ", elongation " << std::round(elongation * 100) / 100 << ", trunk "
    << std::round(trunk_drop * 1e4) / 10 << " mm below the apex";
  return o.str();
}

ArchParameters drawArch(std::uint64_t seed, const ArchDrawOptions& o) {
  Draw d(seed);
  ArchParameters p;
  p.seed = seed;
  // Variants, each with its population frequency unless asked for.
  const double u = d.uniform(0.0, 1.0);
  const int type = o.type != 0 ? o.type : u < 0.565 ? 1 : u < 0.893 ? 2 : 3;
  p.type = static_cast<ArchType>(type);
  p.bovine = o.bovine < 0 ? d.chance(0.136) : o.bovine == 1;
  p.aberrant_rsa = o.aberrant_rsa < 0 ? d.chance(0.010) : o.aberrant_rsa == 1;
  if (p.aberrant_rsa) p.bovine = false;  // (both together: rare, not drawn)
  // Elongation grows with age and with the type.
  p.elongation = o.elongation >= 0.0
                     ? std::clamp(o.elongation, 0.0, 1.0)
                     : std::clamp(d.normal(0.2 + 0.2 * (type - 1), 0.15), 0.0, 1.0);
  // Diameters of adults at the vessels' origins (radii here), mean and SD.
  p.radius_ascending = 0.5 * d.normal(0.0295, 0.0039);
  p.radius_arch = 0.5 * d.normal(0.0271, 0.0032);
  p.radius_descending = 0.5 * d.normal(0.0239, 0.0033);
  p.radius_trunk = 0.5 * d.normal(0.0122, 0.0017);
  p.radius_rcca = 0.5 * d.normal(0.0075, 0.0014);
  p.radius_lcca = 0.5 * d.normal(0.0075, 0.0014);
  p.radius_rsa = 0.5 * d.normal(0.0080, 0.0008);
  p.radius_lsa = 0.5 * d.normal(0.0080, 0.0008);
  // The arch's shape: wider than high, higher when elongated.
  p.width = d.normal(0.052, 0.005);
  p.depth = d.normal(0.036, 0.004);
  p.height = d.normal(0.026, 0.003) * (1.0 + 0.6 * p.elongation);
  // The type: the trunk's origin below the apex, in left carotid diameters.
  const double diameters = type == 1 ? d.uniform(0.2, 0.9)
                           : type == 2 ? d.uniform(1.1, 1.9)
                                       : d.uniform(2.1, 3.0);
  p.trunk_drop = diameters * 2.0 * p.radius_lcca;
  p.height = std::max(p.height, p.trunk_drop + 0.008);
  // Ostia centre to centre along the arch: 12.1 +- 3.0 and 15.9 +- 2.5 mm;
  // as gaps wall to wall, at least 1 mm.
  const double trunk_to_lcca = d.normal(0.0121, 0.0030), lcca_to_lsa = d.normal(0.0159, 0.0025);
  p.gap_trunk_lcca = std::max(0.001, trunk_to_lcca - p.radius_trunk - p.radius_lcca);
  p.gap_lcca_lsa = std::max(0.001, lcca_to_lsa - p.radius_lcca - p.radius_lsa);
  p.trunk_length = d.normal(0.040, 0.006);
  const double tilt = 12.0 * M_PI / 180.0;  // SD of the take-off angles about their means
  p.takeoff_trunk = d.normal(0.0, tilt);
  p.takeoff_lcca = d.normal(0.0, tilt);
  p.takeoff_lsa = d.normal(0.0, tilt);
  return p;
}

Centerline archCenterline(const ArchParameters& p) {
  Builder b;
  // The aorta as one line: up the ascending aorta from the valve, over the
  // arch, down the descending aorta to the femoral side.
  const Vec3 top_ascending = archPoint(p, 0.0);
  std::vector<Vec3> aorta{top_ascending - Vec3(0, 0, 0.06)};
  appendLine(aorta[0], top_ascending, &aorta);
  const size_t arch_start = aorta.size() - 1;
  const double arch_length = archLengthTo(p, M_PI);
  const int n_arch = static_cast<int>(std::ceil(arch_length / kSpacing));
  for (int i = 1; i <= n_arch; ++i) aorta.push_back(archPoint(p, thetaAt(p, arch_length * i / n_arch)));
  const size_t arch_end = aorta.size() - 1;
  appendLine(aorta.back(), aorta.back() - Vec3(0, 0, 0.17), &aorta);
  std::vector<double> radius(aorta.size());
  for (size_t i = 0; i < aorta.size(); ++i) {
    const double t = i <= arch_start ? double(i) / arch_start
                     : i <= arch_end ? double(i - arch_start) / (arch_end - arch_start)
                                     : double(i - arch_end) / (aorta.size() - 1 - arch_end);
    radius[i] = i <= arch_start ? p.radius_ascending + t * (p.radius_arch - p.radius_ascending)
                : i <= arch_end ? p.radius_arch + t * (p.radius_descending - p.radius_arch)
                                : p.radius_descending * (1.0 - 0.05 * t);
  }
  // The ostia along the arch (arc length from its start), at least 6 mm
  // apart from its end.
  const double s_first = archLengthTo(p, std::asin(std::clamp(1.0 - p.trunk_drop / p.height,
                                                              -1.0, 1.0)));
  const double first_radius = p.aberrant_rsa ? p.radius_rcca : p.radius_trunk;
  double s_lcca = s_first + first_radius + p.gap_trunk_lcca + p.radius_lcca;
  double s_lsa = (p.bovine ? s_first + first_radius : s_lcca + p.radius_lcca) + p.gap_lcca_lsa +
                 p.radius_lsa;
  const double room = arch_length - 0.006 - p.radius_lsa;
  if (s_lsa > room) {  // a short arch: the ostia closer together
    const double shift = s_lsa - room;
    s_lsa -= shift, s_lcca -= 0.5 * shift;
  }
  auto onArch = [&](double s) {
    return std::min(arch_end, arch_start + static_cast<size_t>(std::lround(s / arch_length * n_arch)));
  };
  const size_t first_ostium = onArch(s_first), lcca_ostium = onArch(s_lcca),
               lsa_ostium = onArch(s_lsa);
  // An aberrant right subclavian leaves the descending aorta 8 mm down.
  const size_t rsa_ostium = arch_end + static_cast<size_t>(std::lround(0.008 / kSpacing));
  const size_t last_ostium = p.aberrant_rsa ? rsa_ostium : lsa_ostium;
  // Named as a clinician does: the ascending aorta to the first ostium, the
  // arch to the last, the descending aorta on.
  auto part = [&](size_t from, size_t to, int parent, const std::string& name) {
    std::vector<int> ids;
    const int v = static_cast<int>(b.c.vessel_names.size());
    b.c.vessel_names.push_back(name);
    for (size_t i = from; i <= to; ++i) {
      b.c.position.push_back(aorta[i]);
      b.c.radius.push_back(radius[i]);
      b.c.parent.push_back(ids.empty() ? parent : ids.back());
      b.c.type.push_back(v);
      b.c.vessel.push_back(v);
      ids.push_back(b.c.numPoints() - 1);
    }
    return ids;
  };
  const std::vector<int> asc = part(0, first_ostium, -1, "ascending_aorta");
  const std::vector<int> arch = part(first_ostium + 1, last_ostium, asc.back(), "aortic_arch");
  const std::vector<int> desc = part(last_ostium + 1, aorta.size() - 1, arch.back(),
                                     "descending_aorta");
  auto aortaPoint = [&](size_t i) {
    return i <= first_ostium ? asc[i] : i <= last_ostium ? arch[i - first_ostium - 1]
                                                         : desc[i - last_ostium - 1];
  };

  // The branches: up from the arch's top, leaning to their side.
  const Vec3 up = Vec3::UnitZ();
  auto branch = [&](int origin, const Vec3& takeoff, const Vec3& heading, double parent_radius,
                    double length, double r, const std::string& name) {
    const Vec3 o = b.c.position[origin];
    return b.vessel(branchPath(o, takeoff, heading, parent_radius + 0.004, length), r, 0.9 * r,
                    origin, name);
  };
  const int first = aortaPoint(first_ostium);
  if (!p.aberrant_rsa) {
    const std::vector<int> trunk =
        branch(first, tilted(Vec3(-0.45, 0.2, 1.0), p.takeoff_trunk, 0.3), up, p.radius_arch,
               p.trunk_length - p.radius_arch - 0.004, p.radius_trunk, "brachiocephalic_trunk");
    branch(trunk.back(), Vec3(-0.8, 0.0, 0.4), Vec3(-1.0, -0.1, -0.15), 0.0, 0.06, p.radius_rsa,
           "right_subclavian");
    branch(trunk.back(), Vec3(-0.1, 0.05, 1.0), Vec3(-0.03, 0.0, 1.0), 0.0, 0.09, p.radius_rcca,
           "right_common_carotid");
    if (p.bovine) {  // the left carotid from the trunk, just out of the aorta
      const int k = std::min<int>(static_cast<int>(trunk.size()) - 1,
                                  static_cast<int>(std::lround((p.radius_arch + 0.009) / kSpacing)));
      branch(trunk[k], tilted(Vec3(0.6, 0.05, 1.0), 0.5 * p.takeoff_lcca, 1.1),
             Vec3(0.05, 0.0, 1.0), p.radius_trunk, 0.085, p.radius_lcca, "left_common_carotid");
    }
  } else {  // the right carotid first from the arch; the subclavian from the descending aorta
    branch(first, tilted(Vec3(-0.35, 0.2, 1.0), p.takeoff_trunk, 0.3), Vec3(-0.05, 0.0, 1.0),
           p.radius_arch, 0.095, p.radius_rcca, "right_common_carotid");
    branch(aortaPoint(rsa_ostium), Vec3(-0.6, -0.45, 0.7), Vec3(-1.0, 0.0, -0.05), p.radius_descending, 0.10,
           p.radius_rsa, "right_subclavian");
  }
  if (!p.bovine)
    branch(aortaPoint(lcca_ostium), tilted(Vec3(0.1, 0.1, 1.0), p.takeoff_lcca, 1.1),
           Vec3(0.05, 0.0, 1.0), p.radius_arch, 0.09, p.radius_lcca, "left_common_carotid");
  branch(aortaPoint(lsa_ostium), tilted(Vec3(0.35, -0.15, 1.0), p.takeoff_lsa, 2.0),
         Vec3(1.0, 0.0, -0.1), p.radius_arch, 0.07, p.radius_lsa, "left_subclavian");
  b.c.frame = "LAS";
  return b.c;
}

std::vector<std::string> archTargets(const ArchParameters& p) {
  std::vector<std::string> t;
  if (!p.aberrant_rsa) t.push_back("brachiocephalic_trunk");
  for (const char* v :
       {"right_common_carotid", "right_subclavian", "left_common_carotid", "left_subclavian"})
    t.push_back(v);
  return t;
}

std::string archCatheter(const ArchParameters& p, const std::string& target) {
  const bool type3 = p.type == ArchType::kIII;
  const bool right = target == "brachiocephalic_trunk" || target == "right_common_carotid" ||
                     target == "right_subclavian";
  if (p.aberrant_rsa && target == "right_subclavian") return "catheter";  // from the distal arch
  // (A Simmons curve suits the trunk's side of a type III arch better; the
  // autopilot does not know its technique: docs/navigation.md.)
  if (right || (p.bovine && target == "left_common_carotid")) return "headhunter";
  if (target == "left_common_carotid" && type3) return "headhunter";
  return "catheter";
}

}  // namespace evsim
