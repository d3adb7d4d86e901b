"""Regenerate results/: every study in turn (--quick: a smoke run; --out DIR: write there).

The wall time of each study goes to ``run_all_timing.json`` in the output folder."""
import json
import platform
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
STUDIES = ["friction_identification.py", "spring_reading.py", "spring_models.py", "vcb_closing.py", "discrepancy_demo.py", "discovery_demo.py",
           "diagnosis_sweep.py", "diagnosis_realism.py", "design_sensitivity.py", "design_tolerance.py", "design_conclusion_map.py",
           "design_optimum.py", "benchmark.py"]


def output_folder(args):
    """The folder the studies write to: ``--out DIR`` or results/."""
    for i, a in enumerate(args):
        if a == "--out" and i + 1 < len(args):
            return Path(args[i + 1])
        if a.startswith("--out="):
            return Path(a.split("=", 1)[1])
    return HERE.parent / "results"


if __name__ == "__main__":
    extra = sys.argv[1:]
    timing = {"quick": "--quick" in extra, "python": platform.python_version(), "studies_s": {}}
    start = time.time()
    for s in STUDIES:
        t0 = time.time()
        print(f"== {s}", flush=True)
        subprocess.run([sys.executable, str(HERE / s), *extra], check=True)
        timing["studies_s"][s] = round(time.time() - t0, 1)
        print(f"== {s}: {time.time() - t0:.0f} s", flush=True)
    timing["total_min"] = round((time.time() - start) / 60, 2)
    out = output_folder(extra)
    out.mkdir(parents=True, exist_ok=True)
    (out / "run_all_timing.json").write_text(json.dumps(timing, indent=1) + "\n")
    print(f"== all studies: {timing['total_min']:.1f} min", flush=True)
