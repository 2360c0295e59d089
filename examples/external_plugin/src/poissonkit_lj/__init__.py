"""Example third-party poissonkit plugin: a Lennard-Jones pair potential."""

__version__ = "0.1.0"
