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
from pkgutil import extend_path

# The package's parts in every folder of sys.path that holds one: these
# sources, and the catkin workspace's compiled core (_core) and messages
# (msg, srv), whichever of the two folders Python found first.
__path__ = extend_path(__path__, __name__)

from endovascular_sim._core import (  # noqa: E402,F401
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
    write_arch,
)

try:
    import gymnasium as _gymnasium  # noqa: F401
except ImportError:  # the ROS side's Python: the core alone
    pass
else:
    from endovascular_sim.envs.registration import register_environments

    register_environments()


def evsim_binary():
    """The path of the evsim command built beside this module (the devel and
    install spaces share the layout lib/python3/dist-packages/endovascular_sim
    and lib/endovascular_sim/evsim)."""
    import os
    from endovascular_sim import _core
    lib = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(_core.__file__))))
    return os.path.join(lib, "endovascular_sim", "evsim")
