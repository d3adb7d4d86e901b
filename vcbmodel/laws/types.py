"""Type aliases of the laws' signatures (annotations only; nothing here is checked at run time)."""
from __future__ import annotations

from typing import Any

#: A law's numeric argument or result: a float, a numpy array, or a symbolic/traced value (the
#: ``ops`` argument decides). Not ``float``: the same law runs on all of them.
Scalar = Any

#: An ``ops`` namespace: :class:`~vcbmodel.laws.friction.NumericOps` or
#: :class:`~vcbmodel.laws.friction.ArrayOps` (classes of static operations), the class
#: :func:`~vcbmodel.laws.friction.symbolic_ops` returns, or a ``compiled.trace.TraceOps`` instance.
Ops = Any
