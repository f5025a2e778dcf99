"""Constant-velocity Kalman filters for many tracks at once (NumPy, vectorised over tracks).

State per track: [x, y, vx, vy] (m, m/s) in the odometry frame; measurement: [x, y].
The standard discrete Kalman filter (R. E. Kalman 1960; e.g. Bar-Shalom et al., "Estimation
with Applications to Tracking and Navigation", ch. 5-6):

    predict:  x' = F x,  P' = F P F^T + Q,  F = [[I, dt I], [0, I]],
              Q = q [[dt^3/3 I, dt^2/2 I], [dt^2/2 I, dt I]]  (white-noise acceleration)
    update:   S = H P' H^T + R,  K = P' H^T S^-1,  x = x' + K (z - H x'),  P = (I - K H) P'

with H = [I 0] and R = sigma^2 I. Shapes: states (K, 4), covariances (K, 4, 4).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["kalman_predict", "kalman_update"]

FloatArray = NDArray[np.float64]
_H = np.hstack([np.eye(2), np.zeros((2, 2))])


def kalman_predict(states: FloatArray, covariances: FloatArray, dt: float,
                   acceleration_noise: float) -> tuple[FloatArray, FloatArray]:
    """Predict every track dt s ahead; acceleration_noise q in m^2/s^3."""
    transition = np.eye(4)
    transition[0, 2] = transition[1, 3] = dt
    q = acceleration_noise
    block = np.array([[dt**3 / 3.0, dt**2 / 2.0], [dt**2 / 2.0, dt]]) * q
    noise = np.kron(block, np.eye(2))  # ordered [x, y, vx, vy]
    predicted = states @ transition.T
    covariance = transition @ covariances @ transition.T + noise
    return predicted, covariance


def kalman_update(states: FloatArray, covariances: FloatArray, measurements: FloatArray,
                  measurement_noise: float) -> tuple[FloatArray, FloatArray]:
    """Correct tracks (K, 4) with one position measurement each (K, 2); sigma in m."""
    innovation_cov = _H @ covariances @ _H.T + measurement_noise**2 * np.eye(2)  # (K, 2, 2)
    gain = covariances @ _H.T @ np.linalg.inv(innovation_cov)  # (K, 4, 2)
    residual = measurements - states[:, :2]
    updated = states + np.einsum("kij,kj->ki", gain, residual)
    covariance = (np.eye(4) - gain @ _H) @ covariances
    return updated, covariance
