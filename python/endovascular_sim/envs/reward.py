"""The default reward of the navigation environments (replaceable: any
object with ``reset(env)`` and ``__call__(env, outcome) -> float``)."""


class PathProgress:
    """Progress along the centreline path to the target, as stEVE's and
    CathSim's agents are rewarded:

        r = progress_gain · (d_before − d_after) − step_penalty
            + success_bonus (on reaching the target)

    d: the path length [m] along the centrelines from the lead tip to the
    target's depth (``NavigationEnv.remaining_path``). Defaults: 10 per
    metre of progress (1 for the 10 cm of an arch-to-carotid path), 0.005
    per action, 1 on success.
    """

    def __init__(self, progress_gain=10.0, step_penalty=0.005, success_bonus=1.0):
        self.progress_gain = progress_gain
        self.step_penalty = step_penalty
        self.success_bonus = success_bonus
        self.before = 0.0

    def reset(self, env):
        self.before = env.episode.remaining

    def __call__(self, env, outcome):
        after = env.episode.remaining
        r = self.progress_gain * (self.before - after) - self.step_penalty
        self.before = after
        if env.episode.success:
            r += self.success_bonus
        return r
