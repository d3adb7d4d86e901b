"""Solves of the experiments without Exudyn (scipy), for verification of the Exudyn models.

``truths`` and ``truth_friction`` hold synthetic truths from outside the fitted family (Tustin,
LuGre, Dahl friction, position-dependent friction and torque); they import nothing from
``vcbmodel.laws``.

May import: ``vcbmodel.laws``, ``vcbmodel.errors``, numpy, scipy.
"""
