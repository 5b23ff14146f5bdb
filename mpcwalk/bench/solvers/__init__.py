"""``mpcwalk bench solvers``: every QP back-end on the walking QPs, offline and in the loop.

- :mod:`~mpcwalk.bench.solvers.benchmark`: the benchmark, stage by stage
  (:func:`~mpcwalk.bench.solvers.benchmark.run_solver_benchmark`);
- :mod:`~mpcwalk.bench.solvers.config`, :mod:`~mpcwalk.bench.solvers.tolerances`,
  :mod:`~mpcwalk.bench.solvers.results`: what it runs, how a solve is judged, the table of
  solves (``results.csv.gz``) and its statistics;
- ``problems/``: the problem families and the problems sampled from walks;
- ``backends/``: the benchmark's registry of back-ends and their settings per level;
- ``solves/``: one case solved and checked, and the timed solves on Ray timing actors;
- ``loops/``: each back-end as the MPC's solver in a closed loop (LIPM, MuJoCo);
- ``peers/``: the MPC tick against the qpmpc peer, the qpbenchmark test set and run;
- ``report/``: ``report.md`` and its figures.
"""
