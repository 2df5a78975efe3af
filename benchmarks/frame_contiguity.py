#!/usr/bin/env python3
"""How physically contiguous a running process's large memory is: for its
anonymous mappings (heap) and its shared-memory ones (/dev/shm, the MPI
windows) of 2 MiB or more, the share of neighbouring present virtual pages
whose page frames are neighbours too (/proc/PID/pagemap; root only, else the
frames read as 0). A guest's frames say nothing of the host's, but a
process that the kernel gave scattered frames and one it gave runs of them
can be told apart (doc/parallel.md, session 55).

usage: python3 benchmarks/frame_contiguity.py PID [PID ...]
  prints, per PID: kind, megabytes present, contiguous share."""
import struct
import sys

PAGE = 4096


def contiguity(pid):
    """{kind: (pages present, neighbouring present pairs, contiguous pairs)}."""
    kinds = {}
    with open(f"/proc/{pid}/maps") as maps, open(f"/proc/{pid}/pagemap", "rb") as pagemap:
        for line in maps:
            fields = line.split()
            low, high = (int(x, 16) for x in fields[0].split("-"))
            name = fields[5] if len(fields) > 5 else ""
            if high - low < 2 << 20:
                continue
            if name.startswith("/dev/shm"):
                kind = "shm"
            elif name in ("", "[heap]"):
                kind = "heap"
            else:
                continue
            n = (high - low) // PAGE
            pagemap.seek(low // PAGE * 8)
            entries = struct.unpack(f"<{n}Q", pagemap.read(8 * n))
            frames = [e & ((1 << 55) - 1) if e >> 63 else None for e in entries]
            counts = kinds.setdefault(kind, [0, 0, 0])
            counts[0] += sum(f is not None for f in frames)
            for a, b in zip(frames, frames[1:]):
                if a is not None and b is not None:
                    counts[1] += 1
                    counts[2] += b == a + 1
    return kinds


def describe(pid):
    return "; ".join(f"{kind} {present * PAGE >> 20} MB, contiguous {contiguous / max(pairs, 1):.3f}"
                     for kind, (present, pairs, contiguous) in sorted(contiguity(pid).items()))


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    for pid in sys.argv[1:]:
        print(pid, describe(int(pid)))
