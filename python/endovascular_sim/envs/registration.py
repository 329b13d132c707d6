"""Registers the Gymnasium ids (``gymnasium.make("endovascular_sim/...")``)."""
import gymnasium

from endovascular_sim.envs.targets import branch_targets

CONTROL_INTERVAL_FLUOROSCOPY = 1.0 / 7.5  # [s] a fluoroscopy frame, as stEVE steps

ENVIRONMENTS = {
    "endovascular_sim/ArchNavigation-v0": dict(scene="arch_navigation", reset_rotation=3.141592653589793),
    "endovascular_sim/NetworkNavigation-v0": dict(
        scene="network_navigation", targets=branch_targets),
    "endovascular_sim/Navigation-v0": dict(),  # any scene file: gymnasium.make(id, scene=PATH)
}
ARCH_VARIETY = "endovascular_sim/ArchVariety-v0"  # a generated arch per episode


def register_environments():
    for env_id, kwargs in ENVIRONMENTS.items():
        if env_id in gymnasium.registry:
            continue
        gymnasium.register(
            id=env_id,
            entry_point="endovascular_sim.envs.navigation:NavigationEnv",
            vector_entry_point="endovascular_sim.envs.vector:NavigationVectorEnv",
            kwargs=kwargs,
        )
    if ARCH_VARIETY not in gymnasium.registry:
        gymnasium.register(id=ARCH_VARIETY,
                           entry_point="endovascular_sim.envs.arch_variety:ArchVarietyEnv",
                           kwargs=dict(reset_rotation=3.141592653589793))
