"""The sweep engine on a Ray cluster of two nodes on this machine (``ray.cluster_utils``): the
code that connects to a cluster by its address, the cases spread over the nodes, every row
back on the machine that ran the sweep.

Every port of the cluster is chosen by the system (``local_cluster``), so the file runs beside
another file's local Ray instance under ``pytest -n 2``."""

import pytest

from mpcwalk.sweep import Sweep, local_cluster, read_rows, run_sweep, shutdown

pytestmark = pytest.mark.slow


def test_a_sweep_on_a_two_node_cluster_runs_on_both_nodes(tmp_path):
    """Four one-step walks given to the engine with the cluster's address (a head and a
    worker node, one CPU each): every walk has its row, none fell, and the rows' Ray node ids
    are the cluster's two nodes (both ran walks); the driver leaves the cluster at the
    end."""
    import ray

    from mpcwalk.walking.specification import WalkSpec
    from mpcwalk.walking.sweep_cases import WALK_COLUMNS, run_walk_case

    base = WalkSpec.build("bioloid-like", controller="paper-m", command=(0.1, 0.0, 0.0), nb_steps=1)
    cases = tuple(base.replace(seed=seed) for seed in range(4))
    shutdown()  # a local instance left by an earlier test of this process
    with local_cluster(nodes=2, cpus_per_node=1) as address:
        run = run_sweep(
            Sweep("cluster", cases, run_walk_case, WALK_COLUMNS),
            tmp_path,
            address=address,
            progress=False,
        )
        assert ray.is_initialized() and ray.get_runtime_context().gcs_address == address
        nodes = {node["NodeID"]: node["Resources"]["CPU"] for node in ray.nodes() if node["Alive"]}
    assert not ray.is_initialized()
    assert len(nodes) == 2 and set(nodes.values()) == {1.0}
    assert run.complete and run.nb_run == 4 and run.workers == 2  # the cluster's CPUs
    assert [row["case_id"] for row in run.rows] == [case.case_id for case in cases]
    for row in run.rows:
        assert row["error"] is None and row["fell"] is False
        assert row["steps_completed"] == row["steps_planned"] == 2
    assert {row["node"] for row in run.rows} == set(nodes)
    table = read_rows(tmp_path / "results.csv")
    assert [row["node"] for row in table] == [row["node"] for row in run.rows]
