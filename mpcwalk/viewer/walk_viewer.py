"""The scene of one walk on a Viser server.

The robot is drawn from its MuJoCo model (the description both engines load): every visual
geom of its bodies (boxes, spheres, capsules, cylinders, meshes) becomes a scene node, placed
at each time from the logged base pose and joint angles through MuJoCo's forward kinematics.
The rest comes from the log and the plan: planned footsteps (outlines), landed soles
(filled, where each foot was measured after landing), the measured CoM, the ZMP reference
and the measured CoP (per support phase), the support polygon of the planned feet on the
ground at the slider's time, and the pushes as arrows at the torso. A walk on a terrain
shows its blocks (:meth:`Terrain.boxes <mpcwalk.terrain.Terrain.boxes>`) as boxes. The GUI
holds the time slider, a play/pause checkbox and the playback speed.
"""

import threading
import time
from collections.abc import Sequence
from typing import Any

import mujoco
import numpy as np
import pinocchio as pin
import viser

from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.models.support_polygon import foot_rectangle
from mpcwalk.robot import Robot
from mpcwalk.terrain import Terrain
from mpcwalk.walking.log import WalkLog
from mpcwalk.walking.metrics import landing_check_times

_COLORS = {"left": (40, 110, 200), "right": (210, 50, 50)}
_BODY = (170, 175, 185)
_SOLE_THICKNESS = 0.002  # [m] of the footstep plates
_TERRAIN = (158, 143, 122)


def robot_geoms(model: mujoco.MjModel) -> list[int]:
    """The geoms that draw the robot: those of its bodies (not the world's floor or ground)
    in the visible groups 0 to 2."""
    return [g for g in range(model.ngeom) if model.geom_bodyid[g] > 0 and model.geom_group[g] <= 2]


def _quaternion(matrix: np.ndarray) -> np.ndarray:
    quaternion = np.empty(4)
    mujoco.mju_mat2Quat(quaternion, np.ascontiguousarray(matrix, dtype=float).ravel())
    return quaternion  # w, x, y, z: viser's order


def add_terrain(server: viser.ViserServer, terrain: Terrain | None) -> dict[str, Any]:
    """The blocks of ``terrain`` as boxes under ``/terrain`` (none for the level floor);
    returns their handles by name."""
    handles: dict[str, Any] = {}
    for k, box in enumerate(terrain.boxes() if terrain is not None else ()):
        name = f"/terrain/box_{k}"
        handles[name] = server.scene.add_box(
            name,
            color=_TERRAIN,
            dimensions=2.0 * np.asarray(box.half_size),
            wxyz=box.quaternion,
            position=box.center,
        )
    return handles


class RobotScene:
    """The robot's bodies on a Viser server, drawn from its MuJoCo model: every visual geom
    of its bodies becomes a node under ``/robot``, placed by :meth:`place`; the blocks of
    its ``terrain`` (None: the level floor) under ``/terrain``."""

    def __init__(
        self, robot: Robot, server: viser.ViserServer, terrain: Terrain | None = None
    ) -> None:
        self.robot, self.server = robot, server
        self.handles: dict[str, Any] = add_terrain(server, terrain)
        self._data = mujoco.MjData(robot.mj_model)
        self._geoms = robot_geoms(robot.mj_model)
        self._add_robot()

    def _add(self, name: str, handle: Any) -> None:
        self.handles[name] = handle

    def _add_robot(self) -> None:
        model, scene = self.robot.mj_model, self.server.scene
        for g in self._geoms:
            name, size = f"/robot/geom_{g}", model.geom_size[g]
            rgba = model.geom_rgba[g]
            color = np.asarray(255 * rgba[:3], dtype=int) if rgba[3] > 0 else np.array(_BODY)
            handle: Any
            kind = int(model.geom_type[g])  # (numpy ints do not compare with the enum)
            if kind == int(mujoco.mjtGeom.mjGEOM_BOX):
                handle = scene.add_box(name, color=color, dimensions=2.0 * size)
            elif kind == int(mujoco.mjtGeom.mjGEOM_SPHERE):
                handle = scene.add_icosphere(name, radius=float(size[0]), color=color)
            elif kind in (int(mujoco.mjtGeom.mjGEOM_CAPSULE), int(mujoco.mjtGeom.mjGEOM_CYLINDER)):
                capsule = kind == int(mujoco.mjtGeom.mjGEOM_CAPSULE)
                height = 2.0 * float(size[1]) + (2.0 * float(size[0]) if capsule else 0.0)
                handle = scene.add_cylinder(name, radius=float(size[0]), height=height, color=color)
            elif kind == int(mujoco.mjtGeom.mjGEOM_MESH):
                mesh = model.geom_dataid[g]
                first, count = model.mesh_vertadr[mesh], model.mesh_vertnum[mesh]
                faces = model.mesh_face[
                    model.mesh_faceadr[mesh] : model.mesh_faceadr[mesh] + model.mesh_facenum[mesh]
                ]
                handle = scene.add_mesh_simple(
                    name, model.mesh_vert[first : first + count], faces, color=color
                )
            else:  # planes, ellipsoids, height fields: not the robot's
                continue
            self._add(name, handle)

    def place(self, qpos: np.ndarray) -> None:
        """Place the bodies at MuJoCo's configuration ``qpos``."""
        model, data = self.robot.mj_model, self._data
        data.qpos[:] = qpos
        mujoco.mj_kinematics(model, data)
        for g in self._geoms:
            handle = self.handles.get(f"/robot/geom_{g}")
            if handle is not None:
                handle.position = tuple(data.geom_xpos[g])
                handle.wxyz = tuple(_quaternion(data.geom_xmat[g]))


