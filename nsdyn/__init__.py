"""nsdyn — non-smooth structural dynamics of friction base-isolated frames."""

__version__ = "0.1.0"
