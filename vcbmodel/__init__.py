"""vcbmodel: dynamics of spring-driven cam mechanisms in vacuum circuit breakers.

Reproduces and extends Ahn & Kim, "Influence of Spring Dynamics and Friction on Dynamic
Responses in a Spring-Driven Cam" (Trans. KSME A, 2003).

Layers, each a folder that imports only from the ones listed before it:
``laws`` (pure physics) -> ``rig``, ``records`` (files and signals) -> ``model`` (effects,
values, results) -> ``builders`` (Exudyn), ``compiled`` (the laws traced to C), ``reference``
(scipy) -> ``experiments`` (one
record per experiment kind, the simulation chain) -> ``analysis`` (fits, diagnosis) -> ``app``
(command line, figures). ``errors`` and ``parameters`` sit below them all.
"""
__version__ = "0.9.1"
