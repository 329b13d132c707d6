"""The core as a Python module, against evsim and against itself: the same
steps to the last bit, copies and pickles that continue bit for bit, a
rollout equal to its simulations stepped one by one, views of the core's
memory, and bad input refused with the state kept."""
import copy
import json
import pickle
import threading

import numpy as np
import pytest

import endovascular_sim as evs
from conftest import run_evsim

TIMING = ("_ms",)  # wall-clock fields: the only ones two runs may differ in


def without_timing(step):
    return {k: v for k, v in step.items() if not k.endswith(TIMING)}


def test_a_python_run_of_carotid_equals_evsim_run_step_for_step(evsim_binary, tmp_path):
    steps = 2500  # past the first wall contacts (t = 1.345 s), a second of them
    state = tmp_path / "evsim.state"
    lines = run_evsim(evsim_binary, "run", "carotid", "--steps", str(steps), "--json",
                      "--save-state", str(state)).splitlines()
    assert len(lines) == steps
    model = evs.load_scene("carotid")
    data = evs.make_data(model)
    contacts = 0
    for k, line in enumerate(lines):
        evs.step(model, data)
        ours, theirs = json.loads(data.stats_json()), json.loads(line)
        assert without_timing(ours) == without_timing(theirs), f"step {k + 1}"
        assert data.stats["contacts"] == theirs["contacts"]
        contacts += theirs["contacts"]
    assert contacts > 0, "the run must reach the wall to compare the contact solver"
    # Every double of the state to 17 digits: the same bits.
    assert evs.state_text(model, data) == state.read_text()


def stepped(model, data, n):
    evs.step(model, data, n)
    return evs.state_text(model, data)


@pytest.mark.parametrize("scene", ["carotid", "carotid_catheter"])
def test_deepcopy_and_pickle_continue_bit_for_bit(scene):
    model = evs.load_scene(scene)
    data = evs.make_data(model)
    evs.step(model, data, 600)
    twin = copy.deepcopy(data)
    revived = pickle.loads(pickle.dumps(data))
    model_revived = pickle.loads(pickle.dumps(model))
    expected = stepped(model, data, 400)
    assert stepped(model, twin, 400) == expected
    assert stepped(model_revived, revived, 400) == expected
    assert revived.model.name == scene


def test_a_scene_from_text_steps_as_its_file():
    model = evs.load_scene("carotid")
    with open(model.file, encoding="utf-8") as f:
        text = f.read()
    from_text = evs.load_scene_text(text, model.file)
    a, b = evs.make_data(model), evs.make_data(from_text)
    assert stepped(model, a, 300) == stepped(from_text, b, 300)
    # and it pickles by its text
    again = pickle.loads(pickle.dumps(b))
    assert stepped(again.model, again, 100) == stepped(from_text, b, 100)


def random_commands(model, n, t, seed):
    rng = np.random.default_rng(seed)
    limits = np.array([[d["max_insertion_speed"], d["max_rotation_speed"]] for d in model.devices])
    u = rng.uniform(-0.3, 1.0, (n, t, len(model.devices), 2))
    u[..., 1] = rng.uniform(-1.0, 1.0, (n, t, len(model.devices)))
    return (u * limits).reshape(n, t, -1)


@pytest.mark.parametrize("nthread", [1, 2])
def test_a_rollout_equals_its_simulations_stepped_one_by_one(nthread):
    model = evs.load_scene("arch_navigation")
    n, t, hold = 3, 6, 40
    commands = random_commands(model, n, t, seed=7)
    batch = [evs.make_data(model) for _ in range(n)]
    out = evs.rollout(model, batch, commands, steps_per_command=hold, nthread=nthread)
    assert out["node_position"].shape == (n, t, sum(d["num_nodes"] for d in model.devices), 3)
    for i in range(n):
        alone = evs.make_data(model)
        for k in range(t):
            for d in range(len(model.devices)):
                evs.set_command(model, alone, d, commands[i, k, 2 * d], commands[i, k, 2 * d + 1])
            evs.step(model, alone, hold)
            nodes = np.concatenate([dev.position for dev in alone.devices])
            assert np.array_equal(out["node_position"][i, k], nodes), (i, k)
            assert out["time"][i, k] == alone.time
            assert out["inserted_length"][i, k, 1] == alone.devices[1].inserted_length
        assert evs.state_text(model, alone) == evs.state_text(model, batch[i])
    assert not out["failed"].any()


def test_views_are_read_only_and_follow_the_data():
    model = evs.load_scene("carotid")
    data = evs.make_data(model)
    position = data.devices[0].position
    start = position.copy()
    assert position.shape == (model.devices[0]["num_nodes"], 3)
    assert not position.flags.writeable
    with pytest.raises(ValueError):
        position[0, 0] = 1.0
    evs.set_command(model, data, "guidewire", 0.05, 0.0)
    evs.step(model, data, 200)
    assert not np.array_equal(position, start)  # the same view, updated in place
    saved = evs.state_text(model, data)
    now = position.copy()
    evs.reset_data(model, data)
    assert np.array_equal(position, start)  # still a view of the data after a reset
    evs.load_state_text(model, data, saved)
    assert np.array_equal(position, now)  # and after loading a state
    rotation = data.devices[0].rotation
    assert np.allclose(np.linalg.norm(rotation, axis=1), 1.0)
    del data  # the view keeps the data alive
    assert np.array_equal(position, now)


