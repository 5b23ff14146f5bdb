"""``mpcwalk walk ... --view``: the walk shown live in the browser while it runs.

:class:`LiveView` is the control loop's observer: after each tick it gets the time and
MuJoCo's configuration, places the robot (at most ``fps`` times a second) and holds the
simulation to real time (times ``speed``), so that what the browser shows is the walk as it
happens."""

import time

import numpy as np
import viser

from mpcwalk.robot import Robot
from mpcwalk.terrain import Terrain
from mpcwalk.viewer.walk_viewer import RobotScene


class LiveView:
    """A robot on a Viser server, moved by the control loop as it ticks.

    Args:
        robot: The robot that walks.
        server: A running server, or None to start one on ``host:port``.
        speed: Simulated seconds per wall-clock second (0: as fast as the loop runs).
        fps: Largest number of updates of the scene per second.
        terrain: The terrain it walks on, drawn as boxes (None: the level floor).
    """

    def __init__(
        self,
        robot: Robot,
        *,
        server: viser.ViserServer | None = None,
        port: int = 8080,
        host: str = "127.0.0.1",
        speed: float = 1.0,
        fps: float = 30.0,
        terrain: Terrain | None = None,
    ) -> None:
        self.server = server or viser.ViserServer(host=host, port=port, verbose=False)
        self.scene = RobotScene(robot, self.server, terrain)
        self.speed, self.period = float(speed), 1.0 / float(fps)
        self.updates = 0
        self.time = 0.0
        self._start: float | None = None
        self._last = -np.inf

    def __call__(self, t: float, qpos: np.ndarray) -> None:
        """One tick of the walk at simulated time ``t`` [s]."""
        now = time.monotonic()
        if self._start is None:
            self._start = now - t / self.speed if self.speed > 0 else now
        if self.speed > 0:  # hold the simulation to real time (times speed)
            ahead = self._start + t / self.speed - now
            if ahead > 0:
                time.sleep(ahead)
                now += ahead
        self.time = float(t)
        if now - self._last >= self.period:
            self.scene.place(qpos)
            self.updates += 1
            self._last = now

    def close(self) -> None:
        """Stop the server."""
        self.server.stop()
