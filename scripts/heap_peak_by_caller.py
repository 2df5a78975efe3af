#!/usr/bin/env python3
"""Where a process's peak heap is: heaptrack's peak, summed by the deepest
isoimpact function on each allocation's stack (and the function it called).

usage:
  heaptrack -o OUT build/isoimpact FILE.prm        # one process, or per rank:
  mpirun -np 2 sh -c 'exec heaptrack -o OUT.rank$OMPI_COMM_WORLD_RANK \
      build/isoimpact FILE.prm'
  heaptrack_print -f OUT.zst --print-flamegraph OUT.flame \
      --flamegraph-cost-type peak > /dev/null
  python3 scripts/heap_peak_by_caller.py OUT.flame [--top 25]

The flame graph's costs are each stack's share of the peak, so the rows add
up to heaptrack's "peak heap memory consumption"."""
import argparse
import collections
import re


def caller_key(frames):
    """The deepest isoimpact frame and the frame below it (templates and
    arguments elided), or 'other'."""
    for i in range(len(frames) - 1, -1, -1):
        if "isoimpact::" in frames[i]:
            name = re.sub(r"<[^<>]*>", "<>", re.sub(r"\(.*", "", frames[i]))
            callee = re.sub(r"\(.*", "", frames[i + 1]) if i + 1 < len(frames) else ""
            return f"{name[:70]} > {callee[:60]}"
    return "other"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("flame")
    parser.add_argument("--top", type=int, default=25)
    args = parser.parse_args()
    by_caller = collections.Counter()
    total = 0
    with open(args.flame) as flame:
        for line in flame:
            stack, _, cost = line.rstrip().rpartition(" ")
            if not cost.isdigit():
                continue
            total += int(cost)
            by_caller[caller_key(stack.split(";"))] += int(cost)
    print(f"peak heap {total / 1e6:.2f} MB")
    print("| MB | caller > callee |")
    print("|---|---|")
    for key, cost in by_caller.most_common(args.top):
        print(f"| {cost / 1e6:.2f} | {key} |")


if __name__ == "__main__":
    main()
