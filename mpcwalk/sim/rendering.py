"""Offscreen rendering of a simulation to an MP4 video, without a screen.

MuJoCo renders through an OpenGL context. Without a display it needs EGL (GPU or Mesa) or
OSMesa (software). ``mujoco.Renderer`` picks its backend from ``MUJOCO_GL`` once, when
``mujoco`` is first imported, which in mpcwalk happens long before a video is asked for; so
this module creates the headless context itself (MuJoCo's own ``mujoco.egl`` or
``mujoco.osmesa`` context classes) and renders with the same calls as ``mujoco.Renderer``
(``mjv_updateScene``, ``mjr_render``, ``mjr_readPixels``). ``MUJOCO_GL=egl`` or ``osmesa``
forces one backend; otherwise EGL is tried, then OSMesa.

Frames are encoded to H.264 MP4 by ``imageio-ffmpeg``, whose wheel ships an ffmpeg binary.
"""

import functools
import importlib
import os
from pathlib import Path

import mujoco
import numpy as np

from mpcwalk.exceptions import ConfigurationError, RenderingUnavailable, VideoDependencyMissing

BACKENDS = ("egl", "osmesa")
"""Headless OpenGL backends, in the order they are tried."""


@functools.lru_cache(maxsize=1)
def _context_class() -> tuple[str, type]:
    """The first headless backend whose context can be created: (name, GLContext class)."""
    forced = os.environ.get("MUJOCO_GL", "").strip().lower()
    candidates = (forced,) if forced in BACKENDS else BACKENDS
    failures: dict[str, str] = {}
    for name in candidates:
        try:
            context_class = importlib.import_module(f"mujoco.{name}").GLContext
            context = context_class(16, 16)
            context.make_current()
            context.free()
            return name, context_class
        except Exception as error:  # any failure of a backend means: try the next one
            failures[name] = f"{type(error).__name__}: {error}".strip()[:200]
    raise RenderingUnavailable(failures)


def gl_backend() -> str:
    """Name of the headless OpenGL backend that works here (``"egl"`` or ``"osmesa"``).

    Raises:
        RenderingUnavailable: Neither works; the message says how to enable one.
    """
    return _context_class()[0]


class VideoRecorder:
    """Renders frames of a MuJoCo model from a camera tracking the robot, into an MP4 file.

    Args:
        path: Output file (``.mp4``).
        model: MuJoCo model; its offscreen buffer is enlarged to ``width`` x ``height`` if
            needed (a visual setting; the physics is unchanged).
        fps: Frames per second of the video [Hz] (simulated time).
        width: Frame width [pixel], even.
        height: Frame height [pixel], even.
        track_body: Body the camera follows; None for the floating base.
        distance: Camera distance to the tracked body [m]; None for 1.6 x the model extent.
        azimuth: Camera azimuth [deg] (90: looking along +y, from the robot's right).
        elevation: Camera elevation [deg] (negative: from above).
        shadows: Render shadows and floor reflections (3 to 4 times slower with a software
            renderer such as Mesa's llvmpipe).

    Raises:
        RenderingUnavailable: No headless OpenGL backend works.
        VideoDependencyMissing: imageio-ffmpeg is not installed.
        ConfigurationError: Odd or non-positive frame size, non-positive fps.
    """

    def __init__(
        self,
        path: str | Path,
        model: mujoco.MjModel,
        *,
        fps: float = 30.0,
        width: int = 640,
        height: int = 480,
        track_body: int | None = None,
        distance: float | None = None,
        azimuth: float = 135.0,
        elevation: float = -15.0,
        shadows: bool = False,
    ) -> None:
        if width <= 0 or height <= 0 or width % 2 or height % 2:
            raise ConfigurationError(
                f"Video frames must have an even positive size, got {width} x {height} pixels."
            )
        if not fps > 0.0:
            raise ConfigurationError(f"Video fps must be > 0, got {fps!r}.")
        try:
            import imageio_ffmpeg
        except ImportError:
            raise VideoDependencyMissing() from None
        self.backend, context_class = _context_class()
        self.path = Path(path)
        self.model, self.fps, self.width, self.height = model, float(fps), width, height
        model.vis.global_.offwidth = max(model.vis.global_.offwidth, width)
        model.vis.global_.offheight = max(model.vis.global_.offheight, height)
        self._context = context_class(width, height)
        self._context.make_current()
        self._mjr_context = mujoco.MjrContext(model, mujoco.mjtFontScale.mjFONTSCALE_150)
        mujoco.mjr_setBuffer(mujoco.mjtFramebuffer.mjFB_OFFSCREEN, self._mjr_context)
        self._scene = mujoco.MjvScene(model, maxgeom=10000)
        self._scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW] = shadows
        self._scene.flags[mujoco.mjtRndFlag.mjRND_REFLECTION] = shadows
        self._option = mujoco.MjvOption()
        self._rect = mujoco.MjrRect(0, 0, width, height)
        self.camera = mujoco.MjvCamera()
        self.camera.type = mujoco.mjtCamera.mjCAMERA_TRACKING
        self.camera.trackbodyid = int(model.jnt_bodyid[0]) if track_body is None else track_body
        self.camera.distance = 1.6 * model.stat.extent if distance is None else distance
        self.camera.azimuth, self.camera.elevation = azimuth, elevation
        self._pixels = np.empty((height, width, 3), dtype=np.uint8)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._writer = imageio_ffmpeg.write_frames(
            str(self.path),
            (width, height),
            fps=self.fps,
            codec="libx264",
            macro_block_size=1,
            quality=6,
            ffmpeg_log_level="error",
        )
        self._writer.send(None)
        self.nb_frames = 0

    def render(self, data: mujoco.MjData) -> np.ndarray:
        """Render ``data`` (forwarded) to an RGB image, shape (height, width, 3), uint8."""
        self._context.make_current()
        mujoco.mjv_updateScene(
            self.model,
            data,
            self._option,
            None,
            self.camera,
            mujoco.mjtCatBit.mjCAT_ALL,
            self._scene,
        )
        mujoco.mjr_render(self._rect, self._scene, self._mjr_context)
        mujoco.mjr_readPixels(self._pixels, None, self._rect, self._mjr_context)
        return np.flipud(self._pixels).copy()

    def capture(self, data: mujoco.MjData, time: float | None = None) -> bool:
        """Add a frame if the next frame is due at simulated ``time`` [s] (default data.time).

        Returns:
            Whether a frame was written.
        """
        time = data.time if time is None else time
        if time + 1e-9 < self.nb_frames / self.fps:
            return False
        self._writer.send(np.ascontiguousarray(self.render(data)))
        self.nb_frames += 1
        return True

    def close(self) -> None:
        """Finish the MP4 file and free the OpenGL context (safe to call twice)."""
        if self._writer is not None:
            self._writer.close()
            self._writer = None
        if self._context is not None:
            self._context.make_current()
            self._mjr_context.free()
            self._context.free()
            self._context = None

    def __enter__(self) -> "VideoRecorder":
        return self

    def __exit__(self, *exc_info) -> None:
        self.close()
