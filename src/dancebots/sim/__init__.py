"""The 2D simulator: arena and start poses, kinematics, collisions, the simulation loop."""

from dancebots.sim.kinematics import IDEAL, PROFILES, REALISTIC, Profile
from dancebots.sim.setup import Arena, Placement, SetupError, prepare_show
from dancebots.sim.simulator import CollisionEvent, RunResult, SimConfig, simulate

__all__ = [
    "IDEAL",
    "PROFILES",
    "REALISTIC",
    "Arena",
    "CollisionEvent",
    "Placement",
    "Profile",
    "RunResult",
    "SetupError",
    "SimConfig",
    "prepare_show",
    "simulate",
]
