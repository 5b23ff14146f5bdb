"""The 3D viewer in the browser, through Viser's Python API: the scene of a walk holds the
robot, the footsteps, the traces, the pushes and the support polygon, and moves with the
time slider; the live view follows a walk as it runs. With Chromium on the machine, a
headless browser loads the page and two screenshots at two times differ."""

import shutil
import subprocess
import time

import numpy as np
import pytest

from mpcwalk.cli import main as cli_main
from mpcwalk.robot import load_robot
from mpcwalk.terrain import read_terrain
from mpcwalk.viewer.live import LiveView
from mpcwalk.viewer.replay import open_walk
from mpcwalk.walking.runner import run_walk

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def walk_folder(tmp_path_factory):
    out = tmp_path_factory.mktemp("walk") / "out"
    argv = ["walk", "--robot", "bioloid-like", "--controller", "mpc", "--vx", "0.1"]
    argv += ["--steps", "3", "--push", "2.5,0.1,0,3,0", "--out", str(out), "--no-progress"]
    assert cli_main(argv) == 0
    return out


def test_the_replay_scene_holds_the_walk(walk_folder):
    viewer = open_walk(walk_folder, port=0)
    try:
        kinds = {}
        for name in viewer.handles:
            kinds.setdefault(name.split("/")[1], []).append(name)
        assert len(kinds["robot"]) >= 10  # the bioloid-like's bodies
        planned = [n for n in kinds["footsteps"] if "/planned/" in n]
        landed = [n for n in kinds["footsteps"] if "/landed/" in n]
        assert len(planned) == len(viewer.schedule.plan.steps) == 4  # 3 steps and closing
        assert len(landed) == 4
        assert {"/traces/com", "/traces/zmp_reference", "/traces/cop"} <= set(viewer.handles)
        assert kinds["pushes"] == ["/pushes/0"]
        # the robot and the support polygon follow the slider's time
        torso = next(n for n in kinds["robot"])
        before = np.array(viewer.handles[torso].position)
        support_before = np.array(viewer.handles["/support"].points)
        viewer.show(2.2)  # single support of the second step, 0.15 m further on
        after = np.array(viewer.handles[torso].position)
        assert np.linalg.norm(after - before) > 0.05
        assert not np.allclose(np.array(viewer.handles["/support"].points), support_before)
        # play moves the time
        viewer.playing.value = True
        start = viewer.time
        time.sleep(0.5)
        assert viewer.time > start
    finally:
        viewer.close()


def test_the_replay_of_a_walk_on_a_terrain_shows_its_blocks(tmp_path):
    terrain_file = tmp_path / "low.toml"
    terrain_file.write_text("[[stairs]]\nstart = 0.3\nrise = 0.04\nrun = 0.25\ncount = 2\n")
    out = tmp_path / "out"
    argv = ["walk", "--terrain", str(terrain_file), "--steps", "1", "--no-progress"]
    assert cli_main([*argv, "--out", str(out)]) in (0, 1)
    viewer = open_walk(out, port=0)
    try:
        boxes = read_terrain(terrain_file).boxes()
        blocks = sorted(n for n in viewer.handles if n.startswith("/terrain/"))
        assert len(blocks) == len(boxes) == 2  # two treads: a step and the landing after it
        for k, box in enumerate(boxes):
            handle = viewer.handles[f"/terrain/box_{k}"]
            np.testing.assert_allclose(handle.position, box.center)
    finally:
        viewer.close()


def test_replay_of_a_folder_that_is_not_a_walk_is_a_named_error(tmp_path, capsys):
    assert cli_main(["replay", str(tmp_path)]) == 2
    assert "not the output folder of a walk" in capsys.readouterr().err


def test_the_live_view_follows_the_walk():
    robot = load_robot("bioloid-like")
    view = LiveView(robot, port=0, speed=0.0, fps=1000.0)
    try:
        result = run_walk(
            robot, controller="mpc", command=(0.1, 0.0, 0.0), nb_steps=2, observer=view
        )
        assert view.updates == len(result.log)  # every tick shown at this frame rate
        assert view.time == pytest.approx(result.log.time[-1])
        positions = np.array([np.array(h.position) for h in view.scene.handles.values()])
        # the bodies stand where the walk ended: around its final base position
        base = result.log.base_position[-1]
        assert np.abs(positions[:, :2].mean(axis=0) - base[:2]).max() < 0.05
    finally:
        view.close()


CHROMIUM = next(
    (shutil.which(n) for n in ("chromium", "chromium-browser", "google-chrome") if shutil.which(n)),
    None,
)


@pytest.mark.skipif(CHROMIUM is None, reason="no Chromium on this machine")
def test_a_headless_browser_shows_the_robot_moving(walk_folder, tmp_path):
    """Headless Chromium loads the viewer's page; the canvas is not blank, and its pixels
    change between two times of the slider."""
    from PIL import Image

    viewer = open_walk(walk_folder, port=0)
    url = f"http://127.0.0.1:{viewer.server.get_port()}"

    def screenshot(name: str) -> np.ndarray:
        path = tmp_path / name
        subprocess.run(
            [
                CHROMIUM,
                "--headless=new",
                "--no-sandbox",
                "--use-angle=swiftshader",
                "--window-size=800,600",
                "--virtual-time-budget=8000",
                f"--screenshot={path}",
                url,
            ],
            check=True,
            capture_output=True,
            timeout=120,
        )
        return np.asarray(Image.open(path).convert("RGB"), dtype=float)

    try:
        first = screenshot("first.png")
        viewer.show(3.0)
        second = screenshot("second.png")
    finally:
        viewer.close()
    assert first.std() > 5.0  # not a blank canvas
    assert np.abs(first - second).mean() > 0.1  # the robot moved