def test_step_releases_the_gil():
    model = evs.load_scene("carotid")
    data = evs.make_data(model)
    evs.set_command(model, data, "guidewire", 0.03, 0.0)
    inside = threading.Event()
    worker = threading.Thread(target=lambda: (inside.set(), evs.step(model, data, 3000)))
    worker.start()
    inside.wait()
    ran = 0
    while worker.is_alive():  # Python runs here only while step() has let go of the GIL
        ran += 1
    worker.join()
    assert data.step == 3000
    assert ran > 1000


def test_the_tips_contacts_and_stats_of_a_step():
    model = evs.load_scene("carotid")
    data = evs.make_data(model)
    evs.step(model, data, 2500)  # the scripted insertion reaches the wall at t = 1.345 s
    tip = data.tips[0]
    assert tip["vessel"] in model.vessel_names
    assert np.allclose(tip["position"], data.devices[0].position[-1])
    contacts = data.contacts
    k = data.stats["contacts"]
    assert contacts["point"].shape == (k, 3) and k > 0
    assert np.allclose(np.linalg.norm(contacts["normal"], axis=1), 1.0)
    assert data.max_wall_force == pytest.approx(contacts["force"][contacts["other_device"] < 0].max())
    assert evs.locate(model, data, tip["position"])["vessel"] == tip["vessel"]


def test_the_xray_image_shows_the_device_dark_where_it_projects():
    model = evs.load_scene("carotid")
    start, data = evs.make_data(model), evs.make_data(model)
    evs.step(model, data, 2500)
    xray = evs.XrayRenderer(model, pixels=256)
    image, before = xray.render(data).astype(int), xray.render(start).astype(int)
    assert image.shape == (256, 256)
    distal = np.asarray(data.devices[0].position)[-30:]  # its last 3 cm, in the arch now
    u, v = np.round(xray.project(distal)).astype(int).T
    # Where the wire lies now it was not at the start: those pixels darkened.
    assert np.median(before[v, u] - image[v, u]) > 10
    assert np.median(np.abs(before - image)) == 0  # and the rest of the image did not change


def test_the_autopilot_from_python_reports_as_evsim_navigate(evsim_binary):
    summary = json.loads(run_evsim(evsim_binary, "navigate", "arch_to_left_subclavian",
                                   "--quiet").splitlines()[-1])
    model = evs.load_scene("arch_to_left_subclavian")
    data = evs.make_data(model)
    report = evs.run_autopilot(model, data, summary["target"])
    assert report["reached"] == summary["reached"] is True
    assert report["retries"] == summary["retries"]
    assert report["time"] == pytest.approx(summary["time_s"], abs=1e-3)


def test_bad_input_is_refused_and_the_state_kept():
    model = evs.load_scene("arch_navigation")
    data = evs.make_data(model)
    evs.step(model, data, 50)
    before = evs.state_text(model, data)
    with pytest.raises(ValueError, match="finite"):
        evs.set_command(model, data, "guidewire", float("nan"), 0.0)
    with pytest.raises(ValueError, match="its devices: catheter, guidewire"):
        evs.set_command(model, data, "wire", 0.01, 0.0)
    with pytest.raises(ValueError, match="mode"):
        evs.set_command(model, data, 0, 0.01, 0.0, mode="speed")
    with pytest.raises(ValueError):
        evs.set_command(model, data, 0, 10.0, 0.0)  # beyond the drive's 0.05 m/s
    with pytest.raises(ValueError, match="shape"):
        evs.rollout(model, [data], np.zeros((1, 3, 3)))
    with pytest.raises(ValueError, match="numeric"):
        evs.rollout(model, [data], np.array([[["a"] * 4]]))
    nan = np.zeros((1, 2, 4))
    nan[0, 1, 2] = np.nan
    with pytest.raises(ValueError, match=r"commands\[0, 1\] for device 'guidewire'"):
        evs.rollout(model, [data], nan)
    with pytest.raises(ValueError, match="twice"):
        evs.rollout(model, [data, data], np.zeros((2, 1, 4)))
    with pytest.raises(ValueError, match="made for scene"):
        evs.step(evs.load_scene("carotid"), data)
    with pytest.raises(evs.LoadError, match="no such scene"):
        evs.load_scene("no_such_scene")
    with pytest.raises(evs.LoadError) as bad:
        evs.load_scene_text("name: x\ntime_step: -1\n", "/tmp/bad_scene.yaml")
    assert bad.value.file == "/tmp/bad_scene.yaml" and bad.value.line == 2
    assert "time_step" in str(bad.value)
    with pytest.raises(evs.LoadError, match="evsim_state"):
        evs.load_state_text(model, data, "not a state\n")
    assert evs.state_text(model, data) == before
    evs.step(model, data)  # and it steps on
