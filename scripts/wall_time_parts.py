"""Runs a scene several times (default: the benchmark, prm/hertz_fea_hrz.prm)
and prints the median of each part of summary.json's wall_time_parts_s
(set-up, time loop, output, total) and the output's share of the total.

usage: /usr/bin/python3 scripts/wall_time_parts.py [--runs N] [--program P] [PRM]
(run from the repository's root after `bash scripts/setup.sh`)"""
import argparse
import json
import os
import statistics
import subprocess

parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
parser.add_argument("prm", nargs="?", default="prm/hertz_fea_hrz.prm")
parser.add_argument("--runs", type=int, default=5)
parser.add_argument("--program", default="./build/isoimpact")
args = parser.parse_args()

directory = None
for line in open(args.prm):
    words = line.split("#")[0].strip()
    if words.startswith("set Directory"):
        directory = words.split("=", 1)[1].strip()
parts = []
for run in range(args.runs):
    subprocess.run([args.program, args.prm], check=True, stdout=subprocess.DEVNULL)
    parts.append(json.load(open(os.path.join(directory, "summary.json")))["wall_time_parts_s"])
    p = parts[-1]
    print(f"run {run + 1}: " + ", ".join(f"{k} {v:.3f} s" for k, v in p.items()) +
          f", output share {100 * p['output'] / p['total']:.1f} %")
median = {k: statistics.median(p[k] for p in parts) for k in parts[0]}
share = statistics.median(100 * p["output"] / p["total"] for p in parts)
print(f"median of {args.runs} runs of {args.prm}: " + ", ".join(f"{k} {v:.3f} s" for k, v in median.items()) +
      f"; output share {share:.1f} % (median of the runs' shares)")
