"""Example third-party poissonkit plugin: pair potentials, a model family, a scene, an outcome."""

__version__ = "0.2.0"
