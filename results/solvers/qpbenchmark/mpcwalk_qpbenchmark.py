"""qpbenchmark test set of mpcwalk's walking QPs (from `mpcwalk bench solvers`).

Run it with qpbenchmark (pip install "mpcwalk[bench]"):

    python mpcwalk_qpbenchmark.py run [--settings mid_accuracy] [--solver daqp]
    python mpcwalk_qpbenchmark.py report --author <name>
"""

import os

from mpcwalk.bench.solvers.peers.qpbenchmark_test_set import WalkingTestSet

HERE = os.path.dirname(os.path.abspath(__file__))


class MpcwalkQpbenchmark(WalkingTestSet):
    """The walking QPs in data/ next to this file."""

    data_dir = os.path.join(HERE, "data")
    time_limit = 1.0


if __name__ == "__main__":
    from qpbenchmark.benchmark import main

    main(test_set_path=os.path.abspath(__file__),
         results_path=os.path.join(HERE, "results", "qpbenchmark_results.csv"))
