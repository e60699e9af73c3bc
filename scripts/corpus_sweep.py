#!/usr/bin/env python3
"""Bakes every mesh of one or more corpora at default settings, checks each with `hdm check`
(independent of the slab code: Embree on the input) and writes one table per corpus into
docs/figures.md.

A corpus is `libcgal-demo` (every file above 40 KB of Debian's libcgal-demo data archive),
`assimp` (every OBJ, PLY, OFF and STL file of Debian's assimp-testmodels package) or a folder
(every file in it). A third of each corpus, drawn at random with the seed
below, is set aside: the bake is developed on the rest, and the table reports the set-aside part
separately, so that a method tuned to the meshes it was developed on shows as a gap between the
two parts.

Environment: HDM (the hdm program), ONLY (a regex on file names), PART (all, dev or held),
TIMEOUT (seconds per command, default 300), OUT (a folder for the models and logs, default a
temporary one), WRITE (1: write the tables into docs/figures.md), REQUIRE_OK (1: exit 1 unless
every mesh swept passes or is refused as expected).
"""
import json
import os
import random
import re
import subprocess
import sys
import tarfile
import tempfile
import time

HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
HOLDOUT_SEED = 20261123  # fixed before any mesh of either corpus was baked with the method it judges
ARCHIVE = "/usr/share/doc/libcgal-dev/data.tar.gz"
ASSIMP = "/usr/share/assimp/models"
MESH_EXT = (".obj", ".ply", ".off", ".stl")
# Targets every baked mesh must meet ([% of the diagonal] and [%]).
MAX_PCT, RMS_PCT, AGREEMENT_PCT = 0.2, 0.02, 99.5


def corpus_files(corpus, out):
    """(label, [paths]) of one corpus."""
    if corpus == "libcgal-demo":
        dest = os.path.join(out, "libcgal-demo")
        if not os.path.isdir(dest):
            if not os.path.isfile(ARCHIVE):
                sys.exit("corpus_sweep: %s not found (package libcgal-demo)" % ARCHIVE)
            os.makedirs(dest)
            with tarfile.open(ARCHIVE) as t:
                for m in t.getmembers():
                    if m.isfile() and m.name.startswith("data/meshes/") and m.name.count("/") == 2:
                        m.name = os.path.basename(m.name)
                        t.extract(m, dest)
        paths = [os.path.join(dest, f) for f in os.listdir(dest)]
        return corpus, sorted(p for p in paths if os.path.getsize(p) > 40 * 1024)
    if corpus == "assimp":
        if not os.path.isdir(ASSIMP):
            sys.exit("corpus_sweep: %s not found (package assimp-testmodels)" % ASSIMP)
        paths = []
        for sub in ("OBJ", "OFF", "PLY", "STL"):
            d = os.path.join(ASSIMP, sub)
            # Every file of the format's folder: the extension-less ones are format-detection tests.
            paths += [os.path.join(d, f) for f in os.listdir(d)
                      if f.lower().endswith(MESH_EXT) or "." not in f]
        return corpus, sorted(paths)
    if not os.path.isdir(corpus):
        sys.exit("corpus_sweep: %s is neither libcgal-demo, assimp nor a folder" % corpus)
    # A folder: every file in it; hdm reads what assimp reads, and refuses the rest with a reason.
    paths = [os.path.join(corpus, f) for f in os.listdir(corpus)
             if not f.startswith(".") and os.path.isfile(os.path.join(corpus, f))]
    return os.path.basename(os.path.normpath(corpus)), sorted(paths)


def display_name(label, path):
    return os.path.relpath(path, ASSIMP) if label == "assimp" else os.path.basename(path)


