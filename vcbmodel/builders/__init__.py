"""Exudyn builders: each turns a rig, a model spec and a friction law into an Exudyn system
with named sensors (``oCam``, ``mPin``, ... handles; explicit RK4 on minimal coordinates).

May import: ``vcbmodel.laws``, ``vcbmodel.rig``, ``vcbmodel.model``, ``vcbmodel.errors``,
``vcbmodel.parameters``; Exudyn only lazily, through :func:`vcbmodel.builders.core.exudyn_modules`.
"""
