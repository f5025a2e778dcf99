"""The simulation engine: arena and start poses, kinematics, collisions, the LIDAR, the stage
and the recorder (the shows that run on it are in ``shows/``)."""

from dancebots.sim.kinematics import IDEAL, PROFILES, REALISTIC, Profile
from dancebots.sim.setup import Arena, Placement, SetupError, prepare_show

__all__ = [
    "IDEAL",
    "PROFILES",
    "REALISTIC",
    "Arena",
    "Placement",
    "Profile",
    "SetupError",
    "prepare_show",
]
