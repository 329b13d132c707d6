"""ArchVariety: a new patient every episode. Each reset draws an aortic arch
from published anatomical statistics (``write_arch``, the arches of
``evsim arch``: types I-III, bovine, aberrant right subclavian, elongation,
radii, ostia spacing) with the environment's own random generator, writes
it as a patient's VMTK-style centreline and loads it, the guidewire in the
45 degree catheter at the femoral access; the target is drawn among the
arch's branches (the brachiocephalic trunk, both common carotids, both
subclavians). As stEVE's ArchVariety does for its agents; the arch's
variant is in ``info["arch"]``."""
import os
import tempfile

import gymnasium

import endovascular_sim as evs
from endovascular_sim.envs.navigation import NavigationEnv


class ArchVarietyEnv(NavigationEnv):
    """NavigationEnv on a generated arch drawn anew at every reset.

    Options: those of NavigationEnv but ``scene`` and ``model``, and
        arch_type: 0 (drawn with its population frequency) or 1-3.
        bovine, aberrant_subclavian: -1 drawn, 0 never, 1 always.
        folder: where the arches' files go (default: a temporary folder).
    """

    def __init__(self, arch_type=0, bovine=-1, aberrant_subclavian=-1, folder=None, **options):
        for fixed in ("scene", "model"):
            if fixed in options:
                raise TypeError(f"ArchVarietyEnv draws its own scene: no {fixed!r} option")
        self._draw = dict(type=arch_type, bovine=bovine, aberrant_subclavian=aberrant_subclavian)
        self._folder = folder or tempfile.mkdtemp(prefix="evsim_arch_variety_")
        self._options = options
        self.arch = None
        self._draw_and_load(lambda: 1)

    def _load(self, arch):
        """The arch's 45 degree catheter scene, every branch a target."""
        scene = arch["scenes"]["catheter"]
        options = dict(self._options)
        options.setdefault("targets", arch["targets"])
        options["targets"] = [t for t in options["targets"] if t in arch["targets"]]
        NavigationEnv.__init__(self, scene=scene, **options)
        # The last arch's files go (a model keeps its file's path: pickling
        # reloads it, so the current arch's stay).
        if self.arch is not None and self.arch["centerline"] != arch["centerline"]:
            _remove(self.arch)
        self.arch = arch

    def _draw_and_load(self, next_seed, attempts=10):
        """Loads the arch of the next seed; an arch whose files the loader
        refuses gives way to the next seed's (an episode never fails on a
        draw)."""
        for _ in range(attempts):
            arch = evs.write_arch(next_seed(), self._folder, **self._draw)
            try:
                self._load(arch)
                return
            except evs.LoadError as refused:
                _remove(arch)
                last = refused
        raise last

    def reset(self, *, seed=None, options=None):
        gymnasium.Env.reset(self, seed=seed)  # the generator the arch is drawn with
        self._draw_and_load(lambda: int(self.np_random.integers(2**31)))
        observation, info = super().reset(seed=None, options=options)
        info["arch"] = self.arch["summary"]
        return observation, info


def _remove(arch):
    """Deletes an arch's files."""
    for path in {arch["centerline"], *arch["scenes"].values()}:
        if os.path.exists(path):
            os.remove(path)
