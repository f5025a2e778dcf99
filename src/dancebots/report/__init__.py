"""Thin presentation layers over result objects: plots of plans (and later of runs)."""

from dancebots.report.plan_plot import plot_plan

__all__ = ["plot_plan"]
