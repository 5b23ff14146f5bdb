"""A sweep on Ray: the linear MPC and paper M's closed form under three torso masses and two
seeds, each walk a Ray task (Ray starts itself on this machine; pass a cluster's address
as the second argument), the rows in OUT/results.csv. Run it twice: the second run finds
every row and runs nothing.

    python examples/sweep_on_ray.py OUT [ray://HOST:10001]
"""

import sys

from mpcwalk import WalkSpec
from mpcwalk.sweep import Sweep, run_sweep
from mpcwalk.walking.sweep_cases import WALK_COLUMNS, run_walk_case

out = sys.argv[1] if len(sys.argv) > 1 else "out/sweep"
address = sys.argv[2] if len(sys.argv) > 2 else None
walk = WalkSpec.build("bioloid-like", command=(0.1, 0.0, 0.0), nb_steps=3)
cases = tuple(  # each case a walk specification, its id the hash of the specification
    walk.replace(controller=controller, mass_scale=mass, seed=seed)
    for controller in ("mpc", "paper-m-open")
    for mass in (0.8, 1.0, 1.2)
    for seed in (0, 1)
)
run = run_sweep(
    Sweep("mass-sweep", cases, run_walk_case, WALK_COLUMNS), out, address=address, progress=False
)
print(f"{run.nb_run} walks run, {run.nb_resumed} already there, {run.nb_errors} errors")
for row in run.rows:
    print(
        f"{row['controller']:13s} mass x{row['mass_scale']:.1f} seed {row['seed']}: fell {row['fell']}"
    )
print("walk the last one again alone:", cases[-1].command_line(out="out/again"))
