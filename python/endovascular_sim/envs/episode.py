"""When a navigation episode ends, and the metrics it reports in ``info``
(those of the navigation benchmarks: success, safe success, path ratio,
time, peak wall and proximal forces)."""
import math

import endovascular_sim as evs

TARGET_DEPTH = 0.02  # [m] inside the target vessel (or half of a shorter one): reached
OUTSIDE_RADIAL = 1.5  # the tip this many lumen radii from the centreline: out of the tree


class Episode:
    """The episode's state: reached, truncated and why, the peaks so far.

    Terminated: the lead tip reached ``TARGET_DEPTH`` inside the target
    (``remaining_path`` 0). Truncated: the time limit, the tip out of the
    vessel tree (farther than ``OUTSIDE_RADIAL`` lumen radii from every
    centreline), or a step the simulation could not solve (``failure``
    says why; the state stays at the last good step).
    """

    def __init__(self, env, safe_force):
        self.env = env
        self.safe_force = safe_force
        self.depth = TARGET_DEPTH
        self.reset_values()

    def reset_values(self):
        self.start_time = 0.0
        self.initial = 1.0
        self.remaining = 1.0
        self.success = False
        self.terminated = False
        self.truncated = False
        self.failure = ""
        self.peak_wall_force = 0.0
        self.peak_proximal_force = 0.0

    def reset(self):
        self.reset_values()
        env = self.env
        self.start_time = env.data.time
        self.remaining = env.remaining_path()
        if not math.isfinite(self.remaining):
            raise ValueError(f"target {env.target!r} is not connected to the vessel where device "
                             f"{env.model.device_names[env.lead]!r} starts")
        self.initial = max(self.remaining, 1e-9)

    def update(self, outcome):
        env = self.env
        self.peak_wall_force = max(self.peak_wall_force, float(outcome["max_wall_force"]))
        self.peak_proximal_force = max(self.peak_proximal_force,
                                       float(outcome["peak_drive_force"].max()))
        self.remaining = env.remaining_path()
        self.success = self.remaining <= 1e-12
        self.terminated = self.success
        self.truncated = False
        if bool(outcome["failed"]):
            self.truncated, self.failure = True, env.data.last_error or "the step failed"
        elif env.data.time - self.start_time >= env.time_limit - 1e-9:
            self.truncated = not self.terminated
            self.failure = "" if self.terminated else "time limit"
        elif not self.terminated:
            tip = env.data.devices[env.lead].position[-1]
            radial = evs.locate(env.model, env.data, tuple(float(x) for x in tip))["radial"]
            if radial > OUTSIDE_RADIAL:
                self.truncated, self.failure = True, "the tip left the vessel tree"

    def info(self):
        return {
            "target": self.env.target,
            "success": self.success,
            "safe_success": self.success and self.peak_wall_force <= self.safe_force,
            "path_ratio": min(1.0, max(0.0, 1.0 - self.remaining / self.initial)),
            "remaining_path": self.remaining,
            "time": self.env.data.time - self.start_time,
            "peak_wall_force": self.peak_wall_force,
            "peak_proximal_force": self.peak_proximal_force,
            "tip_vessel": self.env.data.tips[self.env.lead]["vessel"],
            "failure": self.failure,
        }

