"""The front door: the ``vcbmodel`` command and the figures.

May import: everything in ``vcbmodel``.
"""
