"""The sweep engine on a Ray cluster of two nodes on this machine (``ray.cluster_utils``): the
code that connects to a cluster by its address, the cases spread over the nodes, every row
back on the machine that ran the sweep.

Every port of the cluster is chosen by the system (``local_cluster``), so the file runs beside
another file's local Ray instance under ``pytest -n 2``."""

import pytest

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.experiments.scaling import (
    ThroughputRun,
    measure_throughput,
    scaling_text,
    summary_rows,
)
from mpcwalk.sweep import Sweep, local_cluster, read_rows, run_sweep, shutdown


@pytest.mark.slow
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
    assert all(0.0 < row["cpu_time_s"] for row in run.rows)
    table = read_rows(tmp_path / "results.csv")
    assert [row["node"] for row in table] == [row["node"] for row in run.rows]


def run(place: str, workers: int, sweep_s: float, repeat: int = 0) -> ThroughputRun:
    busy = 0.8 * sweep_s * workers
    return ThroughputRun(place, workers, repeat, 32, 0, workers, 3.0, sweep_s, busy, 0.5 * busy)


def test_the_throughput_summary_takes_medians_and_ratios():
    """Walks a minute (per core), the speed-up over one worker at the same place and the
    local instance's sweep time over the cluster's, from the medians of the repetitions."""
    runs = [run("local", 1, t, i) for i, t in enumerate((20.0, 22.0, 30.0))]
    runs += [run("local", 2, 11.0), run("cluster", 1, 24.0), run("cluster", 2, 16.0)]
    rows = {(r["place"], r["workers"]): r for r in summary_rows(runs)}
    local1, local2, cluster2 = rows["local", 1], rows["local", 2], rows["cluster", 2]
    assert local1["repeats"] == 3 and local1["sweep_s"] == 22.0
    assert local2["per_minute"] == pytest.approx(60 * 32 / 11.0)
    assert local2["per_minute_per_core"] == pytest.approx(30 * 32 / 11.0)
    assert local2["speed_up"] == pytest.approx(2.0) and cluster2["speed_up"] == 1.5
    assert cluster2["local_over_this"] == pytest.approx(11.0 / 16.0)
    assert cluster2["busy_share"] == pytest.approx(0.8) and cluster2["cpu_share"] == 0.5
    assert cluster2["per_cpu_minute"] == pytest.approx(60 * 32 / (0.5 * 0.8 * 16.0 * 2))
    text = scaling_text(runs, command="mpcwalk experiment scaling robustness", what="32 walks")
    row = (
        "| local cluster (one node per worker) | 2 | 2 | 3.0 | 16.0 | 120.0 | 60.0 | 1.50 | 0.80 |"
    )
    assert row + " 150.0 | 0.50 | 0.69 |" in text


def test_the_throughput_measurement_refuses_bad_input_before_ray_starts(monkeypatch):
    sweep = Sweep("none", (), str, ())
    with pytest.raises(ConfigurationError, match="places among"):
        measure_throughput(sweep, places=("remote",))
    with pytest.raises(ConfigurationError, match="positive integer"):
        measure_throughput(sweep, workers=(0,))
    monkeypatch.setenv("RAY_ADDRESS", "ray://head:10001")
    with pytest.raises(ConfigurationError, match="RAY_ADDRESS is set.*unset it"):
        measure_throughput(sweep)


def test_a_ray_client_address_without_the_client_packages_is_a_named_error(monkeypatch):
    """``ray://`` goes through the Ray client, whose packages (grpc) plain ``ray`` lacks: a
    named error with the fix, before Ray is called."""
    import sys

    from mpcwalk.sweep import SweepDependencyMissing, ensure_ray

    monkeypatch.setitem(sys.modules, "grpc", None)  # as when it is not installed
    with pytest.raises(
        SweepDependencyMissing, match=r"ray://head:10001.*pip install 'ray\[client\]'"
    ):
        ensure_ray(address="ray://head:10001")
