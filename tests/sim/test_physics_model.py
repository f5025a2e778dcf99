"""The physics profile's scene, pure (no MuJoCo needed): bodies from the robot-type table,
wheel speeds from each robot's kinematics, and the MJCF text."""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from dancebots.sim.physics_model import (
    LIGHT_TIMESTEP,
    PHYSICAL_TYPES,
    TIMESTEP,
    physical_type,
    scene_xml,
    wheel_speeds,
)
from dancebots.world.model import BUILTIN_ROBOT_TYPES, RobotType

ROOM = np.array([[-5.0, -5.0], [5.0, -5.0], [5.0, 5.0], [-5.0, 5.0]])


def test_measured_bodies_come_from_the_table_and_others_are_scaled_from_husky() -> None:
    husky = physical_type(BUILTIN_ROBOT_TYPES["HUSKY"])
    assert husky is PHYSICAL_TYPES["HUSKY"]
    assert (husky.wheel_radius, husky.track, husky.wheelbase) == (0.1651, 0.5708, 0.512)
    assert husky.total_mass == pytest.approx(46.034 + 4 * 2.637)
    sim = physical_type(BUILTIN_ROBOT_TYPES["SIM"])  # 1.2 x 0.6 m: HUSKY's proportions
    assert sim.drive == "skid"
    assert sim.wheelbase == pytest.approx(0.512 * 1.2 / 0.99)
    assert sim.track == pytest.approx(0.5708 * 0.6 / 0.67)
    assert sim.mass == pytest.approx(46.034 * (1.2 * 0.6) / (0.99 * 0.67))
    assert physical_type(BUILTIN_ROBOT_TYPES["TURTLEBOT3"]).drive == "differential"
    assert physical_type(BUILTIN_ROBOT_TYPES["TRADR"]).wheels_per_side == 5
    custom = physical_type(RobotType("CART", 0.5, 0.4, 0.3, 1.0))
    assert custom.track < 0.4
    assert custom.wheelbase < 0.5
    assert custom.mass > 0


def test_motors_can_spin_a_wheel_and_servos_are_stiff() -> None:
    for name, body in PHYSICAL_TYPES.items():
        kind = BUILTIN_ROBOT_TYPES[name]
        traction = 1.0 * body.wheel_load * body.wheel_radius  # N m at friction 1
        assert body.max_torque > traction
        # the servo reaches its torque 5 % of the top wheel speed off its command
        top = kind.max_speed / body.wheel_radius
        assert body.kv(kind.max_speed) * 0.05 * top == pytest.approx(body.max_torque)


def test_the_turn_expansion_is_the_coulomb_ratio_of_each_body() -> None:
    """1 + mean(x_i^2) / (b/2)^2 over the wheels at x_i: HUSKY's four wheels 1.80 (Clearpath's
    driver uses 1.875), TRADR's five road wheels a side 1.75, none for a differential robot."""
    husky = PHYSICAL_TYPES["HUSKY"]
    assert husky.turn_expansion == pytest.approx(1 + 0.256 ** 2 / 0.2854 ** 2)
    assert husky.turn_expansion == pytest.approx(1.805, abs=1e-3)
    tradr = PHYSICAL_TYPES["TRADR"]
    xs = np.linspace(-0.275, 0.275, 5)
    assert tradr.turn_expansion == pytest.approx(1 + np.mean(xs ** 2) / 0.225 ** 2)
    assert PHYSICAL_TYPES["TURTLEBOT3"].turn_expansion == 1.0


def test_wheel_speeds_are_each_robots_kinematics() -> None:
    husky, tb3 = PHYSICAL_TYPES["HUSKY"], PHYSICAL_TYPES["TURTLEBOT3"]
    command = np.array([[0.5, 1.0], [0.2, -2.0]])
    widened = wheel_speeds([husky, tb3], command)  # calibrated: the track times 1.805
    b = 0.5708 * husky.turn_expansion
    assert widened[:4].tolist() == pytest.approx([(0.5 - b / 2) / 0.1651] * 2
                                                 + [(0.5 + b / 2) / 0.1651] * 2)
    speeds = wheel_speeds([husky, tb3], command, "geometric")
    left = (0.5 - 1.0 * 0.5708 / 2) / 0.1651
    right = (0.5 + 1.0 * 0.5708 / 2) / 0.1651
    assert speeds.tolist() == pytest.approx([left, left, right, right,
                                             (0.2 + 2.0 * 0.08) / 0.033,
                                             (0.2 - 2.0 * 0.08) / 0.033])


