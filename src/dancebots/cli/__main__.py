"""``python -m dancebots.cli``: the ``dancebots`` command."""

import sys

from dancebots.cli.main import main

sys.exit(main())
