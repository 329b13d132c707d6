// Insertion and rotation at the proximal end. A device enters the body at an
// access point along the axis of an introducer sheath. Material with
// s <= length - inserted_length is still in the sheath: those nodes are held
// straight on the axis (position from the inserted length, twist from the
// commanded rotation); the rest is free. As the inserted length grows, the
// device's material passes the access point node by node.
#pragma once

#include <cmath>
#include <limits>
#include <string>

#include "endovascular_sim/core/types.h"
#include "endovascular_sim/mechanics/device_model.h"
#include "endovascular_sim/mechanics/device_state.h"

namespace evsim {

struct Introducer {
  Vec3 access_point{0.0, 0.0, 0.0};  // world [m]
  Mat3 frame{Mat3::Identity()};      // world; x axis points into the body
};

/// Last node still held in the sheath (always >= 0: node 0 at the most reaches
/// the access point).
int lastHeldNode(const DeviceModel& model, double inserted_length);

/// Pose of a node held straight in the sheath.
void heldPose(const DeviceModel& model, const Introducer& intro, double inserted_length,
              double rotation_angle, int node, Vec3* position, Mat3* rotation);
/// heldPose's position [m] and rotation apart; the rotation (for a node of
/// rest twist `twist` [rad]) is the same for every held node of one twist,
/// so a loop over them computes it once.
Vec3 heldPosition(const DeviceModel& model, const Introducer& intro, double inserted_length,
                  int node);
Mat3 heldRotation(const Introducer& intro, double rotation_angle, double twist);

/// Device at rest: held nodes in the sheath, inserted material in its rest
/// shape continuing from the access point.
DeviceState placeDevice(const DeviceModel& model, const Introducer& intro, double inserted_length,
                        double rotation_angle);

/// How the proximal end is driven.
struct DriveCommand {
  enum class Mode { kVelocity, kPosition };
  Mode mode{Mode::kVelocity};
  double insertion{0.0};  // [m/s] or target inserted length [m]
  double rotation{0.0};   // [rad/s] or target angle [rad]
};

/// Largest absolute rotation a position command may target [rad] (1000 turns).
constexpr double kMaxRotationTarget = 2000.0 * M_PI;

/// Why a command is refused (empty when it is valid): NaN, infinity, a speed
/// beyond the device's limits, a target length outside [0, length], a target
/// rotation beyond kMaxRotationTarget.
std::string validateDriveCommand(const DriveCommand& command, const DeviceModel& model);

/// A device's drive and the introducer it passes through.
///
/// What the drive can apply, like a hand or a robot's rollers: beyond its
/// force [N] along the insertion axis or its torque [N m] about it the
/// device slips in the drive (stalls) and the command is not followed.
/// Infinite (the default): a kinematic drive that imposes its command
/// whatever it takes.
///
/// The introducer's haemostasis valve grips the device: a Coulomb friction
/// of valve_friction [N] against its insertion or retraction and
/// valve_torque [N m] against its rotation while the drive moves it that
/// way. The drive feels it (it adds to the drive's wrench, and counts
/// against the limits); the device's motion beyond the valve does not, the
/// drive imposing the motion. 0 (the default): no valve.
struct DriveSpec {
  double max_force{std::numeric_limits<double>::infinity()};   // [N]
  double max_torque{std::numeric_limits<double>::infinity()};  // [N m]
  double valve_friction{0.0};                                  // [N]
  double valve_torque{0.0};                                    // [N m]
};

/// The motions a drive cannot impose this step, each +1 (in: the resistance
/// to pushing, or to turning in the positive sense, reached the limit), -1
/// (out, or the negative sense), 0 (free).
struct DriveStall {
  int insertion{0};
  int rotation{0};
  /// A stall in the sense the command moves the drive: the command is not
  /// followed (what users are told; a kick against the other sense, as a
  /// shaped tip springs out of the sheath, leaves the command followed).
  bool against_command{false};
  bool any() const { return insertion != 0 || rotation != 0; }
};

/// Advances inserted length and rotation angle over dt [s] toward the command,
/// never faster than the device's limits, and not at all in a stalled
/// direction (the drive slips: the device stays where it is).
void advanceDrive(const DriveCommand& command, const DeviceModel& model, double dt,
                  DeviceState* state, DriveStall stall = {});

}  // namespace evsim
