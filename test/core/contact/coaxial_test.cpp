// Coaxial devices (effect 'coaxial', contact/coaxial.h) against the
// composite-beam answer: a straight wire inside a catheter with a curved tip
// bends the two together; where the two are held to one axis without
// external load, M_catheter + M_wire = 0 with M = EI (kappa - kappa_rest), so
//     kappa = EI_c kappa_c / (EI_c + EI_w).
// Withdrawn, the wire leaves the tip free to take its rest curvature again.
#include "endovascular_sim/contact/coaxial.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "endovascular_sim/sim/simulation.h"
#include "lumen_check.h"
#include "test_helpers.h"

namespace evsim {
namespace {

constexpr double kShaft = 0.05, kTip = 0.03, kTipCurvature = 30.0;  // [m], [m], [1/m]
constexpr double kLumen = 0.485e-3;                                 // [m]

BeamSection catheterSection() {
  BeamSection s = test::wireSection(5e8, 0.835e-3, 1100.0);
  s.inner_radius = kLumen;
  return s;
}

/// Catheter (straight 50 mm shaft, 30 mm tip of curvature 30 /m, 1-2 mm
/// elements, lumen radius 0.485 mm) fully inserted along +x, and a straight
/// wire of radius `wire_radius` [m] and bending stiffness `ratio`
/// EI_catheter inside it, inserted `wire_inserted` [m]; time step dt [s].
SceneModel catheterWithWire(double ratio, double wire_inserted, double wire_radius, double dt) {
  SceneModel m;
  m.name = "coaxial";
  m.time_step = dt;
  m.effects.coaxial = m.effects.subdivision = true;
  DeviceSpec cath;
  cath.name = "catheter";
  cath.rayleigh_mass = 20.0;
  DeviceSectionSpec shaft{"shaft", catheterSection(), kShaft, 25, Vec3::Zero(), 0.0, 0.0};
  DeviceSectionSpec tip{"tip", catheterSection(), kTip, 30, Vec3(0, 0, kTipCurvature), 0.0, 0.0};
  cath.sections = {shaft, tip};
  const BeamSection c = catheterSection();
  const double wire_modulus =
      ratio * c.young_modulus * c.secondMoment() / (M_PI / 4 * std::pow(wire_radius, 4));
  DeviceSpec wire =
      straightDeviceSpec("wire", test::wireSection(wire_modulus, wire_radius), 0.1, 100);
  wire.rayleigh_mass = 20.0;
  m.devices = {buildDeviceModel(cath), buildDeviceModel(wire)};
  m.introducers.assign(2, Introducer{});
  m.initial_inserted_length = {kShaft + kTip, wire_inserted};
  m.initial_rotation = {0.0, 0.0};
  m.outer_of = {-1, 0};
  m.contact.contact_spacing = 1e-3;
  m.contact.lumen_tolerance = 1e-6;  // fits down to 5 um: a fifth of the default
  for (const auto& d : m.devices) m.samples.push_back(sampleDevice(d, m.contact.contact_spacing));
  return m;
}

/// Angle [rad] the catheter turns between material coordinates 55 and 75 mm
/// (the middle of its tip, away from the ends' boundary layers).
double tipTurn(const SceneModel& m, const SimData& d) {
  const auto& x = d.devices[0];
  auto node = [&](double s) {
    for (int i = 0; i < m.devices[0].num_nodes; ++i)
      if (std::abs(m.devices[0].node_s[i] - s) < 1e-9) return i;
    ADD_FAILURE() << "no node at s = " << s;
    return 0;
  };
  const Vec3 a = x.rotation[node(0.055)] * Vec3::UnitX(),
             b = x.rotation[node(0.075)] * Vec3::UnitX();
  return std::acos(std::clamp(a.dot(b), -1.0, 1.0));
}

double kinetic(const SceneModel& m, const SimData& d) {
  return kineticEnergy(m.devices[0], d.devices[0]) + kineticEnergy(m.devices[1], d.devices[1]);
}

void settle(const SceneModel& m, SimData* d, int steps) {
  for (int k = 0; k < steps; ++k) {
    ASSERT_EQ(step(m, d), StepStatus::kOk) << d->last_error;
    ASSERT_LE(test::worstLumenExcess(m, *d), 2.0 * m.contact.lumen_tolerance) << "step " << k;
  }
}

// Quasi-static: a wire fitting the lumen to 5 um, steps of 0.2 ms. (With
// steps of 1 ms and clearances below about 50 um the step's projection
// holds the wire where the free motion left it and the composite comes out
// too stiff; docs/limitations.md.)
class CompositeTip : public ::testing::TestWithParam<double> {};

TEST_P(CompositeTip, WireStraightensTheCatheterTipByTheStiffnessRatio) {
  const double ratio = GetParam();                                     // EI_wire / EI_catheter
  const SceneModel m = catheterWithWire(ratio, 0.085, 0.48e-3, 2e-4);  // 5 mm beyond the tip
  SimData d = makeData(m);
  settle(m, &d, 1500);
  if (HasFatalFailure()) return;
  const double rest = kTipCurvature * 0.02, composite = rest / (1.0 + ratio);
  // The 5 um clearance lets the wire's turn differ from the catheter's by up
  // to 16 c / L^2 * L = 0.004 rad over L = 20 mm; 2 % more for the
  // discretisation (1 mm elements, contacts at the nodes).
  EXPECT_NEAR(tipTurn(m, d), composite, 0.004 + 0.02 * composite) << "rest turn " << rest;
  EXPECT_GT(d.effect_calls.coaxial, 0);
  // Beyond the tip the wire is free: straight (its rest shape) to 1 mrad.
  const auto& w = d.devices[1];
  const Vec3 t0 = w.rotation[96] * Vec3::UnitX(), t1 = w.rotation[100] * Vec3::UnitX();
  EXPECT_LT(std::acos(std::min(1.0, t0.dot(t1))), 1e-3);
}

INSTANTIATE_TEST_SUITE_P(StiffnessRatios, CompositeTip, ::testing::Values(1.0, 4.0));

// The shipped pairing's clearance (0.014 in wire, 0.038 in lumen: 0.3 mm) at
// 1 ms: the two settle, the wire stays in the lumen, and the
// tip turns between the composite and its rest angle; withdrawn behind the
// tip, the wire frees it to its rest curvature.
TEST(Coaxial, LooseWireSettlesAndWithdrawnFreesTheTip) {
  const SceneModel m = catheterWithWire(1.0, 0.085, 0.178e-3, 1e-3);
  SimData d = makeData(m);
  settle(m, &d, 1000);
  if (HasFatalFailure()) return;
  const double rest = kTipCurvature * 0.02;
  // Settled: what moves is a jitter of the resting contacts (about 1e-8 J,
  // against 2e-3 J of elastic energy in the tip; docs/limitations.md).
  EXPECT_LT(kinetic(m, d), 1e-7);
  EXPECT_GT(tipTurn(m, d), rest / 2.0);
  EXPECT_LT(tipTurn(m, d), 0.9 * rest);
  ASSERT_EQ(setCommand(m, &d, "wire", {DriveCommand::Mode::kPosition, 0.04, 0.0}), "");
  settle(m, &d, 2000);
  if (HasFatalFailure()) return;
  EXPECT_NEAR(tipTurn(m, d), rest, 0.01 * rest);
  EXPECT_LT(kinetic(m, d), 1e-7);
}

// The lumen's curvature (docs/model.md, "Coaxial devices") acts on the
// slide of the wire relative to the catheter only. A catheter with a wire
// inside, its tip straightened by the wire, turned slowly at its hub (5
// rad/s): the pair turns as one body, so the tip is where the hub's rotation
// about the insertion axis takes it from rest (the shaft's torsion lags by
// the twist of 80 mm at 5 rad/s, < 1e-2 rad). A spring on each device's own
// motion held the tip 0.11 rad behind; the plain step (no curvature term)
// ends 15 mm off.
TEST(Coaxial, ACatheterWithItsWireTurnsAsOneBody) {
  for (const double lumen_settle : {0.1, 1e-3}) {  // the default, and a loop run to 0.1 %
    SceneModel m = catheterWithWire(1.0, 0.085, 0.178e-3, 1e-3);
    m.contact.lumen_settle = lumen_settle;
    m.contact.max_activation_loops = 40;
    SimData d = makeData(m);
    settle(m, &d, 300);
    if (HasFatalFailure()) return;
    const Vec3 rest = d.devices[0].position.back();
    const double hub_before = d.devices[0].rotation_angle;
    ASSERT_EQ(setCommand(m, &d, "catheter", {DriveCommand::Mode::kVelocity, 0.0, 5.0}), "");
    settle(m, &d, 300);
    if (HasFatalFailure()) return;
    const double turned = d.devices[0].rotation_angle - hub_before;
    EXPECT_NEAR(turned, 1.5, 1e-9);
    const Vec3 expected = Eigen::AngleAxisd(turned, Vec3::UnitX()) * rest;
    const Vec3 tip = d.devices[0].position.back();
    const double radius = std::hypot(rest.y(), rest.z());
    EXPECT_LT((tip - expected).norm(), 1e-2 * radius) << "lumen_settle " << lumen_settle;
    EXPECT_NEAR(std::atan2(tip.z(), tip.y()), turned, 1e-2) << "lumen_settle " << lumen_settle;
  }
}

// The status method reads W's columns as it needs them (contact.
// columns_on_demand, contact/delassus_columns.h) instead of the whole W:
// the same LCPs to round-off, so the same run. The Headhunter with its wire
// in the descending aorta, both advanced and the catheter turned: 150-250
// lumen and wall rows a step, the lumen's curvature springs eliminated.
TEST(Coaxial, ColumnsOnDemandFollowTheWholeOperatorsRun) {
  constexpr int kSteps = 1500;
  std::vector<std::vector<Vec3>> tips;
  std::vector<long> rows, on_demand_loops;
  for (const bool on_demand : {true, false}) {
    SceneModel m = loadScene("arch_to_right_common_carotid");
    m.contact.columns_on_demand = on_demand;
    SimData d = makeData(m);
    ASSERT_EQ(setCommand(m, &d, "headhunter", {DriveCommand::Mode::kVelocity, 0.03, 4.0}), "");
    ASSERT_EQ(setCommand(m, &d, "guidewire", {DriveCommand::Mode::kVelocity, 0.03, 0.0}), "");
    long sum = 0, loops = 0;
    for (int k = 0; k < kSteps; ++k) {
      ASSERT_EQ(step(m, &d), StepStatus::kOk) << k;
      sum += d.stats.contact.contacts;
      loops += d.stats.contact.on_demand_loops;
    }
    tips.push_back({d.devices[0].position.back(), d.devices[1].position.back()});
    rows.push_back(sum);
    on_demand_loops.push_back(loops);
  }
  EXPECT_GT(on_demand_loops[0], 0);  // the path ran (where it pays: contact_system.cpp) ...
  EXPECT_EQ(on_demand_loops[1], 0);  // ... and is off when asked
  // Round-off apart (a column carried along the chain alone, not in the
  // sweep): the tips within 10 nm, the rows within 2 %.
  for (int k = 0; k < 2; ++k) EXPECT_LT((tips[0][k] - tips[1][k]).norm(), 1e-8) << "device " << k;
  EXPECT_NEAR(rows[0], rows[1], 0.02 * rows[1]);
  std::printf(
      "[ metric   ] columns on demand: tips %.2g and %.2g m from the whole W's, %.0f rows a step, "
      "%ld loops on demand\n",
      (tips[0][0] - tips[1][0]).norm(), (tips[0][1] - tips[1][1]).norm(),
      static_cast<double>(rows[0]) / kSteps, on_demand_loops[0]);
}

// The cheap certificate (surelyWithinLumen) against the full search
// (locateInLumen): a point it certifies is never beyond the lumen by more
// than the allowance, whatever the wire's offset; and it spares the search
// for most of the points well inside.
TEST(Coaxial, CertifiedPointsLieWithinTheLumenByTheFullSearch) {
  const SceneModel m = catheterWithWire(1.0, 0.085, 0.178e-3, 1e-3);
  SimData d = makeData(m);
  settle(m, &d, 200);  // the catheter's tip bent, the wire in it
  if (HasFatalFailure()) return;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> offset(-0.45e-3, 0.45e-3);
  int certified = 0, well_inside = 0, checked = 0;
  for (int trial = 0; trial < 40; ++trial) {
    DeviceState wire = d.devices[1];  // the whole wire shifted across the lumen
    const Vec3 shift(offset(rng), offset(rng), offset(rng));
    for (Vec3& x : wire.position) x += shift;
    for (const double allowance : {0.0, 1e-6, 5e-6}) {
      OuterAxisCache cache;
      for (const SamplePoint& s : m.samples[1]) {
        const LumenLocation loc = locateInLumen(m.devices[1], wire, s, m.devices[0], d.devices[0]);
        const bool sure =
            surelyWithinLumen(m.devices[1], wire, s, m.devices[0], d.devices[0], allowance, &cache);
        ++checked;
        if (!loc.inside) {
          EXPECT_TRUE(sure);  // outside the overlap: no lumen holds it
          continue;
        }
        if (sure) {
          ++certified;
          EXPECT_LE(loc.excess(), allowance) << "trial " << trial << " element " << s.element;
        }
        well_inside += loc.excess() < -0.05e-3;
      }
    }
  }
  EXPECT_GT(checked, 1000);
  EXPECT_GT(certified, well_inside / 2) << "of " << well_inside << " points 50 um inside";
}

TEST(Coaxial, InnerDevicePlacedOnTheOuterAxisAndFreeBeyondItsTip) {
  const SceneModel m = catheterWithWire(1.0, 0.085, 0.178e-3, 1e-3);
  const SimData d = makeData(m);
  EXPECT_LT(test::worstLumenExcess(m, d), 1e-9);
  // The outer device's own shape: the first wire node past the catheter's tip
  // continues along the catheter's tip tangent.
  const Vec3 tip = d.devices[0].position.back();
  const Vec3 tangent = d.devices[0].rotation.back() * Vec3::UnitX();
  const Vec3 beyond = d.devices[1].position.back();
  EXPECT_NEAR((beyond - tip).normalized().dot(tangent), 1.0, 1e-6);
  EXPECT_NEAR((beyond - tip).norm(), 0.005, 1e-6);
}

}  // namespace
}  // namespace evsim
