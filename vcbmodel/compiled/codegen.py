"""C source of a traced system: its right-hand side, its guards and a fixed-step RK4 driver.

The driver is the classical four-stage Runge-Kutta scheme on (q, v), the scheme of Exudyn's
``RK44`` solver that the Exudyn models use, with the same fixed step, so the two agree to
round-off where the equations are the same (tests: 1e-9 rad).

A recorded step evaluates the right-hand side at its end for the outputs; the next step's first
stage is that same evaluation (the same time, state and memory: the pre-step left the memory's
bytes as they were), so it is taken over instead of computed again: four evaluations a step
instead of five when every step is recorded, the same numbers bit for bit.
"""
from __future__ import annotations

from dataclasses import dataclass

from .inputs import parametrize
from .trace import Graph, TraceOps

#: C declarations of the compiled module (cffi's ``cdef``)
CDEF = """
int guards_ok(const double *p);
long integrate(const double *p, double *x, double *d, double h, long nsteps, long every, double *rec);
"""

_DRIVER = """
long integrate(const double *p, double *x, double *d, double h, long nsteps, long every, double *rec)
{
    /* RK4 with fixed step h; a row (t, x, aux) every `every` steps from t = 0 into rec; the
       memory d is latched from the state at the start of each step (prestep).
       Returns the rows written, or -(step) at the first non-finite state. */
    double k1[N], k2[N], k3[N], k4[N], xt[N], aux[A > 0 ? A : 1], d0[M > 0 ? M : 1];
    long rows = 0;
    int i, k1_here;  /* k1 holds rhs(t, x, d) of the coming step (from the row just recorded) */
    rhs(0.0, p, x, d, k1, aux);
    rec[0] = 0.0;
    for (i = 0; i < N; ++i) rec[1 + i] = x[i];
    for (i = 0; i < A; ++i) rec[1 + N + i] = aux[i];
    rows = 1;
    k1_here = 1;
    for (long s = 0; s < nsteps; ++s) {
        const double t = (double)s * h;
        if (M > 0) {
            memcpy(d0, d, sizeof(double) * (M > 0 ? M : 1));
            prestep(t, p, x, d);
            if (memcmp(d0, d, sizeof(double) * (M > 0 ? M : 1)) != 0) k1_here = 0;
        }
        if (!k1_here) rhs(t, p, x, d, k1, aux);
        k1_here = 0;
        for (i = 0; i < N; ++i) xt[i] = x[i] + 0.5 * h * k1[i];
        rhs(t + 0.5 * h, p, xt, d, k2, aux);
        for (i = 0; i < N; ++i) xt[i] = x[i] + 0.5 * h * k2[i];
        rhs(t + 0.5 * h, p, xt, d, k3, aux);
        for (i = 0; i < N; ++i) xt[i] = x[i] + h * k3[i];
        rhs(t + h, p, xt, d, k4, aux);
        for (i = 0; i < N; ++i) {
            x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            if (!isfinite(x[i])) return -(s + 1);
        }
        if ((s + 1) % every == 0) {
            double *row = rec + rows * (1 + N + A);
            rhs((double)(s + 1) * h, p, x, d, k1, aux);
            k1_here = 1;
            row[0] = (double)(s + 1) * h;
            for (i = 0; i < N; ++i) row[1 + i] = x[i];
            for (i = 0; i < A; ++i) row[1 + N + i] = aux[i];
            ++rows;
        }
    }
    return rows;
}
"""


@dataclass
class TracedSystem:
    """A system traced at its initial state: the graph, the accelerations, the named outputs and
    the pre-step's new memory values (traced expressions), and the state size."""

    graph: Graph
    accelerations: list
    outputs: dict
    memory: list
    n: int


def trace_system(equations, prestep, setup) -> TracedSystem:
    """Trace ``equations`` (and ``prestep``) at ``setup``'s initial state and memory."""
    graph = Graph()
    ops = TraceOps(graph)
    n = len(setup.q0)
    q = [graph.state(f"x[{i}]", setup.q0[i]) for i in range(n)]
    v = [graph.state(f"x[{n + i}]", setup.v0[i]) for i in range(n)]
    memory = [graph.state(f"d[{i}]", m) for i, m in enumerate(setup.memory)]
    t = graph.state("t", 0.0)
    inputs = parametrize(setup.inputs, graph)
    accelerations, outputs = equations(t, q, v, memory, inputs, ops)
    if len(accelerations) != n:
        raise ValueError(f"{equations.__name__}: {len(accelerations)} accelerations for {n} coordinates")
    new_memory = list(prestep(t, q, v, memory, inputs, ops)) if prestep is not None else []
    if len(new_memory) != len(memory):
        raise ValueError("the pre-step function must return one value per memory value")
    return TracedSystem(graph, list(accelerations), dict(outputs), new_memory, n)


def c_source(traced: TracedSystem) -> str:
    """The module's C: ``rhs`` (dx/dt of x = (q, v) and the outputs), ``prestep``, ``guards_ok``
    and ``integrate``."""
    n, graph = traced.n, traced.graph
    rhs_outputs = {f"f[{n + i}]": a for i, a in enumerate(traced.accelerations)}
    rhs_outputs.update({f"aux[{j}]": e for j, e in enumerate(traced.outputs.values())})
    lines = ["#include <math.h>", "#include <string.h>", f"#define N {2 * n}", f"#define A {len(traced.outputs)}",
             f"#define M {len(traced.memory)}", "",
             "static void rhs(double t, const double *p, const double *x, const double *d, double *f, double *aux)",
             "{", "    (void)t; (void)p; (void)d; (void)aux;"]
    lines += [f"    f[{i}] = x[{n + i}];" for i in range(n)]
    lines += graph.c_statements(rhs_outputs)
    lines += ["}", "", "static void prestep(double t, const double *p, const double *x, double *d)", "{",
              "    (void)t; (void)p; (void)x; (void)d;"]
    if traced.memory:
        new = {f"double m{i}": e for i, e in enumerate(traced.memory)}
        lines += graph.c_statements(new, prefix="s")
        lines += [f"    d[{i}] = m{i};" for i in range(len(traced.memory))]
    lines += ["}", "", "int guards_ok(const double *p)", "{", "    int ok = 1;"]
    lines += graph.c_guards()
    lines += ["    return ok;", "}", _DRIVER]
    return "\n".join(lines) + "\n"
