"""Built-in poissonkit plugin: the non-holonomic systems of Borisov–Mamaev–Tsiganov's survey
(Chaplygin ball, Veselova, BMF, Routh sphere, Suslov, the classes of Theorems 1–2), their
verification (:func:`poissonkit_nonholonomic.verify.verify_system`) and time-changed integration
(:mod:`poissonkit.numerics.conformal`).
"""
