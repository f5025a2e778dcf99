"""The shows, each a thin shell on the engine of ``sim/`` (the stage and the recorder) and
the same loop (``loop.py``): the formation show (``formation.py``: the robots' brains follow
the plan) and the queue show (``queue.py``: the second seed's followers)."""

from dancebots.shows.formation import STATUS, Fault, RobotEvent, RunResult, SimConfig, simulate
from dancebots.shows.queue import QueueConfig, QueueResult, queue_placement, simulate_queue

__all__ = [
    "STATUS",
    "Fault",
    "QueueConfig",
    "QueueResult",
    "RobotEvent",
    "RunResult",
    "SimConfig",
    "queue_placement",
    "simulate",
    "simulate_queue",
]
