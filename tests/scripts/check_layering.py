"""The layering of the library, checked from the #include lines: a file of
layer k (its folder under include/isoimpact/ or source/; source/isoimpact.cc
is layer 6) includes no header of a layer above k.

  check_layering.py ROOT              check the tree at ROOT; exit 1 and name
                                      every wrong-way include
  check_layering.py --self-test ROOT  copy the tree to a temporary folder, add
                                      a wrong-way include and assert that the
                                      check fails and names that file"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

LAYERS = {"nurbs": 1, "fe": 2, "discretization": 3, "mechanics": 4,
          "time_integration": 5, "scene": 6}
PROGRAM = os.path.join("source", "isoimpact.cc")
INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]isoimpact/([^>"]*)[>"]')


def layer_of_file(relative_path):
    """The layer of a file under include/isoimpact/ or source/, or None."""
    if relative_path == PROGRAM:
        return "scene"
    parts = relative_path.split(os.sep)
    folder = parts[2] if parts[0] == "include" and len(parts) > 3 else \
        parts[1] if parts[0] == "source" and len(parts) > 2 else None
    return folder if folder in LAYERS else None


def check(root):
    """Returns (files, include lines, list of problems)."""
    n_files, n_includes, problems = 0, 0, []
    for top in ("include", "source"):
        for directory, _, names in sorted(os.walk(os.path.join(root, top))):
            for name in sorted(names):
                if not name.endswith((".h", ".cc")):
                    continue
                path = os.path.relpath(os.path.join(directory, name), root)
                layer = layer_of_file(path)
                n_files += 1
                if layer is None:
                    problems.append(f"{path}: not in a layer folder")
                    continue
                for number, line in enumerate(open(os.path.join(root, path)), 1):
                    match = INCLUDE.match(line)
                    if not match:
                        continue
                    n_includes += 1
                    header = match.group(1)
                    included = header.split("/")[0] if "/" in header else None
                    if included not in LAYERS:
                        problems.append(f"{path}:{number}: <isoimpact/{header}> is not in a "
                                        "layer folder")
                    elif LAYERS[included] > LAYERS[layer]:
                        problems.append(f"{path}:{number}: layer {LAYERS[layer]} ({layer}) "
                                        f"includes <isoimpact/{header}> of layer "
                                        f"{LAYERS[included]} ({included})")
    return n_files, n_includes, problems


def main(root):
    n_files, n_includes, problems = check(root)
    print(f"checked {n_files} files and {n_includes} #include <isoimpact/...> lines")
    for problem in problems:
        print("FAIL " + problem)
    if n_files == 0 or n_includes == 0:
        print("FAIL no files or no include lines found under " + root)
        return 1
    print(f"{len(problems)} wrong-way or unplaced includes")
    return 1 if problems else 0


def self_test(root):
    """The check passes on a copy of the tree and fails, naming the file, once
    a nurbs source includes a scene header."""
    failures = 0
    with tempfile.TemporaryDirectory() as copy:
        for top in ("include", "source"):
            shutil.copytree(os.path.join(root, top), os.path.join(copy, top))
        run = [sys.executable, os.path.abspath(__file__), copy]
        clean = subprocess.run(run, capture_output=True, text=True)
        print(f"unchanged copy: exit {clean.returncode}")

        wrong = os.path.join("source", "nurbs", "knot_vector.cc")
        with open(os.path.join(copy, wrong), "a") as f:
            f.write("#include <isoimpact/scene/scene.h>\n")
        broken = subprocess.run(run, capture_output=True, text=True)
        print(f"with a wrong-way include in {wrong}: exit {broken.returncode}\n"
              + broken.stdout.strip())
        named = any(line.startswith("FAIL " + wrong + ":") and "scene/scene.h" in line
                    for line in broken.stdout.splitlines())
        for what, ok in [("unchanged copy passes", clean.returncode == 0),
                         ("wrong-way include fails (exit 1)", broken.returncode == 1),
                         (f"the failure names {wrong} and scene/scene.h", named)]:
            print(("ok   " if ok else "FAIL ") + what)
            failures += not ok
    return 1 if failures else 0


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "--self-test":
        sys.exit(self_test(sys.argv[2]))
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    sys.exit(main(sys.argv[1]))
