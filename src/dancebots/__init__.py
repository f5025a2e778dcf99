"""dancebots: choreograph, check, simulate and run formations of ground robots."""

__version__ = "0.1.0"
__all__ = ["__version__"]
