"""Pure physics: the paper's laws as functions of numbers, with units in their docstrings.

Friction (eq. 2-6, 13), loads and reactions (eq. 1, 5-6, 9-13), closing-spring chains (eq. 7-8),
coil stiffness, contact laws and the whole breaker's geometry and forces. Testable without
Exudyn. May import: numpy, scipy, ``vcbmodel.errors``, ``vcbmodel.parameters``; Exudyn only
lazily inside :func:`vcbmodel.laws.friction.symbolic_ops`.
"""
