"""Coefficient tables of the Wisdom–Holman splittings (kept for old imports).

They live in :mod:`poissonkit.numerics.integrators.wisdom_holman.tables`.
"""

from poissonkit.numerics.integrators.wisdom_holman.tables import (CORRECTOR_ORDERS, TABLE_ORDERS,
                                                                  blanes_coefficients,
                                                                  corrector_operators)

__all__ = ["CORRECTOR_ORDERS", "TABLE_ORDERS", "blanes_coefficients", "corrector_operators"]
