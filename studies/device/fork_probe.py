"""Is a closing slower in a worker process than in the main one? Per-closing processor time of the
compiled reference closing (sweep.figures_of_merit) after each process's own warm-up, in: this process;
forked pool workers (1, 2, 4, 8, 16 at once); the same with gc.freeze() before the fork; fresh
(spawned) processes (1, 2, 16 at once)."""
import copy
import gc
import json
import multiprocessing as mp
import statistics
import subprocess
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from vcbmodel import parameters as P
from vcbmodel.analysis.sweep import figures_of_merit
from vcbmodel.experiments.loading import rig_from_data

N = int(sys.argv[2]) if len(sys.argv) > 2 else 30

def per_closing(n=N):
    rig = rig_from_data(copy.deepcopy(P.REFERENCE_BREAKER))
    for _ in range(2):
        figures_of_merit(rig)
    t = time.process_time(); w = time.perf_counter()
    for _ in range(n):
        figures_of_merit(rig)
    return (time.process_time() - t) / n, (time.perf_counter() - w) / n

def pool(k, freeze=False):
    if freeze:
        gc.freeze()
    with ProcessPoolExecutor(k, mp_context=mp.get_context("fork")) as ex:
        r = list(ex.map(per_closing, [N] * k))
    if freeze:
        gc.unfreeze()
    return statistics.mean(c for c, _ in r)

def spawned(k):
    ps = [subprocess.Popen([sys.executable, __file__, "--child", str(N)], stdout=subprocess.PIPE, text=True)
          for _ in range(k)]
    return statistics.mean(float(p.communicate()[0].split()[-1]) for p in ps)

# MAIN
if __name__ == "__main__" and sys.argv[1] == "--child":
    print(per_closing()[0])
elif __name__ == "__main__":
    res = {}
    cores = len(__import__("os").sched_getaffinity(0))
    ks = [k for k in (1, 2, 4, 8, 16) if k <= cores]
    for rnd in range(2):
        res.setdefault("main", []).append(per_closing()[0])
        for k in ks:
            res.setdefault(f"fork_{k}", []).append(pool(k))
            res.setdefault(f"fork_frozen_{k}", []).append(pool(k, True))
        for k in sorted({1, 2, ks[-1]}):
            res.setdefault(f"spawn_{k}", []).append(spawned(k))
        print(rnd, {k: round(1e3 * v[-1], 1) for k, v in res.items()}, flush=True)
    med = {k: statistics.median(v) for k, v in res.items()}
    print("ms per closing (median):", {k: round(1e3 * v, 1) for k, v in med.items()})
    print("vs main:", {k: round(med["main"] / v, 3) for k, v in med.items()})
    json.dump({"per_closing_s": res, "median_s": med}, open(sys.argv[1], "w"), indent=1)
