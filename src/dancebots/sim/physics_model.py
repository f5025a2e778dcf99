"""The robots, the room and the people of a show as a MuJoCo scene (the ``physics`` profile).

Pure: robot types in, physical parameters and MJCF text out; nothing here imports MuJoCo
(``sim.physics`` runs the scene). Units m, kg, s, rad; world frame.

**Robots.** Each robot type becomes a chassis box on wheels driven by velocity servos
(``<velocity>`` actuators: torque = kv (commanded - actual wheel speed), capped at the motor's
torque). Skid-steer robots (HUSKY, SIM) have four wheels, tracked ones (TRADR) a row of road
wheels under each side standing in for a track, differential ones (TURTLEBOT3) two wheels and
frictionless ball casters in front and behind. A commanded (v, w) becomes wheel speeds by the
robot's own kinematics, (v -+ w b / 2) / r for the left and right side (r the wheel radius).
A skid-steer or tracked robot cannot turn without its wheels sliding sideways, so with b its
track (``geometric``) it turns more slowly than commanded: a HUSKY at about 0.55 of the rate,
the SIM robot at 0.4. Real drivers widen b for it (Clearpath's HUSKY driver by 1.875), and so
does the ``calibrated`` drive (the default, the ``physics`` profile): b is the track times the
body's ICR expansion (:attr:`PhysicalType.turn_expansion`); ``physics-geometric`` keeps the
plain track, and the followers' feedback alone closes the gap.

Where the numbers come from (:data:`PHYSICAL_TYPES`):

* HUSKY: Clearpath's ``husky_description`` URDF (chassis 46.034 kg; wheels 2.637 kg, radius
  0.1651 m, width 0.1143 m; wheelbase 0.512 m; track 0.5708 m) and the thesis's footprint
  (99 x 67 cm, 1 m/s); height 0.39 m (Clearpath's data sheet).
* TURTLEBOT3 (Burger): ROBOTIS e-Manual (about 1 kg; wheel radius 0.033 m; wheel separation
  0.160 m; 138 x 178 x 192 mm; 0.22 m/s).
* TRADR: the thesis gives its footprint (73 x 60 cm) and speed (0.5 m/s), not its mass or
  tracks: 25 kg, a 0.55 m track of 5 road wheels of radius 0.07 m per side, 0.45 m apart
  (assumed, from the footprint).
* SIM: the thesis's 2D simulator robot (1.2 x 0.6 m, 0.5 m/s) has no body: a skid-steer
  robot with HUSKY's proportions and mass per footprint area (assumed).
* Any other type of a world file: like SIM, from its footprint.

Assumed for every robot (no seed gives them): wheel-floor friction 1.0 (rubber on a hall
floor); a motor torque that can spin a wheel against its traction (4 times the friction
torque), so traction, not the motor, limits a turn; a stiff wheel speed loop that reaches that
torque 5 % of the top wheel speed off its command. Contacts are soft (``solimp`` 0 0.95 0.001, as
MuJoCo's documentation suggests for wheels that must slide): with MuJoCo's stiff default a
skid-steer HUSKY turned at a fifth of the Coulomb-friction prediction; soft, it turns on the
spot at 0.54 of its commanded rate, where Coulomb friction predicts 0.55 and the real robot's
controller multiplies the wheel separation by about 1.5-1.9 (a turn rate of 0.53-0.67).

**Room, obstacles and people.** Every edge of the room and of each obstacle is a thin static
wall of its height; people are kinematic cylinders (mocap bodies) moved to where the
simulator's spectators and crowds walk. Wheels touch only the floor; chassis, walls and
people touch each other (a track's road wheels overlap and must not touch).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from dancebots.world.model import BUILTIN_ROBOT_TYPES, RobotType

__all__ = ["FRICTION", "GRAVITY", "LIGHT_TIMESTEP", "PHYSICAL_TYPES", "SERVO_ERROR", "TIMESTEP",
           "Drive", "DriveKinematics",
           "PhysicalType", "physical_type", "scene_xml", "wheel_speeds"]

FloatArray = NDArray[np.float64]
Drive = Literal["skid", "tracks", "differential"]
DriveKinematics = Literal["calibrated", "geometric"]

GRAVITY = 9.81
"""m/s^2."""
FRICTION = 1.0
"""Wheel-floor friction coefficient (assumed: rubber on a hall floor)."""
SERVO_ERROR = 0.05
"""The wheel servos reach their torque limit at this fraction of the top wheel speed off the
commanded one (assumed: a stiff speed loop, as the robots' motor drivers close)."""
TORQUE_MARGIN = 4.0
"""The motor torque as a multiple of the torque that makes a wheel slip (assumed)."""
TIMESTEP = 0.005
"""s: the engine's step (20 per 0.1 s tick of the stage)."""
LIGHT_TIMESTEP = 0.002
"""s: the step where a robot is lighter than LIGHT_MASS (the 1 kg TurtleBot3 on 33 mm wheels:
its turns broke down at 0.004 s and more)."""
LIGHT_MASS = 5.0
"""kg."""
TURN_EXPANSION_MAX = 3.0
"""The widest a driver widens the track (a 5 x 0.05 m world-file robot would need 3,800 times:
its wheels flung it off the floor)."""
WALL_THICKNESS = 0.05
"""m: the thickness of the static walls along the room's and the obstacles' edges."""
PERSON_HEIGHT = 1.7
"""m: the people's cylinders where a spectator gives no height."""


@dataclass(frozen=True, slots=True)
class PhysicalType:
    """A robot type's body: ``drive``; chassis ``mass`` (kg) and ``height`` (m, floor to top);
    ``wheel_radius``, ``wheel_mass`` (kg, each); ``wheels_per_side``; ``wheelbase`` (m, first
    to last wheel along x; 0 for one wheel a side); ``track`` (m, between the left and right
    contact lines); ``source``: where the numbers come from."""

    drive: Drive
    mass: float
    height: float
    wheel_radius: float
    wheel_mass: float
    wheels_per_side: int
    wheelbase: float
    track: float
    source: str

    @property
    def total_mass(self) -> float:
        return self.mass + 2 * self.wheels_per_side * self.wheel_mass

    @property
    def wheel_load(self) -> float:
        """N: the weight each wheel carries standing (a caster carries none)."""
        return self.total_mass * GRAVITY / (2 * self.wheels_per_side)

    @property
    def armature(self) -> float:
        """kg m^2: the gearmotor's rotor inertia as the wheel feels it (times the gear ratio
        squared), assumed equal to the inertia of the robot's mass share a wheel drives."""
        return (self.total_mass / (2 * self.wheels_per_side)) * self.wheel_radius ** 2

    @property
    def turn_expansion(self) -> float:
        """How much wider than its track a skid-steer or tracked robot turns (Mandow et al.,
        "Experimental kinematics for wheeled skid-steer mobile robots", IROS 2007: the
        instantaneous centres of rotation of the two sides lie this many half-tracks from the
        centre). The moment balance of friction at wheels at x_i along the body and +-b/2
        across that slide equally fast (Coulomb friction exactly for two wheels a side, an
        approximation for a track's road wheels): turning on the spot balances where
        w = u (b/2) / (mean x_i^2 + (b/2)^2), so
        1 + mean x_i^2 / (b/2)^2: HUSKY 1.80 (Clearpath's own driver multiplies the wheel
        separation by 1.875), SIM 2.47, TRADR 1.75; 1 for a differential robot; at most
        TURN_EXPANSION_MAX (a body much longer than wide hardly turns by skidding at all)."""
        if self.drive == "differential" or self.wheels_per_side < 2:
            return 1.0
        xs = np.linspace(-self.wheelbase / 2, self.wheelbase / 2, self.wheels_per_side)
        return min(1.0 + float(np.mean(xs ** 2)) / (self.track / 2.0) ** 2, TURN_EXPANSION_MAX)

    def kv(self, max_speed: float) -> float:
        """N m s: the wheel servo's gain: the motor torque at SERVO_ERROR of the wheel speed
        that drives the robot at ``max_speed`` m/s (a stiff speed loop)."""
        return self.max_torque / (SERVO_ERROR * max_speed / self.wheel_radius)

    @property
    def max_torque(self) -> float:
        """N m: each wheel's motor torque."""
        return TORQUE_MARGIN * FRICTION * self.wheel_load * self.wheel_radius


PHYSICAL_TYPES: dict[str, PhysicalType] = {
    "HUSKY": PhysicalType("skid", 46.034, 0.39, 0.1651, 2.637, 2, 0.512, 0.5708,
                          "Clearpath husky_description URDF, data sheet; thesis ch. 2"),
    "TURTLEBOT3": PhysicalType("differential", 0.85, 0.192, 0.033, 0.05, 1, 0.0, 0.160,
                               "ROBOTIS e-Manual, TurtleBot3 Burger"),
    "TRADR": PhysicalType("tracks", 25.0, 0.5, 0.07, 0.3, 5, 0.55, 0.45,
                          "thesis ch. 2 footprint and speed; mass and tracks assumed"),
}


def physical_type(robot_type: RobotType) -> PhysicalType:
    """The body of ``robot_type``: measured for HUSKY, TURTLEBOT3 and (partly) TRADR; for any
    other type a skid-steer robot with HUSKY's proportions scaled to its footprint and HUSKY's
    mass per footprint area (SIM, a world file's types)."""
    known = PHYSICAL_TYPES.get(robot_type.name)
    builtin = BUILTIN_ROBOT_TYPES.get(robot_type.name)
    if known is not None and builtin is not None and (
            abs(builtin.length - robot_type.length) < 0.01
            and abs(builtin.width - robot_type.width) < 0.01):
        return known  # a world file that gives HUSKY another size gets a scaled body
    husky, husky_type = PHYSICAL_TYPES["HUSKY"], (0.99, 0.67)
    length, width = robot_type.length, robot_type.width
    area = (length * width) / (husky_type[0] * husky_type[1])
    scale = min(length / husky_type[0], width / husky_type[1])
    return PhysicalType("skid", husky.mass * area, husky.height * scale,
                        husky.wheel_radius * scale, husky.wheel_mass * area, 2,
                        husky.wheelbase * length / husky_type[0],
                        husky.track * width / husky_type[1],
                        "HUSKY's proportions scaled to the footprint (assumed)")


def wheel_speeds(bodies: Sequence[PhysicalType], command: FloatArray,
                 drive: DriveKinematics = "calibrated") -> FloatArray:
    """The wheel speeds (rad/s) for commands (R, 2) (v m/s, w rad/s), in the scene's actuator
    order (per robot its left wheels, then its right wheels): (v -+ w b / 2) / r on the left
    and right, r the wheel radius, b the track (``geometric``) or the track times the body's
    :attr:`~PhysicalType.turn_expansion` (``calibrated``: what the robots' drivers do, so that
    a skid-steer robot turns about as fast as commanded although its wheels slip)."""
    speeds = []
    for body, (v, w) in zip(bodies, np.asarray(command, dtype=float).tolist(), strict=True):
        n = body.wheels_per_side
        b = body.track * (body.turn_expansion if drive == "calibrated" else 1.0)
        speeds += [(v - w * b / 2.0) / body.wheel_radius] * n
        speeds += [(v + w * b / 2.0) / body.wheel_radius] * n
    return np.array(speeds)


def _f(value: float) -> str:
    return f"{value:.6g}"


def _robot_xml(index: int, body: PhysicalType, kind: RobotType,
               pose: FloatArray) -> tuple[str, list[str]]:
    """A robot's body (MJCF) at ``pose`` (x, y, yaw) and its actuators (left, then right)."""
    r, length, width = body.wheel_radius, kind.length, kind.width
    bottom = 0.5 * r  # the chassis clears the floor by half a wheel radius
    half_height = max(body.height - bottom, 0.02) / 2.0
    yaw = float(pose[2])
    parts = [f'<body name="robot{index}" pos="{_f(pose[0])} {_f(pose[1])} {_f(r)}" '
             f'quat="{_f(math.cos(yaw / 2))} 0 0 {_f(math.sin(yaw / 2))}">',
             f'<freejoint name="robot{index}"/>',
             f'<geom type="box" size="{_f(length / 2)} {_f(width / 2)} {_f(half_height)}" '
             f'pos="0 0 {_f(bottom - r + half_height)}" mass="{_f(body.mass)}" '
             'contype="2" conaffinity="2" rgba="0.3 0.5 0.8 1"/>']
    if body.drive == "differential":  # frictionless ball casters in front and behind
        caster = min(r, 0.02)
        parts += [f'<geom type="sphere" size="{_f(caster)}" pos="{_f(x)} 0 {_f(caster - r)}" '
                  f'mass="{_f(body.wheel_mass)}" condim="1" priority="1" friction="0 0 0" '
                  'contype="1" conaffinity="0"/>' for x in (0.35 * length, -0.35 * length)]
    actuators = []
    n = body.wheels_per_side
    xs = [0.0] if n == 1 else np.linspace(body.wheelbase / 2, -body.wheelbase / 2, n).tolist()
    for side, sign in (("l", 1.0), ("r", -1.0)):
        for k, x in enumerate(xs):
            name = f"robot{index}_{side}{k}"
            # a sphere touches the floor at one point, like a narrow tyre (a cylinder touches
            # at its two rims and scrubs when it turns)
            parts.append(f'<body name="{name}" pos="{_f(x)} {_f(sign * body.track / 2)} 0">'
                         f'<joint name="{name}" type="hinge" axis="0 1 0" '
                         f'armature="{_f(body.armature)}"/>'
                         f'<geom type="sphere" size="{_f(r)}" mass="{_f(body.wheel_mass)}" '
                         f'friction="{_f(FRICTION)} 0.005 0.0001" contype="1" '
                         'conaffinity="0"/></body>')  # the floor, not each other
            actuators.append(f'<velocity joint="{name}" kv="{_f(body.kv(kind.max_speed))}" '
                             f'forcerange="{_f(-body.max_torque)} {_f(body.max_torque)}"/>')
    parts.append("</body>")
    return "".join(parts), actuators


def _walls_xml(polygon: FloatArray, height: float, name: str, outside: bool) -> str:
    """Thin static boxes along every edge of ``polygon`` (N, 2), ``height`` m tall, each with
    one face on the edge and the box ``outside`` the polygon (a room's walls: the robots stand
    inside) or inside it (an obstacle's): a robot touches the wall where its footprint reaches
    the edge, as the stage's contact test has it."""
    points = np.asarray(polygon, dtype=float)
    x, y = points[:, 0], points[:, 1]
    twice_area = float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))
    side = (1.0 if outside else -1.0) * (1.0 if twice_area > 0.0 else -1.0)
    perimeter = float(np.hypot(*(np.roll(points, -1, axis=0) - points).T).sum())
    # inside an obstacle no thicker than the obstacle (2 area / perimeter: a thin slab's
    # thickness), so that no box pokes out of it
    thickness = WALL_THICKNESS if outside else min(
        WALL_THICKNESS, abs(twice_area) / perimeter if perimeter > 0.0 else WALL_THICKNESS)
    walls = []
    for k in range(len(points)):
        a, b = points[k], points[(k + 1) % len(points)]
        length = float(np.hypot(*(b - a)))
        if length <= 0.0:
            continue
        normal = np.array([b[1] - a[1], a[0] - b[0]]) / length  # right of a -> b
        middle = (a + b) / 2.0 + side * normal * thickness / 2.0
        angle = math.atan2(float(b[1] - a[1]), float(b[0] - a[0]))
        walls.append(f'<geom name="{name}_{k}" type="box" size="{_f(length / 2)} '
                     f'{_f(thickness / 2)} {_f(height / 2)}" pos="{_f(middle[0])} '
                     f'{_f(middle[1])} {_f(height / 2)}" euler="0 0 {_f(math.degrees(angle))}" '
                     'contype="2" conaffinity="2" rgba="0.6 0.6 0.6 1"/>')
    return "".join(walls)


