"""Follower laws: the thesis follower (eq. 4.4); obstacle avoidance and others to come."""

from dancebots.control.follower import FollowerParams, FollowerState, thesis_follower_step

__all__ = ["FollowerParams", "FollowerState", "thesis_follower_step"]
