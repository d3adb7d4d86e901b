"""Shared helpers of the study scripts: output folder, JSON/Markdown tables, quick mode."""
import argparse
import json
import logging
import os
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


def parse_args(description, flags=None):
    """--out and --quick, and the study's own on/off ``flags`` ({"--name": help})."""
    p = argparse.ArgumentParser(description=description)
    p.add_argument("--out", default=str(ROOT / "results"), help="output folder (default results/)")
    p.add_argument("--quick", action="store_true", help="smaller, faster run (smoke tests)")
    for flag, text in (flags or {}).items():
        p.add_argument(flag, action="store_true", help=text)
    a = p.parse_args()
    os.makedirs(a.out, exist_ok=True)
    logging.basicConfig(level=logging.INFO, format="%(message)s")  # the library's progress lines on stderr
    return a


def write_json(path, data):
    """``data`` as indented JSON; a file name inside the JSON's own folder is written relative to it (the
    results read the same on every machine, wherever the repository lies)."""
    folder = str(Path(path).resolve().parent) + os.sep
    Path(path).write_text(json.dumps(_relative(data, folder), indent=2, default=float) + "\n")


def _relative(data, folder: str):
    if isinstance(data, str):
        return data[len(folder):] if data.startswith(folder) else data
    if isinstance(data, dict):
        return {k: _relative(v, folder) for k, v in data.items()}
    if isinstance(data, (list, tuple)):
        return [_relative(v, folder) for v in data]
    return data


def markdown_table(headers, rows):
    lines = ["| " + " | ".join(headers) + " |", "|" + "---|" * len(headers)]
    lines += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(lines) + "\n"
