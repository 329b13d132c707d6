// Contacts against analytic answers and Signorini's law on the shipped scenes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>

#include "endovascular_sim/contact/contact_solver.h"
#include "endovascular_sim/geometry/vessel_field.h"
#include "endovascular_sim/mechanics/device_model.h"
#include "endovascular_sim/mechanics/so3.h"
#include "endovascular_sim/sim/simulation.h"
#include "test_helpers.h"

namespace evsim {
namespace {

/// A straight wire (nitinol, 0.2 m, 40 elements) released on the floor z = 0
/// under gravity.
SceneModel wireOnFloor(LcpSolver solver) {
  SceneModel m;
  m.name = "floor";
  m.time_step = 1e-3;
  m.effects.gravity = true;
  m.gravity = Vec3(0, 0, -9.81);
  DeviceSpec spec = straightDeviceSpec("wire", test::wireSection(60e9, 2e-4), 0.2, 40);
  spec.rayleigh_mass = 20.0;
  m.devices.push_back(buildDeviceModel(spec));
  Introducer intro;
  intro.access_point = Vec3(0, 0, 2e-4 + 1e-5);  // 10 um above the floor
  m.introducers.push_back(intro);
  m.initial_inserted_length.push_back(m.devices[0].length);
  m.initial_rotation.push_back(0.0);
  m.surface = std::make_shared<PlaneSurface>(Vec3::Zero(), Vec3::UnitZ());
  m.contact.lcp.solver = solver;
  m.contact.contact_spacing = 2.5e-3;
  // Equilibrium to 1e-6 of the weight needs the contacts resolved finer than
  // the default 1 nm / 1 um bands, within which nodes may jitter by a few nm
  // per step (momentum changes of ~1e-5 of the weight).
  m.contact.root.crossing_depth = 1e-12;
  m.contact.penetration_tolerance = 1e-9;
  m.samples.push_back(sampleDevice(m.devices[0], m.contact.contact_spacing));
  return m;
}

class FloorEquilibrium : public ::testing::TestWithParam<LcpSolver> {};

TEST_P(FloorEquilibrium, ContactForcesSumToTheWeight) {
  const SceneModel m = wireOnFloor(GetParam());
  SimData d = makeData(m);
  d.devices[0].released = true;
  double weight = 0.0;
  for (double mass : m.devices[0].node_mass) weight += mass * 9.81;
  // At rest the contact forces carry the weight. Nodes may still chatter by
  // nanometres inside the tolerance bands, which moves single steps' sums by
  // ~1e-6; momentum balance makes the time average exact, so both are checked.
  Vec3 total = Vec3::Zero(), average = Vec3::Zero();
  const int settle = 3000, window = 1000;
  for (int k = 0; k < settle + window; ++k) {
    ASSERT_EQ(step(m, &d), StepStatus::kOk) << d.last_error;
    total.setZero();
    for (const Contact& c : d.contacts) total += c.force * c.normal;
    if (k >= settle) {
      average += total / window;
      EXPECT_NEAR(total.z(), weight, 1e-5 * weight) << "step " << k;
    }
  }
  std::printf("[ metric   ] floor (%s): %zu contacts, mean sum of forces %.9e N, weight %.9e N\n",
              lcpSolverName(GetParam()), d.contacts.size(), average.z(), weight);
  EXPECT_NEAR(average.z(), weight, 1e-6 * weight);
  EXPECT_LT(average.head<2>().norm(), 1e-9 * weight);
  for (const Vec3& x : d.devices[0].position) EXPECT_NEAR(x.z(), 2e-4, 1e-6);  // resting on it
}

INSTANTIATE_TEST_SUITE_P(Solvers, FloorEquilibrium,
                         ::testing::Values(LcpSolver::kStatusMethod, LcpSolver::kLemke),
                         [](const auto& info) { return std::string(lcpSolverName(info.param)); });

/// Signorini after every step: forces >= 0, active contacts on their plane,
/// no point beyond the wall by more than the tolerance.
void expectSignorini(const SceneModel& m, const SimData& d, const std::string& where) {
  const double tol = m.contact.penetration_tolerance;
  EXPECT_LE(d.stats.contact.max_penetration_m, tol) << where;
  EXPECT_LE(d.stats.contact.lcp_residual, 1e-10) << where;
  for (const Contact& c : d.contacts) {
    EXPECT_GE(c.force, 0.0) << where;
    EXPECT_GE(c.gap, -tol) << where;
    if (c.force > 0.0) {
      EXPECT_LE(std::abs(c.gap), tol) << where << " force " << c.force;
    }
  }
}

class SceneSignorini : public ::testing::TestWithParam<std::string> {};

TEST_P(SceneSignorini, HoldsAfterEveryStep) {
  const SceneModel m = loadScene(GetParam());
  SimData d = makeData(m);
  int max_contacts = 0, steps_with_contacts = 0;
  const int steps = GetParam() == "aneurysm" ? 1500 : 4000;
  for (int k = 0; k < steps; ++k) {
    ASSERT_EQ(step(m, &d), StepStatus::kOk) << GetParam() << " step " << k << ": " << d.last_error;
    expectSignorini(m, d, GetParam() + " step " + std::to_string(k));
    if (::testing::Test::HasFailure()) return;
    max_contacts = std::max(max_contacts, d.stats.contact.active_contacts);
    steps_with_contacts += d.stats.contact.active_contacts > 0;
  }
  std::printf("[ metric   ] %s: %d steps with contacts, at most %d active\n", GetParam().c_str(),
              steps_with_contacts, max_contacts);
  EXPECT_GT(steps_with_contacts, 0) << "the scene never touched a wall";
}

INSTANTIATE_TEST_SUITE_P(Shipped, SceneSignorini,
                         ::testing::Values("carotid", "aneurysm", "network"));

TEST(ContactOptions, OutOfRangeAreRefused) {
  ContactOptions o;
  EXPECT_EQ(validateContactOptions(o), "");
  o.max_activation_loops = 0;
  EXPECT_NE(validateContactOptions(o).find("max_activation_loops"), std::string::npos);
  o = ContactOptions{};
  o.lcp.tolerance = -1.0;
  EXPECT_NE(validateContactOptions(o).find("tolerance"), std::string::npos);
  o = ContactOptions{};
  o.max_subdivisions = 40;
  EXPECT_NE(validateContactOptions(o).find("max_subdivisions"), std::string::npos);
  o = ContactOptions{};
  o.curvature_loops = 0;
  EXPECT_NE(validateContactOptions(o).find("curvature_loops"), std::string::npos);
}

/// A scene with a 20 mm vessel of radius 2 mm along x and no device yet
/// (1 ms steps).
SceneModel tubeScene() {
  SceneModel m;
  m.time_step = 1e-3;
  Centerline c;
  for (int i = 0; i <= 4; ++i) {
    c.position.push_back(Vec3(0.005 * i, 0.0, 0.0));
    c.radius.push_back(2e-3);
    c.parent.push_back(i - 1);
    c.type.push_back(0);
  }
  auto vessels = std::make_shared<const VesselField>(
      c, std::vector<AneurysmSpec>{}, std::vector<MotionRegion>{}, VesselFieldOptions{});
  m.vessels = vessels;
  m.surface = vessels;
  return m;
}

/// A wire lying just beyond the wall of a tube (within the tolerance band)
/// and thrown across it: its free motion ends beyond the far
/// wall, beyond every vessel's support (a flat field, no projection). The
/// plane is where the path leaves the lumen through the far wall; the plane
/// of the near wall where the wire starts would hold nothing (it used to be
/// added again in every loop until the step failed; 'tortuous' did so at a
/// J-tip squeezed against a wall).
TEST(Contact, AnElementsPointsAtOnceAreEachPointsPosition) {
  // samplePositions (an element's points with its tangents formed once, as
  // detection places them) gives samplePosition's numbers to the bit on a
  // bent, twisted device, nodes and interior points alike, and both lie on
  // the element's Hermite axis (axisPoint, formed on its own).
  const DeviceModel model =
      buildDeviceModel(straightDeviceSpec("wire", test::wireSection(60e9, 2e-4), 0.05, 12));
  DeviceState x = restState(model);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < model.num_nodes; ++i) {
    x.position[i] += 1e-3 * Vec3(u(rng), u(rng), u(rng));
    x.rotation[i] = expQuaternion(0.5 * Vec3(u(rng), u(rng), u(rng))) * x.rotation[i];
  }
  const std::vector<SamplePoint> samples = sampleDevice(model, 1e-3);
  int interior = 0;
  for (size_t lo = 0; lo < samples.size();) {
    size_t hi = lo + 1;
    while (hi < samples.size() && samples[hi].element == samples[lo].element) ++hi;
    std::vector<Vec3> at(hi - lo);
    samplePositions(model, x, &samples[lo], static_cast<int>(hi - lo), at.data());
    for (size_t k = lo; k < hi; ++k) {
      EXPECT_EQ(at[k - lo], samplePosition(model, x, samples[k])) << "sample " << k;
      const Vec3 on_axis = axisPoint(model, x, samples[k].element, samples[k].xi).position;
      EXPECT_LT((at[k - lo] - on_axis).norm(), 1e-15) << "sample " << k;
      interior += samples[k].xi > 0.0 && samples[k].xi < 1.0;
    }
    lo = hi;
  }
  EXPECT_GT(interior, 30);
}

TEST(Contact, APointThrownAcrossTheLumenGetsTheFarWall) {
  SceneModel m = tubeScene();
  const auto vessels = m.vessels;
  const double r = 2e-4;
  DeviceSpec spec = straightDeviceSpec("wire", test::wireSection(60e9, r), 0.012, 12);
  m.devices.push_back(buildDeviceModel(spec));
  // The wall below the axis at x = 10 mm, by bisection on g.
  double inside = 0.0, outside = -5e-3;
  for (int k = 0; k < 60; ++k) {
    const double y = 0.5 * (inside + outside);
    (vessels->evaluate(Vec3(0.01, y, 0.0), r).value > 0.0 ? inside : outside) = y;
  }
  Introducer intro;
  intro.access_point = Vec3(0.004, outside - 0.5e-6, 0.0);  // 0.5 um beyond the wall
  m.introducers.push_back(intro);
  m.initial_inserted_length.push_back(m.devices[0].length);  // all of it free
  m.initial_rotation.push_back(0.0);
  m.samples.push_back(sampleDevice(m.devices[0], m.contact.contact_spacing));
  SimData d = makeData(m);
  // Across the tube [m/s]: the wire, held at its proximal node, is a
  // cantilever of about 130 N/m at its tip; this throws it some 0.1 m.
  for (Vec3& v : d.devices[0].velocity) v = Vec3(0.0, 2000.0, 0.0);
  const Vec3 thrown = Vec3(0.01, 0.02, 0.0);
  ASSERT_EQ(vessels->evaluate(thrown, r).gradient.norm(), 0.0);  // flat: beyond the support
  ASSERT_EQ(step(m, &d), StepStatus::kOk) << d.last_error;
  double deepest = 0.0, highest = -1.0;
  for (const Vec3& p : d.devices[0].position) {
    const FieldSample g = vessels->evaluate(p, r);
    ASSERT_GT(g.gradient.norm(), 0.0) << p.transpose();
    deepest = std::max(deepest, -g.value / g.gradient.norm());
    highest = std::max(highest, p.y());
  }
  std::printf(
      "[ metric   ] thrown across the lumen: deepest %.3g m beyond the wall, highest y %.4g m\n",
      deepest, highest);
  EXPECT_LE(deepest, 1.01 * m.contact.penetration_tolerance);
  EXPECT_GT(highest, 0.0);  // it crossed the axis: held by the far wall, not the near one
}

TEST(Contact, APointBeyondEveryVesselsSupportIsOutsideTheTree) {
  SceneModel m = tubeScene();
  const auto vessels = m.vessels;
  DeviceSpec spec = straightDeviceSpec("wire", test::wireSection(60e9, 2e-4), 0.05, 50);
  m.devices.push_back(buildDeviceModel(spec));
  Introducer intro;
  intro.access_point = Vec3(0.01, 0.05, 0.0);  // 50 mm beside the vessel
  m.introducers.push_back(intro);
  m.initial_inserted_length.push_back(0.02);
  m.initial_rotation.push_back(0.0);
  m.samples.push_back(sampleDevice(m.devices[0], m.contact.contact_spacing));
  const Vec3 far = Vec3(0.02, 0.05, 0.0);
  ASSERT_LT(vessels->evaluate(far, 2e-4).value, 0.0);
  ASSERT_EQ(vessels->evaluate(far, 2e-4).gradient.norm(), 0.0);  // flat: beyond the support
  SimData d = makeData(m);
  const Vec3 tip = d.devices[0].position.back();
  EXPECT_EQ(step(m, &d), StepStatus::kContactsUnsolved);
  // Its depth is no number: the message says where it is, never "inf".
  EXPECT_NE(d.last_error.find("lies outside the vessel tree, at ("), std::string::npos)
      << d.last_error;
  EXPECT_EQ(d.last_error.find("inf"), std::string::npos) << d.last_error;
  EXPECT_EQ(d.devices[0].position.back(), tip);  // the state is kept
}

}  // namespace
}  // namespace evsim

