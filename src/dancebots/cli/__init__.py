"""The ``dancebots`` command: a thin shell that reads files, calls the core, prints results.

``main.py`` is the parser, ``common.py`` what the commands share (exit statuses, printing,
the output writer), and one module per command. Importing the package is cheap: a command's
core modules are imported when it runs.
"""

from dancebots.cli.main import main

__all__ = ["main"]
