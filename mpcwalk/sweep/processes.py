"""Child processes for parallel walks and benchmark workers: one thread per numerical library.

Walks and timed cases run in worker processes side by side; each must keep to one core, or
the BLAS and solver thread pools of the workers fight for the same cores and the timings
mean nothing.
"""

import contextlib
import os
from collections.abc import Iterator

#: Environment of the workers: one thread per numerical library.
SINGLE_THREAD_ENV = {
    "OMP_NUM_THREADS": "1",
    "OPENBLAS_NUM_THREADS": "1",
    "MKL_NUM_THREADS": "1",
    "RAYON_NUM_THREADS": "1",
    "VECLIB_MAXIMUM_THREADS": "1",
    "NUMEXPR_NUM_THREADS": "1",
    "XLA_FLAGS": "--xla_cpu_multi_thread_eigen=false intra_op_parallelism_threads=1",
}


@contextlib.contextmanager
def single_thread_environment() -> Iterator[None]:
    """Set :data:`SINGLE_THREAD_ENV` while child processes are started, then restore the
    environment."""
    saved = {k: os.environ.get(k) for k in SINGLE_THREAD_ENV}
    os.environ.update(SINGLE_THREAD_ENV)
    try:
        yield
    finally:
        for key, value in saved.items():
            if value is None:
                os.environ.pop(key, None)
            else:
                os.environ[key] = value
