"""What a sensor adds to a record besides noise, each behind one protocol (:mod:`.protocol`):
narrow spectral lines (:mod:`.lines`: mains pickup), a clock's timing jitter (:mod:`.jitter`) and an
ADC's or an encoder's rounding (:mod:`.quantisation`). Every module of this folder is imported
here, so an artefact that registers itself in its own module is set aside by the verdict and the
search alike with no other change."""
from __future__ import annotations

import importlib
import pkgutil

from .protocol import ARTEFACTS, Artefact, Found, ResidualView, found_named, register, set_aside

for _module in pkgutil.iter_modules(__path__):
    if _module.name != "protocol":
        importlib.import_module(f"{__name__}.{_module.name}")

__all__ = ["ARTEFACTS", "Artefact", "Found", "ResidualView", "found_named", "register", "set_aside"]
