"""vcbmodel: dynamics of spring-driven cam mechanisms in vacuum circuit breakers.

Reproduces and extends Ahn & Kim, "Influence of Spring Dynamics and Friction on Dynamic
Responses in a Spring-Driven Cam" (Trans. KSME A, 2003).
"""
__version__ = "0.1.0"
