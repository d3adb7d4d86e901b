"""Print one of the README's two opening commands (``main`` or ``test``), verbatim.

CI runs the README's own words, so the README and CI cannot drift apart.
"""
import re
import sys
from pathlib import Path

text = Path(__file__).resolve().parents[1].joinpath("README.md").read_text(encoding="utf-8")
block = re.search(r"```(?:bash|sh)\n(.*?)```", text, re.S)
lines = [ln for ln in block.group(1).splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
if len(lines) != 2:
    sys.exit(f"README.md: the first code block must hold exactly two commands, found {len(lines)}")
print(lines[{"main": 0, "test": 1}[sys.argv[1]]])
