"""What a simulation is asked to include and what it returns: the effect registry (each
effect an on/off component owning its parameters and where their values may come from),
the one rule for model values, and the result type with units.

May import: ``vcbmodel.laws``, ``vcbmodel.rig``, ``vcbmodel.errors``, ``vcbmodel.parameters``.
"""
