"""Regenerate results/: every study (--quick: a smoke run; --out DIR: write there).

The studies are independent processes (none reads another's output), run in two lanes at once
so the 2 cores stay busy: the realism study (itself two diagnoses at a time, each of which keeps
the cores only partly busy while its fits wait on their simulations) beside all the others in
turn. The benchmark runs last and alone: its wall times are the speed evidence. Times a study
reports of its own work (a fit's, a diagnosis's seconds) are wall times beside the other lane.

The wall and processor time of each study go to ``run_all_timing.json`` in the output folder."""
import json
import os
import platform
import subprocess
import sys
import threading
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
#: Lanes run at once, each its studies in turn; then the studies in ALONE, one at a time.
LANES = (["diagnosis_realism.py"],
         ["friction_identification.py", "spring_reading.py", "spring_models.py", "vcb_closing.py", "vcb_cycle.py", "discrepancy_demo.py",
          "discovery_demo.py", "diagnosis_sweep.py", "design_sensitivity.py", "design_tolerance.py",
          "design_conclusion_map.py", "design_optimum.py"])
ALONE = ["benchmark.py"]
STUDIES = [s for lane in LANES for s in lane] + ALONE


def output_folder(args):
    """The folder the studies write to: ``--out DIR`` or results/."""
    for i, a in enumerate(args):
        if a == "--out" and i + 1 < len(args):
            return Path(args[i + 1])
        if a.startswith("--out="):
            return Path(a.split("=", 1)[1])
    return HERE.parent / "results"


class Runner:
    """Runs studies as child processes and keeps each one's wall and processor seconds (its own and
    its children's: simulation and record workers); after a failure no new study starts (the one
    running in the other lane finishes)."""

    def __init__(self, extra):
        self.extra, self.wall, self.cpu, self.failed = extra, {}, {}, []
        self.lock = threading.Lock()

    def run(self, script):
        with self.lock:
            if self.failed:
                return
            print(f"== {script}", flush=True)
            t0 = time.time()
            p = subprocess.Popen([sys.executable, str(HERE / script), *self.extra])
        _, status, usage = os.wait4(p.pid, 0)
        p.returncode = os.waitstatus_to_exitcode(status)
        with self.lock:
            self.wall[script] = round(time.time() - t0, 1)
            self.cpu[script] = round(usage.ru_utime + usage.ru_stime, 1)
            print(f"== {script}: {self.wall[script]:.0f} s ({self.cpu[script]:.0f} s processor)", flush=True)
            if p.returncode != 0:
                self.failed.append(f"{script} (exit status {p.returncode})")

    def lane(self, scripts):
        for s in scripts:
            self.run(s)


def main():
    extra = sys.argv[1:]
    runner = Runner(extra)
    start = time.time()
    threads = [threading.Thread(target=runner.lane, args=(lane,)) for lane in LANES]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    runner.lane(ALONE)
    if runner.failed:
        sys.exit(f"run_all: failed: {', '.join(runner.failed)}")
    timing = {"quick": "--quick" in extra, "python": platform.python_version(), "cores": os.cpu_count(),
              "lanes": [list(lane) for lane in LANES], "alone": ALONE,
              "studies_s": {s: runner.wall[s] for s in STUDIES},
              "studies_processor_s": {s: runner.cpu[s] for s in STUDIES},
              "total_min": round((time.time() - start) / 60, 2)}
    out = output_folder(extra)
    out.mkdir(parents=True, exist_ok=True)
    (out / "run_all_timing.json").write_text(json.dumps(timing, indent=1) + "\n")
    print(f"== all studies: {timing['total_min']:.1f} min", flush=True)


if __name__ == "__main__":
    main()