def held_out(label, names):
    """The names set aside by the seeded draw: a third of the corpus."""
    rng = random.Random("%d:%s" % (HOLDOUT_SEED, label))
    return set(rng.sample(sorted(names), len(names) // 3))


def run(cmd, stdout, stderr, timeout):
    with open(stdout, "w") as o, open(stderr, "a") as e:
        try:
            return subprocess.run(cmd, stdout=o, stderr=e, timeout=timeout).returncode
        except subprocess.TimeoutExpired:
            return 124


def load(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def sweep_one(hdm, path, name, out, timeout):
    stem = os.path.join(out, re.sub(r"[^A-Za-z0-9_.-]", "_", name))
    for ext in (".bake", ".check", ".err"):
        if os.path.exists(stem + ext):
            os.remove(stem + ext)
    t0 = time.time()
    rc = run([hdm, "bake", path, "-o", stem + ".hdm", "--json"], stem + ".bake", stem + ".err", timeout)
    wall = time.time() - t0
    if rc == 0:
        rc = run([hdm, "check", stem + ".hdm", "--against", path, "--json"], stem + ".check", stem + ".err",
                 timeout)
    row = {"name": name, "rc": rc, "wall": wall, "bytes": os.path.getsize(path)}
    b, c = load(stem + ".bake"), load(stem + ".check")
    if rc == 0 and b and c:
        f = c["fidelity"]
        row.update(slabs=c["slabs"], grid=c["grid"], bake_s=b["total_seconds"], triangles=b["input_triangles"],
                   submesh=b["submesh_triangles"], max=f["max_pct"], max_back=f["max_back_pct"], rms=f["rms_pct"],
                   rms_back=f["rms_back_pct"], agreement=100 * c["contact"]["agreement"],
                   invalid=c["invalid_slabs"], overlapping=c["overlapping_pairs"])
        row["ok"] = (row["invalid"] == 0 and row["overlapping"] == 0 and max(row["max"], row["max_back"]) <= MAX_PCT
                     and max(row["rms"], row["rms_back"]) <= RMS_PCT and row["agreement"] >= AGREEMENT_PCT)
    else:
        with open(stem + ".err", errors="replace") as e:
            lines = [l.strip() for l in e if l.strip()]
        reason = lines[-1] if lines else "exit %d" % rc
        row["reason"] = ("timed out" if rc == 124 else
                         reason.replace("hdm: error: ", "").replace(os.path.dirname(path) + "/", ""))[:300]
    return row


def print_row(r):
    if "slabs" in r:
        print("%-34s %s %6d slabs n=%-2d %6.1f s  %5.2f sub/in  max %.3f/%.3f%%  rms %.4f/%.4f%%  agree %.2f%%  "
              "invalid %d  overlapping %d" % (
                  r["name"], "ok " if r["ok"] else "BAD", r["slabs"], r["grid"], r["bake_s"],
                  r["submesh"] / max(r["triangles"], 1), r["max"], r["max_back"], r["rms"], r["rms_back"],
                  r["agreement"], r["invalid"], r["overlapping"]), file=sys.stderr, flush=True)
    else:
        print("%-34s refused: %s" % (r["name"], r["reason"]), file=sys.stderr, flush=True)


def summary(rows):
    baked = [r for r in rows if "slabs" in r]
    ok = [r for r in baked if r["ok"]]
    slow = max(baked, key=lambda r: r["bake_s"]) if baked else None
    ratios = sorted(r["submesh"] / max(r["triangles"], 1) for r in baked if r["triangles"] >= 20000)
    text = "%d meshes; %d bake and pass every target, %d bake and miss one, %d refused" % (
        len(rows), len(ok), len(baked) - len(ok), len(rows) - len(baked))
    if slow:
        text += "; slowest bake %s, %.1f s" % (slow["name"], slow["bake_s"])
    if ratios:
        text += "; submesh triangles per input triangle (inputs of 20,000 triangles or more): median %.2f, max %.2f" % (
            ratios[len(ratios) // 2], ratios[-1])
    return text


def table(label, rows):
    dev = [r for r in rows if not r["held"]]
    held = [r for r in rows if r["held"]]
    t = ["<!-- CORPUS %s BEGIN (scripts/corpus_sweep.sh writes this table) -->" % label, "",
         "- all: " + summary(rows) + ".",
         "- developed on (two thirds): " + summary(dev) + ".",
         "- set aside (a third, seed %d): " % HOLDOUT_SEED + summary(held) + ".", "",
         "| mesh | set | KB | input triangles | slabs | n | submesh / input | bake s | max % (model->input / back) "
         "| RMS % (both) | agreement % | invalid | overlapping | |",
         "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | --- | --- | ---: | ---: | ---: | --- |"]
    for r in sorted(rows, key=lambda r: (r["held"], r["name"].lower())):
        part = "set aside" if r["held"] else "dev"
        kb = r["bytes"] // 1024
        if "slabs" in r:
            t.append("| %s | %s | %d | %d | %d | %d | %.2f | %.1f | %.3f / %.3f | %.4f / %.4f | %.2f | %d | %d | %s |" % (
                r["name"], part, kb, r["triangles"], r["slabs"], r["grid"], r["submesh"] / max(r["triangles"], 1),
                r["bake_s"], r["max"], r["max_back"], r["rms"], r["rms_back"], r["agreement"], r["invalid"],
                r["overlapping"], "ok" if r["ok"] else "**missed**"))
        else:
            t.append("| %s | %s | %d | refused: %s | | | | | | | | | | |" % (
                r["name"], part, kb, r["reason"].replace("|", "/")))
    t += ["", "<!-- CORPUS %s END -->" % label]
    return "\n".join(t)


def write_table(label, text):
    doc_path = os.path.join(HERE, "docs", "figures.md")
    doc = open(doc_path).read()
    begin, end = "<!-- CORPUS %s BEGIN" % label, "<!-- CORPUS %s END -->" % label
    a, b = doc.find(begin), doc.find(end)
    if a < 0 or b < 0:
        sys.exit("corpus_sweep: docs/figures.md has no CORPUS %s markers" % label)
    with open(doc_path, "w") as f:
        f.write(doc[:a] + text + doc[b + len(end):])


def main():
    hdm = os.environ.get("HDM", os.path.join(HERE, "build", "bin", "hdm"))
    only = os.environ.get("ONLY")
    part = os.environ.get("PART", "all")
    timeout = float(os.environ.get("TIMEOUT", "300"))
    out = os.environ.get("OUT") or tempfile.mkdtemp(prefix="corpus_sweep.")
    os.makedirs(out, exist_ok=True)
    corpora = sys.argv[1:] or ["libcgal-demo", "assimp"]
    failed = swept = 0
    for corpus in corpora:
        label, paths = corpus_files(corpus, out)
        names = {display_name(label, p): p for p in paths}
        held = held_out(label, names)
        rows = []
        with open(os.path.join(out, label + ".rows.jsonl"), "w") as log:
            for name in sorted(names):
                if only and not re.search(only, name):
                    continue
                if part != "all" and (name in held) != (part == "held"):
                    continue
                row = sweep_one(hdm, names[name], name, out, timeout)
                row["held"] = name in held
                rows.append(row)
                log.write(json.dumps(row) + "\n")
                log.flush()
                print_row(row)
        swept += len(rows)
        failed += sum(1 for r in rows if not r.get("ok"))
        if not rows:
            continue
        print("%s: %s" % (label, summary(rows)), file=sys.stderr)
        if os.environ.get("WRITE", "1") == "1" and part == "all" and not only:
            write_table(label, table(label, rows))
    if os.environ.get("REQUIRE_OK") == "1":
        if swept == 0:
            sys.exit("corpus_sweep: no mesh matches ONLY")
        if failed:
            sys.exit("corpus_sweep: %d of %d meshes miss a target or are refused" % (failed, swept))


if __name__ == "__main__":
    main()
