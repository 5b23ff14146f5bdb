"""Where the sweeps run: a local Ray instance, started on first use, or a Ray cluster.

Local by default: the first sweep of a process starts Ray on this machine (no set-up, no
network; one CPU slot per core, or ``workers`` of them) and leaves it up for the next sweeps
of the process (:func:`shutdown` stops it; Ray stops it at exit). ``address``
(``ray://HOST:PORT``, a Ray client server, or ``HOST:PORT`` from a node of the cluster) or the
``RAY_ADDRESS`` environment variable connect to a cluster instead; its nodes need mpcwalk
installed (the same version), since the tasks import it.

Every worker runs with one thread per numerical library
(:data:`~mpcwalk.sweep.processes.SINGLE_THREAD_ENV`): one walk per CPU slot.

:func:`local_cluster` starts a cluster of several nodes on this machine (Ray's
``cluster_utils``): the cluster path without a cluster, for the tests and the throughput
measurement.
"""

import contextlib
import importlib.util
import logging
import os
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

from mpcwalk.exceptions import ConfigurationError, MpcwalkError
from mpcwalk.sweep.processes import SINGLE_THREAD_ENV, single_thread_environment

ADDRESS_VARIABLE = "RAY_ADDRESS"
"""Environment variable of the cluster's address (Ray's own)."""


class SweepDependencyMissing(MpcwalkError, ImportError):
    """Ray is not installed, or (``client``) the Ray client's packages for a ``ray://``
    address are not."""

    def __init__(self, *, client: str | None = None) -> None:
        if client is None:
            message = "The sweeps run on Ray, which is not installed: pip install 'ray'."
        else:
            message = (
                f"A ray:// address ({client}) goes through the Ray client, whose packages are "
                "not installed (mpcwalk needs plain ray): pip install 'ray[client]', or give "
                "the cluster's HOST:PORT (the head's port, 6379 by default) from a machine of "
                "the cluster."
            )
        super().__init__(message)


@dataclass
class _State:
    """The Ray instance this process started or connected to."""

    address: str | None = None
    local_cpus: int = 0


_STATE = _State()


def import_ray() -> Any:
    """The ``ray`` module, or :class:`SweepDependencyMissing`."""
    try:
        import ray
    except ImportError as error:
        raise SweepDependencyMissing() from error
    return ray


def cluster_address(address: str | None = None) -> str | None:
    """The cluster to use: ``address``, else ``RAY_ADDRESS``, else None (local)."""
    if address:
        return address
    return os.environ.get(ADDRESS_VARIABLE) or None


def check_workers(workers: int | None) -> None:
    """Raise ConfigurationError unless ``workers`` is None or a positive integer."""
    if workers is None:
        return
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise ConfigurationError(f"workers must be a positive integer, got {workers!r}.")


def ensure_ray(*, address: str | None = None, workers: int | None = None) -> int:
    """Start Ray on this machine, or connect to a cluster, unless this process already did.

    Args:
        address: Cluster address (None: ``RAY_ADDRESS``, else a local instance).
        workers: Local CPU slots (None: one per core). A local instance with fewer slots,
            started by this process, is restarted with more.

    Returns:
        The CPU slots of the instance (the cluster's CPUs).

    Raises:
        SweepDependencyMissing: Ray is not installed, or the Ray client's packages for a
            ``ray://`` address are not.
        ConfigurationError: ``workers`` is not a positive integer.
    """
    check_workers(workers)
    ray = import_ray()
    address = cluster_address(address)
    if address is not None and address.startswith("ray://"):
        if importlib.util.find_spec("grpc") is None:  # the Ray client's, not plain ray's
            raise SweepDependencyMissing(client=address)
    wanted = workers or os.cpu_count() or 1
    if ray.is_initialized():
        local = _STATE.address is None and _STATE.local_cpus > 0
        if local and address is None and wanted > _STATE.local_cpus:
            shutdown()
        elif address is None or address == _STATE.address:
            return max(1, int(ray.cluster_resources().get("CPU", 1)))
        else:
            shutdown()
    options: dict[str, Any] = {
        "log_to_driver": False,
        "logging_level": logging.WARNING,
        "runtime_env": {"env_vars": dict(SINGLE_THREAD_ENV)},
    }
    if address is None:
        with single_thread_environment():  # the local workers inherit it as well
            ray.init(address="local", num_cpus=wanted, include_dashboard=False, **options)
        _STATE.address, _STATE.local_cpus = None, wanted
    else:
        ray.init(address=address, **options)
        _STATE.address, _STATE.local_cpus = address, 0
    return max(1, int(ray.cluster_resources().get("CPU", 1)))


def shutdown() -> None:
    """Stop the local Ray instance (or leave the cluster) this process started."""
    try:
        import ray
    except ImportError:
        return
    if ray.is_initialized():
        ray.shutdown()
    _STATE.address, _STATE.local_cpus = None, 0


@contextlib.contextmanager
def ray_session(*, address: str | None = None, workers: int | None = None) -> Iterator[int]:
    """:func:`ensure_ray` as a context: yields the number of cases to run at once
    (``workers``, else the instance's CPU slots)."""
    slots = ensure_ray(address=address, workers=workers)
    yield workers or slots


@contextlib.contextmanager
def local_cluster(*, nodes: int = 2, cpus_per_node: int = 1) -> Iterator[str]:
    """A Ray cluster of ``nodes`` nodes on this machine, for the time of the block; yields
    its address, which the sweeps take as a real cluster's (``address=``, ``--address``).

    ``ray.cluster_utils.Cluster``: a head node and ``nodes - 1`` worker nodes, each its own
    raylet with ``cpus_per_node`` CPU slots, every port chosen by the system (none of Ray's
    fixed defaults, so it runs beside another Ray instance), no dashboard; its workers run
    with :data:`~mpcwalk.sweep.processes.SINGLE_THREAD_ENV`. It runs the code that connects
    to a cluster and spreads the cases over its nodes, the network aside. At the end, this
    process leaves the cluster (:func:`shutdown`, if it joined it) and the nodes stop.

    Raises:
        SweepDependencyMissing: Ray is not installed.
        ConfigurationError: ``nodes`` or ``cpus_per_node`` is not a positive integer.
    """
    for name, value in (("nodes", nodes), ("cpus_per_node", cpus_per_node)):
        if isinstance(value, bool) or not isinstance(value, int) or value < 1:
            raise ConfigurationError(
                f"{name} of a local cluster must be a positive integer, got {value!r}."
            )
    import_ray()
    from ray.cluster_utils import Cluster

    node: dict[str, Any] = {"num_cpus": cpus_per_node, "dashboard_agent_listen_port": None}
    with single_thread_environment():  # the nodes' workers inherit it
        cluster = Cluster(
            initialize_head=True,
            connect=False,
            head_node_args={**node, "include_dashboard": False},
        )
    try:
        with single_thread_environment():
            for _ in range(nodes - 1):
                cluster.add_node(**node)
        cluster.wait_for_nodes()
        yield str(cluster.address)
    finally:
        if _STATE.address == cluster.address:
            shutdown()
        cluster.shutdown()


def where(address: str | None = None) -> str:
    """Where the sweeps run, in words (for the reports)."""
    address = cluster_address(address)
    return "local Ray instance" if address is None else f"Ray cluster at {address}"


__all__ = [
    "ADDRESS_VARIABLE",
    "SweepDependencyMissing",
    "check_workers",
    "cluster_address",
    "ensure_ray",
    "import_ray",
    "local_cluster",
    "ray_session",
    "shutdown",
    "where",
]
