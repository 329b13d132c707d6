"""endovascular_sim: catheter, guidewire and coil navigation in blood vessels.

The core's own names, as MuJoCo's bindings do: a ``SceneModel`` (loaded once,
immutable), its ``SimData`` (the state, numpy views of the core's arrays),
``step(model, data, nstep)`` with the GIL released, drive commands, the
autopilot, X-ray images, state files, copies and pickles, and ``rollout``
of a batch on a C++ thread pool. Gymnasium environments are registered
when gymnasium is importable (``endovascular_sim.envs``).

    import endovascular_sim as evs
    model = evs.load_scene("carotid")
    data = evs.make_data(model)
    evs.set_command(model, data, "guidewire", insertion=0.01, rotation=0.0)
    evs.step(model, data, 1000)
    data.devices[0].position       # (nodes x 3) [m], a view
"""
from endovascular_sim._core import (  # noqa: F401
    Autopilot,
    DeviceState,
    LoadError,
    SceneModel,
    SimData,
    StepError,
    XrayRenderer,
    command,
    config_directory,
    detach,
    load_scene,
    load_scene_text,
    load_state,
    load_state_text,
    locate,
    make_data,
    remaining_path,
    required_depth,
    reset_data,
    rollout,
    run_autopilot,
    save_state,
    set_command,
    shipped_scenes,
    state_text,
    step,
)

try:
    import gymnasium as _gymnasium  # noqa: F401
except ImportError:  # the ROS side's Python: the core alone
    pass
else:
    from endovascular_sim.envs.registration import register_environments

    register_environments()
