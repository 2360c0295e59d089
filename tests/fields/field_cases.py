"""Shared cases of the external-field tests: a cylinder magnet (magpylib keywords, SI), the
box above it the tests tabulate, and the tolerance."""

CYLINDER = {"polarization": [0.0, 0.0, 1.0], "dimension": [0.05, 0.01]}
REGION = (-0.01, -0.01, 0.025, 0.01, 0.01, 0.045)
TOL = 1e-4
