"""``python -m dancebots.cli``: the ``dancebots`` command."""

import sys

from dancebots.cli import command

sys.exit(command())
