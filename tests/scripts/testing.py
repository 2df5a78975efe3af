"""Small helpers shared by the program-level tests: checks that print the
value, the expected value and the tolerance, and a closing count line."""
import sys

_checks = {"passed": 0, "failed": 0}
# The failed checks' lines, repeated by report() at the end: a log cut to its
# last lines (CI's) still names them.
_failures = []


def check_close(what, value, expected, tolerance, relative=True):
    error = abs(value - expected)
    allowed = tolerance * abs(expected) if relative else tolerance
    ok = value == value and error <= allowed  # value == value: not NaN
    _checks["passed" if ok else "failed"] += 1
    line = (f"{'ok  ' if ok else 'FAIL'} {what}: {value:.10g} expected {expected:.10g} "
            f"(error {error:.3g}, allowed {allowed:.3g})")
    print(line)
    if not ok:
        _failures.append(line)
    return ok


def check_true(what, condition):
    _checks["passed" if condition else "failed"] += 1
    line = f"{'ok  ' if condition else 'FAIL'} {what}"
    print(line)
    if not condition:
        _failures.append(line)
    return condition


def report():
    if _failures:
        print("failed checks, again:")
        for line in _failures:
            print(line)
    print(f"{_checks['passed']} passed, {_checks['failed']} failed")
    sys.exit(0 if _checks["failed"] == 0 else 1)


def _parse_prm(lines):
    """For each line of a deal.II parameter file: (path, key) of a
    'set Key = value' line, with path the tuple of enclosing subsections, or
    None; and for each subsection path the index of its 'end' line."""
    keys, ends, path = [], {}, []
    for index, line in enumerate(lines):
        words = line.split("#")[0].strip()
        if words.startswith("subsection "):
            path.append(words[len("subsection "):].strip())
        elif words == "end" and path:
            ends[tuple(path)] = index
            path.pop()
        elif words.startswith("set ") and "=" in words:
            keys.append((tuple(path), words[4:].split("=")[0].strip()))
            continue
        keys.append(None)
    return keys, ends


def read_prm(path):
    """The values of a parameter file: {"Subsection/Key": "value"}."""
    lines = open(path).read().splitlines()
    keys, _ = _parse_prm(lines)
    return {"/".join(key[0] + (key[1],)): line.split("#")[0].split("=", 1)[1].strip()
            for key, line in zip(keys, lines) if key}


def edit_prm(source, dest, edits):
    """Writes the parameter file `source` to `dest` with the values of
    `edits`, {"Subsection/.../Key": value}: an existing key gets the value, a
    missing key is added at the end of its subsection (created if missing),
    and the value None removes the key. Returns dest."""
    lines = open(source).read().splitlines()
    keys, ends = _parse_prm(lines)
    edits = {tuple(name.split("/")): value for name, value in edits.items()}
    existing = {key[0] + (key[1],) for key in keys if key}
    added = {}
    for full, value in edits.items():
        if full not in existing and value is not None:
            added.setdefault(full[:-1], []).append(f"set {full[-1]} = {value}")
    end_of = {index: path for path, index in ends.items()}
    output = []
    for index, (key, line) in enumerate(zip(keys, lines)):
        if index in end_of:
            indent = "  " * len(end_of[index])
            output += [indent + setting for setting in added.pop(end_of[index], [])]
        full = key[0] + (key[1],) if key else None
        if full not in edits:
            output.append(line)
        elif edits[full] is not None:
            output.append(f"{line.split('=', 1)[0].rstrip()} = {edits[full]}")
    for path, settings in added.items():
        output.append("")
        output += ["  " * depth + "subsection " + name for depth, name in enumerate(path)]
        output += ["  " * len(path) + setting for setting in settings]
        output += ["  " * depth + "end" for depth in reversed(range(len(path)))]
    with open(dest, "w") as f:
        f.write("\n".join(output) + "\n")
    return dest