def test_the_scene_has_every_robot_wall_and_person() -> None:
    types = [BUILTIN_ROBOT_TYPES["HUSKY"], BUILTIN_ROBOT_TYPES["TRADR"]]
    starts = np.array([[0.0, 0.0, 0.0], [2.0, 1.0, math.pi / 2]])
    obstacle = np.array([[3.0, 3.0], [4.0, 3.0], [3.5, 4.0]])
    root = ET.fromstring(scene_xml(types, starts, ROOM, 2.0, [(obstacle, 0.5)],
                                   np.array([[0.25, 1.7, 0.0]] * 3)))
    assert float(root.find("option").get("timestep")) == TIMESTEP  # type: ignore[union-attr]
    bodies = root.find("worldbody")
    assert bodies is not None
    assert [b.get("name") for b in bodies.findall("body") if b.get("name", "").startswith(
        "robot")] == ["robot0", "robot1"]
    assert len(root.findall(".//freejoint")) == 2
    assert len(root.findall("actuator/velocity")) == 4 + 10  # HUSKY 2 x 2, TRADR 2 x 5
    walls = [g for g in bodies.findall("geom") if g.get("name", "").startswith(("wall",
                                                                                "obstacle"))]
    assert len(walls) == 4 + 3
    people = [b for b in bodies.findall("body") if b.get("mocap") == "true"]
    assert len(people) == 3
    robot1 = bodies.find("body[@name='robot1']")
    assert robot1 is not None
    assert robot1.get("pos", "").split()[:2] == ["2", "1"]
    w, _, _, z = (float(v) for v in robot1.get("quat", "").split())
    assert 2 * math.atan2(z, w) == pytest.approx(math.pi / 2, abs=1e-5)


def test_a_light_robot_gets_the_small_step() -> None:
    root = ET.fromstring(scene_xml([BUILTIN_ROBOT_TYPES["TURTLEBOT3"]], np.zeros((1, 3)), ROOM,
                                   1.0, [], np.zeros((0, 3))))
    assert float(root.find("option").get("timestep")) == LIGHT_TIMESTEP  # type: ignore[union-attr]


def test_walls_lie_outside_the_room_and_inside_obstacles_thin_ones_too() -> None:
    """Each wall box has one face on its polygon's edge, outside the room and inside an
    obstacle, whichever way the polygon winds; an obstacle 2 cm thick gets walls no thicker
    than itself (a 5 cm box would poke out and stop a robot before its edge)."""
    slab = np.array([[2.0, 0.0], [3.0, 0.0], [3.0, 0.02], [2.0, 0.02]])
    for room, obstacle in ((ROOM, slab), (ROOM[::-1].copy(), slab[::-1].copy())):
        root = ET.fromstring(scene_xml([BUILTIN_ROBOT_TYPES["HUSKY"]], np.zeros((1, 3)), room,
                                       1.0, [(obstacle, 0.5)], np.zeros((0, 3))))
        geoms = {g.get("name"): g for g in root.iter("geom")
                 if g.get("name", "").startswith(("wall", "obstacle"))}
        for name, geom in geoms.items():
            x, y, _ = (float(v) for v in geom.get("pos", "").split())
            half = float(geom.get("size", "").split()[1])  # half the thickness
            if name.startswith("wall"):  # outside the 10 x 10 room
                assert max(abs(x), abs(y)) == pytest.approx(5.0 + half)
            elif name.startswith("obstacle"):  # inside the slab
                assert half <= 0.01 + 1e-9
                assert 2.0 - 1e-9 <= x <= 3.0 + 1e-9  # its centre inside the slab
                assert -1e-9 <= y <= 0.02 + 1e-9
