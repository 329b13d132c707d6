// The stability suite: hard cases driven for thousands of steps. After every
// step: the step succeeded (the status method terminated, contacts solved
// within the subdivision limit), every position and velocity is finite, no
// point lies beyond the wall by more than the tolerance, the subdivisions
// stay within their limit, and the kinetic energy stays bounded (see
// kineticBound).
//
// Each case is a shipped scene, so `evsim run SCENE` shows it. Horizons are
// those verified here; docs/README name the cases that still fail beyond.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "endovascular_sim/mechanics/elasticity.h"
#include "endovascular_sim/sim/simulation.h"

namespace evsim {
namespace {

struct Outcome {
  long steps{0};
  double max_penetration_m{0.0};
  double max_kinetic_energy_J{0.0};
  int max_active_contacts{0};
  int max_subdivisions{0};
  double mean_ms{0.0};
};

double totalMass(const DeviceModel& d) {
  double m = 0.0;
  for (double v : d.node_mass) m += v;
  return m;
}

/// Bound of a device's kinetic energy [J]: the larger of the elastic energy
/// of the device held straight (the most its pre-shape can release: a coil's
/// helix springing back) and the device moving as a whole at 1 m/s (twenty
/// times the fastest insertion).
double kineticBound(const DeviceModel& d, const Introducer& intro) {
  const double straightened = elasticEnergy(d, placeDevice(d, intro, 0.0, 0.0));
  return std::max(straightened, 0.5 * totalMass(d) * 1.0 * 1.0);
}

/// Steps the scene, asserting after every step (gtest's fatal assertions need
/// a void function: the outcome comes back through `result`).
void drive(const std::string& scene, long steps, Outcome* result) {
  const SceneModel model = loadScene(scene);
  SimData data = makeData(model);
  Outcome& out = *result;
  const double tolerance = model.contact.penetration_tolerance;
  const int subdivision_limit = (1 << model.contact.max_subdivisions) - 1;
  for (long k = 0; k < steps; ++k) {
    const StepStatus status = step(model, &data);
    ASSERT_EQ(status, StepStatus::kOk) << scene << " step " << k + 1 << ": " << data.last_error;
    for (size_t i = 0; i < model.devices.size(); ++i) {
      const DeviceState& d = data.devices[i];
      for (size_t n = 0; n < d.position.size(); ++n) {
        ASSERT_TRUE(d.position[n].allFinite() && d.velocity[n].allFinite() &&
                    d.angular_velocity[n].allFinite())
            << scene << " step " << k + 1 << " node " << n;
      }
      const double ke = kineticEnergy(model.devices[i], d);
      const double bound = kineticBound(model.devices[i], model.introducers[i]);
      ASSERT_LT(ke, bound) << scene << " step " << k + 1 << ": kinetic energy";
      out.max_kinetic_energy_J = std::max(out.max_kinetic_energy_J, ke);
    }
    ASSERT_LE(data.stats.max_penetration_m, tolerance + 1e-12) << scene << " step " << k + 1;
    ASSERT_LE(data.stats.subdivisions, subdivision_limit) << scene << " step " << k + 1;
    out.max_penetration_m = std::max(out.max_penetration_m, data.stats.max_penetration_m);
    out.max_active_contacts = std::max(out.max_active_contacts, data.stats.active_contacts);
    out.max_subdivisions = std::max(out.max_subdivisions, data.stats.subdivisions);
    out.mean_ms += data.stats.wall_ms / steps;
    ++out.steps;
  }
  std::printf("[ metric   ] %s: kinetic energy bound %.3g J\n", scene.c_str(),
              kineticBound(model.devices[0], model.introducers[0]));
  std::printf(
      "[ metric   ] %s: %ld steps, at most %d active contacts, penetration <= %.3g um, "
      "kinetic energy <= %.3g J, subdivisions <= %d, mean step %.3f ms\n",
      scene.c_str(), out.steps, out.max_active_contacts, out.max_penetration_m * 1e6,
      out.max_kinetic_energy_J, out.max_subdivisions, out.mean_ms);
}

TEST(Stability, CoilDeployedIntoTheAneurysmWithSelfContact) {
  Outcome o;
  drive("aneurysm", 3000, &o);  // 30 mm of coil into a 7 mm dome
  EXPECT_EQ(o.steps, 3000);
  EXPECT_GT(o.max_active_contacts, 10);  // the coil presses on the dome and on itself
}

TEST(Stability, GuidewireBucklesInADeadEnd) {
  // 40 mm/s into a closed 60 mm tube: by 2.5 s, 100 mm of wire are in.
  Outcome o;
  drive("dead_end", 2500, &o);
  EXPECT_EQ(o.steps, 2500);
  EXPECT_GT(o.max_active_contacts, 20);  // buckled against both walls
}

TEST(Stability, VesselsMoveWhileTheWireTouchesThem) {
  Outcome o;
  drive("network", 3000, &o);  // cardiac and respiratory motion
  EXPECT_EQ(o.steps, 3000);
  EXPECT_GT(o.max_active_contacts, 0);
}

TEST(Stability, LargestTimeStepAndFastestInsertion) {
  // 40 ms steps, 50 mm/s: up the aorta into the subclavian artery (2.8 s).
  Outcome o;
  drive("large_step", 70, &o);
  EXPECT_EQ(o.steps, 70);
  EXPECT_GT(o.max_active_contacts, 5);
}

}  // namespace
}  // namespace evsim
