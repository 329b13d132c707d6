"""What a navigation agent observes (replaceable: any callable of no
arguments with a ``space``, built from the environment)."""
import gymnasium
import numpy as np

import endovascular_sim as evs

TRACKED_BEHIND_TIP = (0.0, 0.005, 0.01, 0.02, 0.04)  # [m] along the lead device from its tip
SCALE = 0.1  # [m] positions are observed in units of 10 cm from the lead tip's start


class TrackedPoints:
    """A flat float32 vector:

    - the lead device's tip and points 5, 10, 20 and 40 mm behind it
      (along its shape), then every other device's tip: in "3d" their
      positions in the scene frame less the lead tip's start, over 10 cm;
      in "2d" their pixels on the X-ray detector (as a clinician sees
      them), centred and over half the detector's side;
    - the target: the point of its centreline at the reached depth, alike;
    - the last action (per device: insertion, rotation, in [-1, 1]);
    - each device's inserted length over its length.

    With ``pixels`` the observation is a Dict: {"state": that vector,
    "pixels": the X-ray image, (size x size x 1) uint8}.
    """

    def __init__(self, env, mode="3d", pixels=False):
        if mode not in ("3d", "2d"):
            raise ValueError(f"observation {mode!r}: use '3d' or '2d'")
        self.env, self.mode, self.pixels = env, mode, pixels
        n = len(env.model.devices)
        dims = 3 if mode == "3d" else 2
        points = len(TRACKED_BEHIND_TIP) + (n - 1) + 1
        size = points * dims + 2 * n + n
        self.origin = np.array(env.data.devices[env.lead].position[-1], dtype=np.float64)
        state = gymnasium.spaces.Box(-np.inf, np.inf, (size,), np.float32)
        if pixels:
            side = env.xray.pixels
            image = gymnasium.spaces.Box(0, 255, (side, side, 1), np.uint8)
            self.space = gymnasium.spaces.Dict({"state": state, "pixels": image})
        else:
            self.space = state

    def points(self):
        """The tracked points (k x 3) [m]: the lead's, the other tips, the target."""
        env = self.env
        lead = np.asarray(env.data.devices[env.lead].position)
        out = list(_points_behind_tip(lead, TRACKED_BEHIND_TIP))
        out += [np.asarray(d.position[-1]) for i, d in enumerate(env.data.devices) if i != env.lead]
        out.append(self.target_point())
        return np.array(out)

    def target_point(self):
        """The target's centreline point at the reached depth [m] (once per target)."""
        env = self.env
        if getattr(self, "_target", None) != env.target:
            depth = evs.required_depth(env.model, env.target, env.episode.depth)
            self._target, self._target_point = env.target, np.array(
                env.model.vessel_point(env.target, depth))
        return self._target_point

    def __call__(self):
        env = self.env
        p = self.points()
        if self.mode == "3d":
            coords = (p - self.origin) / SCALE
        else:
            half = 0.5 * env.xray.pixels
            coords = (env.xray.project(p) - half) / half
        inserted = [d.inserted_length / info["length"]
                    for d, info in zip(env.data.devices, env.model.devices)]
        state = np.concatenate([coords.ravel(), env.last_action, inserted]).astype(np.float32)
        if not self.pixels:
            return state
        return {"state": state, "pixels": env.xray.render(env.data)[:, :, None]}


def _points_behind_tip(nodes, distances):
    """Points at the given distances [m] behind the last node, along the
    polyline of the nodes (the first node where the device is shorter)."""
    back = nodes[::-1]
    seg = np.linalg.norm(np.diff(back, axis=0), axis=1)
    s = np.concatenate([[0.0], np.cumsum(seg)])
    return np.stack([np.interp(distances, s, back[:, k]) for k in range(3)], axis=1)