def scene_xml(types: Sequence[RobotType], starts: FloatArray, room: FloatArray | None,
              wall_height: float, obstacles: Sequence[tuple[FloatArray, float]],
              people: FloatArray) -> str:
    """The MJCF scene: robots of ``types`` at ``starts`` (R, 3), the ``room`` polygon (N, 2)
    with walls ``wall_height`` m tall (None: an open floor), ``obstacles`` (polygon (M, 2),
    height m) and ``people`` (C, 3) as (radius m, height m, unused) kinematic cylinders
    (mocap bodies, placed at every step)."""
    robots, actuators = [], []
    for i, (kind, pose) in enumerate(zip(types, np.asarray(starts, dtype=float), strict=True)):
        body, acts = _robot_xml(i, physical_type(kind), kind, pose)
        robots.append(body)
        actuators.extend(acts)
    walls = "" if room is None else _walls_xml(room, wall_height, "wall", outside=True)
    walls += "".join(_walls_xml(polygon, height, f"obstacle{k}", outside=False)
                     for k, (polygon, height) in enumerate(obstacles))
    persons = "".join(
        f'<body name="person{k}" mocap="true" pos="0 0 {_f(-10.0 - height)}">'
        f'<geom type="cylinder" size="{_f(radius)} {_f(height / 2)}" pos="0 0 {_f(height / 2)}" '
        'contype="2" conaffinity="2" rgba="0.7 0.4 0.7 1"/></body>'
        for k, (radius, height, _) in enumerate(np.asarray(people, dtype=float).reshape(-1, 3)))
    light = any(physical_type(kind).total_mass < LIGHT_MASS for kind in types)
    return ('<mujoco model="dancebots">'
            f'<option timestep="{_f(LIGHT_TIMESTEP if light else TIMESTEP)}" '
            'integrator="implicitfast" '
            f'gravity="0 0 {_f(-GRAVITY)}"/>'
            '<default><geom solimp="0 0.95 0.001"/></default>'
            '<worldbody><geom name="floor" type="plane" size="0 0 1" contype="1" conaffinity="1" '
            f'friction="{_f(FRICTION)} 0.005 0.0001"/>'
            f"{walls}{''.join(robots)}{persons}</worldbody>"
            f"<actuator>{''.join(actuators)}</actuator></mujoco>")