namespace evsim {
namespace {

// Device-device contact: a released wire lying across two rigid parallel
// wires (held in their introducers; no vessel at all), under gravity:
//
//        A (released, along y)
//   ===========================
//      ||                ||
//     B1 (along x)      B2 (along x, 30 mm apart; frictionless, so they
//                                     must be level, or A slides off)
SceneModel wireAcrossTwoWires() {
  SceneModel m;
  m.time_step = 1e-3;
  m.effects.gravity = true;
  m.gravity = Vec3(0, 0, -9.81);
  m.effects.device_contact = true;
  m.contact.contact_spacing = 1e-3;
  m.contact.root.crossing_depth = 1e-12;
  m.contact.penetration_tolerance = 1e-9;
  const BeamSection s = test::wireSection(60e9, 2e-4);
  DeviceSpec top = straightDeviceSpec("top", s, 0.06, 60);
  top.rayleigh_mass = 20.0;
  for (int k = 0; k < 3; ++k) {
    DeviceSpec spec = k == 0 ? top : straightDeviceSpec("rail" + std::to_string(k), s, 0.06, 30);
    spec.rayleigh_mass = 20.0;
    m.devices.push_back(buildDeviceModel(spec));
    Introducer intro;
    if (k == 0) {  // along y, 5 um above the rails
      intro.access_point = Vec3(0.0, -0.03, 4e-4 + 5e-6);
      intro.frame = expSO3(Vec3(0, 0, M_PI / 2));
    } else {  // along x from -30 to +30 mm, at y = -15 mm and +15 mm, all held
      intro.access_point = Vec3(0.03, k == 1 ? -0.015 : 0.015, 0.0);
    }
    m.introducers.push_back(intro);
    m.initial_inserted_length.push_back(k == 0 ? 0.06 : 0.0);
    m.initial_rotation.push_back(0.0);
    m.samples.push_back(sampleDevice(m.devices.back(), m.contact.contact_spacing));
  }
  return m;
}

/// The top wire's weight [N].
double topWireWeight(const SceneModel& m) {
  double weight = 0.0;
  for (double mass : m.devices[0].node_mass) weight += mass * 9.81;
  return weight;
}

/// The rails' vertical force on the top wire [N], and its pairs that carry one.
double supportOfTopWire(const SimData& d, int* pairs) {
  double up = 0.0;
  for (const Contact& c : d.contacts) {
    if (c.other_device < 0 || c.force <= 0.0) continue;
    ++*pairs;
    EXPECT_EQ(c.device == 0 || c.other_device == 0, true);
    up += (c.device == 0 ? 1.0 : -1.0) * c.force * c.normal.z();
  }
  return up;
}

TEST(DeviceContact, WireRestingAcrossTwoWiresIsCarriedByThem) {
  const SceneModel m = wireAcrossTwoWires();
  SimData d = makeData(m);
  d.devices[0].released = true;
  const double weight = topWireWeight(m);
  double average = 0.0;
  const int settle = 2000, window = 500;
  int pairs = 0;
  for (int k = 0; k < settle + window; ++k) {
    ASSERT_EQ(step(m, &d), StepStatus::kOk) << d.last_error;
    EXPECT_LE(d.stats.contact.max_penetration_m, m.contact.penetration_tolerance) << "step " << k;
    if (k < settle) continue;
    average += supportOfTopWire(d, &pairs) / window;
  }
  std::printf("[ metric   ] wire across two wires: mean support %.9e N, weight %.9e N\n", average,
              weight);
  EXPECT_GT(pairs, 0);
  EXPECT_NEAR(average, weight, 1e-6 * weight);
  // It rests on the rails (at 0.4 mm, the sum of the radii) and its free
  // ends hang below them.
  EXPECT_NEAR(d.devices[0].position[15].z(), 4e-4, 1e-8);
  EXPECT_LT(d.devices[0].position[0].z(), d.devices[0].position[15].z());
}

// The pairs that carry the resting wire start each step from the last
// one's (keepPairs), across both wires' axes as found afresh: stepped on
// without sleeping, the wire stays on the rails at the sum of the radii,
// carried by its weight, each step in one activation loop. (Kept with the
// normal between their centres at x_t instead, the pairs pushed the wire
// along the rails between their samples, and it fell through at step 250.)
TEST(DeviceContact, PairsKeptFromStepToStepHoldAWireAtRest) {
  SceneModel m = wireAcrossTwoWires();
  m.sleep.enabled = false;  // every step solved
  SimData d = makeData(m);
  d.devices[0].released = true;
  const double weight = topWireWeight(m);
  const int settle = 200, window = 1800;
  int second_loops = 0, late_pairs = 0, pairs = 0;
  double average = 0.0, lowest = 1.0, highest = -1.0;
  for (int k = 0; k < settle + window; ++k) {
    ASSERT_EQ(step(m, &d), StepStatus::kOk) << d.last_error;
    if (k < settle) continue;
    second_loops += d.stats.contact.activation_loops > 1;
    late_pairs += d.stats.contact.late_rows.pair;
    average += supportOfTopWire(d, &pairs) / window;
    lowest = std::min(lowest, d.devices[0].position[15].z());
    highest = std::max(highest, d.devices[0].position[15].z());
  }
  std::printf(
      "[ metric   ] resting wire, %d steps: mean support %.9e N (weight %.9e N), crossing at "
      "%.9e-%.9e m, %d steps with a second loop, %d late pair rows\n",
      window, average, weight, lowest, highest, second_loops, late_pairs);
  EXPECT_GT(pairs, 0);
  EXPECT_NEAR(average, weight, 1e-6 * weight);
  EXPECT_NEAR(lowest, 4e-4, 1e-8);
  EXPECT_NEAR(highest, 4e-4, 1e-8);
  EXPECT_EQ(second_loops, 0);
  EXPECT_EQ(late_pairs, 0);
}

}  // namespace
}  // namespace evsim
