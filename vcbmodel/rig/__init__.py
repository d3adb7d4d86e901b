"""What a rig is: the data of a rig file (``vcb-rig/1``), its JSON reader and section readers,
the model choice (the spring-model value and the rig file's ``model``
section), and units (what a file may state, how a figure is shown). Units are SI
(m, kg, s, N, rad).

May import: ``vcbmodel.laws`` (checks of the breaker's geometry), ``vcbmodel.errors``,
``vcbmodel.parameters``, numpy.
"""
