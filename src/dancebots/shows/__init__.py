"""The shows, each a thin shell on the engine of ``sim/`` (the stage and the recorder) and
the same loop (``loop.py``): the formation show (``formation.py``: the robots' brains follow
the plan) and the queue show (``queue.py``: the second seed's followers).

Import the show you run from its module: this package imports neither, so a formation run
never loads the queue's detectors (scikit-learn: about 100 MB and a second)."""

__all__: list[str] = []
