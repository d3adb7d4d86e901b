"""C source of a traced system: its right-hand side, its guards and a fixed-step RK4 driver.

The driver is the classical four-stage Runge-Kutta scheme on (q, v), the scheme of Exudyn's
``RK44`` solver that the Exudyn models use, with the same fixed step, so the two agree to
round-off where the equations are the same (tests: 1e-9 rad).
"""
from __future__ import annotations

from .trace import Graph, TraceOps
from .inputs import parametrize

#: C declarations of the compiled module (cffi's ``cdef``)
CDEF = """
int guards_ok(const double *p);
long integrate(const double *p, double *x, double h, long nsteps, long every, double *rec);
"""

_DRIVER = """
long integrate(const double *p, double *x, double h, long nsteps, long every, double *rec)
{
    /* RK4 with fixed step h; a row (t, x, aux) every `every` steps from t = 0 into rec.
       Returns the rows written, or -(step) at the first non-finite state. */
    double k1[N], k2[N], k3[N], k4[N], xt[N], aux[A > 0 ? A : 1];
    long rows = 0;
    int i;
    rhs(0.0, p, x, k1, aux);
    rec[0] = 0.0;
    for (i = 0; i < N; ++i) rec[1 + i] = x[i];
    for (i = 0; i < A; ++i) rec[1 + N + i] = aux[i];
    rows = 1;
    for (long s = 0; s < nsteps; ++s) {
        const double t = (double)s * h;
        rhs(t, p, x, k1, aux);
        for (i = 0; i < N; ++i) xt[i] = x[i] + 0.5 * h * k1[i];
        rhs(t + 0.5 * h, p, xt, k2, aux);
        for (i = 0; i < N; ++i) xt[i] = x[i] + 0.5 * h * k2[i];
        rhs(t + 0.5 * h, p, xt, k3, aux);
        for (i = 0; i < N; ++i) xt[i] = x[i] + h * k3[i];
        rhs(t + h, p, xt, k4, aux);
        for (i = 0; i < N; ++i) {
            x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            if (!isfinite(x[i])) return -(s + 1);
        }
        if ((s + 1) % every == 0) {
            double *row = rec + rows * (1 + N + A);
            rhs((double)(s + 1) * h, p, x, k1, aux);
            row[0] = (double)(s + 1) * h;
            for (i = 0; i < N; ++i) row[1 + i] = x[i];
            for (i = 0; i < A; ++i) row[1 + N + i] = aux[i];
            ++rows;
        }
    }
    return rows;
}
"""


def trace_system(equations, inputs, q0, v0):
    """Trace ``equations(t, q, v, inputs, ops)`` at the initial state; returns (graph,
    accelerations, outputs) with the traced expressions."""
    graph = Graph()
    ops = TraceOps(graph)
    n = len(q0)
    q = [graph.state(f"x[{i}]", q0[i]) for i in range(n)]
    v = [graph.state(f"x[{n + i}]", v0[i]) for i in range(n)]
    t = graph.state("t", 0.0)
    traced_inputs = parametrize(inputs, graph)
    accelerations, outputs = equations(t, q, v, traced_inputs, ops)
    if len(accelerations) != n:
        raise ValueError(f"{equations.__name__}: {len(accelerations)} accelerations for {n} coordinates")
    return graph, list(accelerations), dict(outputs)


def c_source(graph, accelerations, outputs, n):
    """The module's C: ``rhs`` (dx/dt of x = (q, v) and the outputs), ``guards_ok`` and ``integrate``."""
    targets = {f"f[{i}]": f"x[{n + i}]" for i in range(n)}
    rhs_outputs = {f"f[{n + i}]": a for i, a in enumerate(accelerations)}
    rhs_outputs.update({f"aux[{j}]": e for j, e in enumerate(outputs.values())})
    lines = ["#include <math.h>", f"#define N {2 * n}", f"#define A {len(outputs)}", "",
             "static void rhs(double t, const double *p, const double *x, double *f, double *aux)", "{",
             "    (void)t; (void)p; (void)aux;"]
    lines += [f"    {k} = {v};" for k, v in targets.items()]
    lines += graph.c_statements(rhs_outputs)
    lines += ["}", "", "int guards_ok(const double *p)", "{", "    int ok = 1;"]
    lines += graph.c_guards()
    lines += ["    return ok;", "}", _DRIVER]
    return "\n".join(lines) + "\n"
