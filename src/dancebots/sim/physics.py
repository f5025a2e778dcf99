"""The ``physics`` profile's engine: a show's robots, room and people in MuJoCo.

A thin shell around ``mujoco`` (the scene is :func:`dancebots.sim.physics_model.scene_xml`):
the stage hands it each robot's command (v, w) and the people's discs every step; it turns
the commands into wheel speeds by each robot's kinematics, moves the people's bodies, steps
the engine and returns where the robots are and how fast they really move. The LIDAR is cast
by the project's caster on these poses (``sim.raycast``), the same as in the other profiles,
so that differences between profiles come from the physics alone (docs/physics.md).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from types import ModuleType

import numpy as np
from numpy.typing import NDArray

from dancebots.sim.physics_model import (
    DriveKinematics,
    physical_type,
    scene_xml,
    wheel_speeds,
)
from dancebots.world.model import RobotType

__all__ = ["INSTALL_HINT", "PhysicsUnavailableError", "PhysicsWorld", "load_mujoco"]

FloatArray = NDArray[np.float64]

INSTALL_HINT = ("the physics profile runs on MuJoCo, which is not installed here: install it "
                "with `.venv/bin/pip install 'dancebots[physics]'` (or `pip install mujoco`), "
                "or use --profile ideal or realistic")


class PhysicsUnavailableError(RuntimeError):
    """MuJoCo is not installed (the message says how to install it)."""


def load_mujoco() -> ModuleType:
    """The ``mujoco`` module, or :class:`PhysicsUnavailableError` saying how to install it."""
    try:
        import mujoco
    except ImportError:
        raise PhysicsUnavailableError(INSTALL_HINT) from None
    module: ModuleType = mujoco
    return module


class PhysicsWorld:
    """The MuJoCo scene of a stage: robots of ``types`` (R,) at ``starts`` (R, 3), the room
    polygon (N, 2) with walls ``wall_height`` m tall, ``obstacles`` (polygon, height) and
    ``people`` (C, 2) as (radius, height) in m, placed at every :meth:`step`; ``drive``: how
    the robots' drivers turn (v, w) into wheel speeds (``physics_model.wheel_speeds``)."""

    def __init__(self, types: Sequence[RobotType], starts: FloatArray, room: FloatArray,
                 wall_height: float, obstacles: Sequence[tuple[FloatArray, float]],
                 people: FloatArray, drive: DriveKinematics = "calibrated") -> None:
        mujoco = load_mujoco()
        self._mujoco = mujoco
        self.drive: DriveKinematics = drive
        self.bodies = [physical_type(t) for t in types]
        shapes = np.asarray(people, dtype=float).reshape(-1, 2)
        self.model = mujoco.MjModel.from_xml_string(scene_xml(
            types, starts, room, wall_height, obstacles,
            np.column_stack([shapes, np.zeros(len(shapes))])))
        self.data = mujoco.MjData(self.model)
        self.base_timestep = float(self.model.opt.timestep)  # s: the longest step it takes
        joints = [self.model.joint(f"robot{i}").id for i in range(len(self.bodies))]
        self._qpos = np.array([self.model.jnt_qposadr[j] for j in joints], dtype=np.int64)
        self._dof = np.array([self.model.jnt_dofadr[j] for j in joints], dtype=np.int64)
        # per robot its wheels' dof addresses, left and right (the actuators' order)
        self._wheels = [tuple(np.array([self.model.jnt_dofadr[self.model.joint(
            f"robot{i}_{side}{k}").id] for k in range(body.wheels_per_side)], dtype=np.int64)
            for side in "lr") for i, body in enumerate(self.bodies)]
        self._mocap = np.array([self.model.body(f"person{k}").mocapid[0]
                                for k in range(len(shapes))], dtype=np.int64)
        mujoco.mj_forward(self.model, self.data)

    @property
    def timestep(self) -> float:
        """s: the engine's step."""
        return float(self.model.opt.timestep)

    def step(self, command: FloatArray, dt: float, people: FloatArray,
             ) -> tuple[FloatArray, FloatArray]:
        """Drive with ``command`` (R, 2) (v m/s, w rad/s) for ``dt`` s among ``people`` (C, 2+)
        at (x, y) m; returns the robots' poses (R, 3) (x, y, yaw in rad, wrapped) and their
        achieved velocities (R, 2) (v along the heading, w)."""
        data = self.data
        data.ctrl[:] = wheel_speeds(self.bodies, command, self.drive)
        if len(self._mocap):
            data.mocap_pos[self._mocap, :2] = np.asarray(people, dtype=float)[:, :2]
            data.mocap_pos[self._mocap, 2] = 0.0
        steps = max(1, math.ceil(dt / self.base_timestep - 1e-9))
        self.model.opt.timestep = dt / steps  # whole steps that add up to dt exactly
        self._mujoco.mj_step(self.model, data, nstep=steps)
        return self.poses(), self.velocities()

    def poses(self) -> FloatArray:
        """(R, 3) x, y (m) and yaw (rad, in (-pi, pi]) of every robot's chassis."""
        q = self.data.qpos
        a = self._qpos
        w, x, y, z = q[a + 3], q[a + 4], q[a + 5], q[a + 6]
        yaw = np.arctan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
        return np.column_stack([q[a], q[a + 1], yaw])

    def velocities(self) -> FloatArray:
        """(R, 2) each robot's speed along its heading (m/s) and its yaw rate (rad/s)."""
        qv = self.data.qvel
        d = self._dof
        yaw = self.poses()[:, 2]
        forward = qv[d] * np.cos(yaw) + qv[d + 1] * np.sin(yaw)
        return np.column_stack([forward, qv[d + 5]])

    def wheel_rates(self) -> FloatArray:
        """(R,) the yaw rate (rad/s) each robot's wheels would give if they did not slip:
        r (mean right wheel speed - mean left wheel speed) / track. Against the achieved yaw
        rate (:meth:`velocities`) it shows the slip."""
        qv = self.data.qvel
        return np.array([body.wheel_radius * (float(qv[right].mean()) - float(qv[left].mean()))
                         / body.track for body, (left, right) in zip(self.bodies, self._wheels,
                                                                     strict=True)])

    def __repr__(self) -> str:
        return (f"PhysicsWorld({len(self.bodies)} robots, {self.model.nbody} bodies, "
                f"step {self.timestep:g} s, {math.ceil(1 / self.timestep)} Hz)")