class WalkViewer:
    """A walk on a Viser server: its scene and its playback controls.

    Args:
        robot: The robot that walked.
        log: Its log (with the base position: logs of mpcwalk 0.1 and later).
        schedule: The planned footsteps and phases.
        pushes: ``(start [s], duration [s], force (3,) [N])`` of each push.
        server: A running Viser server, or None to start one on ``host:port``.
        port: Port of a new server (0: any free one).
        host: Host of a new server.
        terrain: The terrain it walked on (None: the level floor).
    """

    def __init__(
        self,
        robot: Robot,
        log: WalkLog,
        schedule: ContactSchedule,
        *,
        pushes: Sequence[tuple[float, float, Any]] = (),
        server: viser.ViserServer | None = None,
        port: int = 8080,
        host: str = "127.0.0.1",
        terrain: Terrain | None = None,
    ) -> None:
        self.robot, self.log, self.schedule = robot, log, schedule
        self.pushes = [(float(s), float(d), np.asarray(f, dtype=float)) for s, d, f in pushes]
        self.server = server or viser.ViserServer(host=host, port=port, verbose=False)
        self.handles: dict[str, Any] = {}
        self.robot_scene = RobotScene(robot, self.server, terrain)
        self.handles.update(self.robot_scene.handles)
        self._frame_the_walk()
        self._add_footsteps()
        self._add_traces()
        self._add_gui()
        self.time = float(log.time[0]) if len(log) else 0.0
        self.show(self.time)

    # ------------------------------------------------------------------ scene
    def _frame_the_walk(self) -> None:
        """A ground grid, and the camera looking at the walk from its side, far enough to
        see the robot's height and the footsteps."""
        plan = self.schedule.plan
        steps = np.array([foot.xy for foot in (plan.initial_left, plan.initial_right, *plan.steps)])
        centre = np.append(0.5 * (steps.min(axis=0) + steps.max(axis=0)), 0.0)
        size = max(float(np.ptp(steps, axis=0).max()), 2.5 * self.robot.com_height)
        self.server.scene.add_grid("/ground", width=4 * size, height=4 * size, cell_size=0.1)
        camera = self.server.initial_camera
        camera.look_at = tuple(centre + np.array([0.0, 0.0, 0.5 * self.robot.com_height]))
        camera.position = tuple(centre + np.array([0.3, -1.2, 0.6]) * size)

    def _add(self, name: str, handle: Any) -> None:
        self.handles[name] = handle

    def _add_footsteps(self) -> None:
        scene, plan, foot = self.server.scene, self.schedule.plan, self.schedule.foot
        for k, step in enumerate(plan.steps):
            outline = foot_rectangle(step.xy, step.yaw, foot.length, foot.width).vertices
            points = np.column_stack([outline, np.full(len(outline), step.position[2] + 0.001)])
            segments = np.stack([points, np.roll(points, -1, axis=0)], axis=1)
            self._add(
                f"/footsteps/planned/{k}",
                scene.add_line_segments(
                    f"/footsteps/planned/{k}", segments, _COLORS[step.side.value], thickness=0.003
                ),
            )
        log = self.log
        for k, t in enumerate(landing_check_times(self.schedule)):
            if not len(log) or t > log.time[-1] + 1e-9:
                break
            i = min(int(np.searchsorted(log.time, t - 1e-9)), len(log) - 1)
            j = 0 if plan.steps[k].side.value == "left" else 1
            yaw = float(log.sole_yaws[i, j])
            self._add(
                f"/footsteps/landed/{k}",
                scene.add_box(
                    f"/footsteps/landed/{k}",
                    color=_COLORS[plan.steps[k].side.value],
                    dimensions=(foot.length, foot.width, _SOLE_THICKNESS),
                    opacity=0.35,
                    wxyz=tuple(
                        pin.Quaternion(pin.rpy.rpyToMatrix(0.0, 0.0, yaw)).coeffs()[[3, 0, 1, 2]]
                    ),
                    position=tuple(log.sole_positions[i, j] + [0, 0, 0.5 * _SOLE_THICKNESS]),
                ),
            )

    def _add_traces(self) -> None:
        scene, log = self.server.scene, self.log
        if not len(log):
            return
        ground = np.zeros((len(log), 1))

        def polyline(name: str, xy: np.ndarray, color, z=ground) -> None:
            points = np.column_stack([xy[:, :2], z])
            keep = np.isfinite(points).all(axis=1)
            segments = np.stack([points[:-1], points[1:]], axis=1)[keep[:-1] & keep[1:]]
            if len(segments):
                self._add(name, scene.add_line_segments(name, segments, color, thickness=0.002))

        polyline("/traces/com", log.com, (0, 0, 0), log.com[:, 2:3])
        polyline("/traces/com_ground", log.com, (60, 60, 60))
        polyline("/traces/zmp_reference", log.zmp_reference, (120, 160, 0))
        phases = self.schedule.phase_index(log.time)
        cut = np.r_[True, np.diff(phases) != 0]  # no segment across a phase change
        cop = np.array(log.cop[:, :2], dtype=float)
        cop[cut] = np.nan
        polyline("/traces/cop", cop, (220, 40, 40))
        for i, (start, _, force) in enumerate(self.pushes):
            k = min(int(np.searchsorted(log.time, start)), len(log) - 1)
            origin = log.base_position[k] if np.isfinite(log.base_position[k]).all() else log.com[k]
            tip = origin + 0.02 * force  # 2 cm per newton
            self._add(
                f"/pushes/{i}",
                scene.add_arrows(
                    f"/pushes/{i}", np.array([[origin, tip]]), (250, 140, 0), shaft_radius=0.004
                ),
            )
        self._add("/support", scene.add_line_segments("/support", np.zeros((1, 2, 3)), (0, 120, 0)))

    def _add_gui(self) -> None:
        gui, log = self.server.gui, self.log
        end = float(log.time[-1]) if len(log) else 0.0
        start = float(log.time[0]) if len(log) else 0.0
        self.slider = gui.add_slider(
            "time [s]", min=start, max=max(end, start + 1e-3), step=0.01, initial_value=start
        )
        self.playing = gui.add_checkbox("play", initial_value=False)
        self.speed = gui.add_slider("speed", min=0.1, max=4.0, step=0.1, initial_value=1.0)
        self.slider.on_update(lambda _: self.show(float(self.slider.value)))
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._play, daemon=True)
        self._thread.start()

    # ------------------------------------------------------------------ time
    def configuration(self, t: float) -> np.ndarray | None:
        """The robot's configuration (Pinocchio's q) at ``t`` from the log, None when the
        log has no base position."""
        log = self.log
        i = min(max(int(np.searchsorted(log.time, t - 1e-9)), 0), len(log) - 1)
        base = log.base_position[i]
        if not np.isfinite(base).all():
            return None
        rotation = pin.rpy.rpyToMatrix(*log.base_rpy[i])
        return np.concatenate([base, pin.Quaternion(rotation).coeffs(), log.joint_positions[i]])

    def show(self, t: float) -> None:
        """Place the robot and the support polygon at time ``t`` [s]."""
        self.time = float(t)
        q = self.configuration(t) if len(self.log) else None
        if q is not None:
            self.robot_scene.place(self.robot.q_to_qpos(q))
        polygon = self.schedule.support_polygon(min(t, self.schedule.duration)).vertices
        points = np.column_stack([polygon, np.full(len(polygon), 0.003)])
        self.handles["/support"].points = np.stack([points, np.roll(points, -1, axis=0)], axis=1)

    def _play(self) -> None:
        last = time.monotonic()
        while not self._stop.is_set():
            time.sleep(0.03)
            now = time.monotonic()
            if self.playing.value and len(self.log):
                t = self.time + (now - last) * float(self.speed.value)
                if t > float(self.log.time[-1]):
                    t = float(self.log.time[0])
                self.slider.value = round(t, 2)  # type: ignore[misc]  # (settable at run time)
                self.show(t)
            last = now

    def close(self) -> None:
        """Stop the playback and the server."""
        self._stop.set()
        self._thread.join(timeout=1.0)
        self.server.stop()
