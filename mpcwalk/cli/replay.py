"""``mpcwalk replay DIR``: a walk's output folder in the browser viewer."""

import argparse
import time
from pathlib import Path


def add_parser(sub) -> argparse.ArgumentParser:
    """Add ``replay`` to ``sub``."""
    p = sub.add_parser(
        "replay",
        help="open a walk's output folder in the browser (3D viewer)",
        description="Open the output folder of mpcwalk walk in a 3D viewer in the browser: "
        "the robot, planned and landed footsteps, CoM, ZMP reference and measured CoP, the "
        "support polygon, pushes, a time slider with play and speed.",
    )
    p.add_argument("folder", type=Path, help="output folder of mpcwalk walk (--out)")
    p.add_argument("--port", type=int, default=8080, help="port of the viewer (default 8080)")
    p.add_argument("--host", default="127.0.0.1", help="host to serve on (default 127.0.0.1)")
    p.set_defaults(run=run)
    return p


def run(args: argparse.Namespace) -> int:
    """Serve the viewer of ``args.folder`` until interrupted."""
    from mpcwalk.viewer.replay import open_walk

    viewer = open_walk(args.folder, port=args.port, host=args.host)
    print(
        f"the walk of {args.folder} on http://{args.host}:{viewer.server.get_port()} "
        "(Ctrl+C to stop)"
    )
    try:
        while True:
            time.sleep(1.0)
    except KeyboardInterrupt:
        viewer.close()
    return 0
