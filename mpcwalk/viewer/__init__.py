"""A walk in the browser: the robot's bodies, planned and landed footsteps, CoM, ZMP
reference and measured CoP traces, the support polygon, pushes as arrows, and a time slider
with play, pause and speed (:class:`WalkViewer`, ``mpcwalk replay DIR``), on Viser."""

from mpcwalk.viewer.walk_viewer import WalkViewer, robot_geoms

__all__ = ["WalkViewer", "robot_geoms"]
