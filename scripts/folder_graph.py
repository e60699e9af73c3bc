#!/usr/bin/env python3
"""Prints the folder-level include graph of hdm's libraries: one line per arrow "from -> to (n)",
n being the number of #include lines, from include/hdm/<folder> and src/<folder> to the folders of
the hdm headers they include (src-relative "../" includes count too). Arrows that run against the
data flow (docs/architecture.md) are marked "AGAINST THE FLOW" and make the exit status 1.

Usage: python3 scripts/folder_graph.py [REPO] [--mermaid]
"""
import collections
import os
import re
import sys

# The data flow, bottom to top: a folder may include folders of a lower level only.
LEVEL = {"core": 0, "mesh": 1, "slab": 2, "query": 3, "haptics": 4, "edit": 4, "session": 5,
         "atlas": 4, "analysis": 4, "pipeline": 5, "io": 5, "render": 5, "bridge": 6, "harness": 7}
INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]([^>"]+)[>"]')


def folder_of(root, path):
    parts = os.path.relpath(path, root).split(os.sep)
    return parts[2] if parts[0] == "include" else parts[1]


def graph(root):
    edges = collections.Counter()
    for top in ("include/hdm", "src"):
        for d, _, files in os.walk(os.path.join(root, top)):
            for f in files:
                if not f.endswith((".h", ".cpp")):
                    continue
                path = os.path.join(d, f)
                if len(os.path.relpath(path, root).split(os.sep)) < 3:
                    continue  # src/CMakeLists.txt and the like
                src = folder_of(root, path)
                with open(path, errors="replace") as text:
                    for line in text:
                        m = INCLUDE.match(line)
                        if not m:
                            continue
                        inc = m.group(1)
                        if inc.startswith("hdm/"):
                            dst = inc.split("/")[1]
                        elif inc.startswith("../"):
                            dst = folder_of(root, os.path.normpath(os.path.join(d, inc)))
                        else:
                            continue
                        if dst != src:
                            edges[(src, dst)] += 1
    return edges


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    root = args[0] if args else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    edges = graph(root)
    against = [(a, b) for (a, b) in edges if LEVEL.get(a, 99) <= LEVEL.get(b, 99)]
    if "--mermaid" in sys.argv:
        print("flowchart BT")
        for (a, b), n in sorted(edges.items()):
            print(f"  {a} -->|{n}| {b}" if (a, b) not in against else f"  {a} -.->|{n} against the flow| {b}")
    else:
        for (a, b), n in sorted(edges.items()):
            print(f"{a} -> {b} ({n})" + ("  AGAINST THE FLOW" if (a, b) in against else ""))
    return 1 if against else 0


if __name__ == "__main__":
    sys.exit(main())
