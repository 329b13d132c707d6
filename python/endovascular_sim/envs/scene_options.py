"""A scene for an environment: a shipped name or a file, with the options
an environment may change (its physics time step)."""
import math

import yaml

import endovascular_sim as evs


def load_env_scene(scene, time_step=None):
    """The scene's model; with ``time_step`` [s] its file's time step replaced."""
    model = evs.load_scene(scene)
    if time_step is None or time_step == model.time_step:
        return model
    if not (isinstance(time_step, (int, float)) and math.isfinite(time_step) and time_step > 0):
        raise ValueError(f"time_step {time_step!r} must be a positive number of seconds")
    with open(model.file, encoding="utf-8") as f:
        spec = yaml.safe_load(f)
    spec["time_step"] = float(time_step)
    return evs.load_scene_text(yaml.safe_dump(spec, sort_keys=False), model.file)
