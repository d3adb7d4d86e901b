"""Per-process throughput of a pure arithmetic loop (shares nothing: no files, no memory traffic) at
1, 2, 4, 8, 16 simultaneous processes: what the machine itself gives each core as more are busy."""
import json
import statistics
import subprocess
import sys
import time
LOOP = "import time\nt=time.process_time()\ns=0\nfor i in range(12_000_000): s+=i*i\nprint(time.process_time()-t)"
out = {}
for rnd in range(3):
    for n in (1, 2, 4, 8, 16):
        t0 = time.perf_counter()
        ps = [subprocess.Popen([sys.executable, "-c", LOOP], stdout=subprocess.PIPE, text=True) for _ in range(n)]
        cpu = [float(p.communicate()[0]) for p in ps]
        wall = time.perf_counter() - t0
        out.setdefault(n, []).append({"wall_s": wall, "cpu_mean_s": statistics.mean(cpu)})
        print(rnd, n, round(wall, 3), round(statistics.mean(cpu), 3), flush=True)
res = {n: {"cpu_per_process_s": statistics.median(r["cpu_mean_s"] for r in v),
           "wall_s": statistics.median(r["wall_s"] for r in v)} for n, v in out.items()}
one = res[1]["cpu_per_process_s"]
for n, r in res.items():
    r["throughput_per_process_vs_1"] = one / r["cpu_per_process_s"]
print(json.dumps(res, indent=1))
json.dump({"rounds": out, "medians": res}, open(sys.argv[1], "w"), indent=1)
