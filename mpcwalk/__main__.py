"""``python -m mpcwalk`` runs the command line."""

import sys

from mpcwalk.cli import main

sys.exit(main())
