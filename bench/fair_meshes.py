#!/usr/bin/env python3
"""flexure fair on every CGAL demo mesh with a boundary (issue #30): docs/commands/fair.md's table
of the input's metric against the current one.

Run by ``scripts/bench fair-meshes [ARGS]`` (not a test). For each mesh of CGAL's demo data
(``--meshes``: a directory of .off files, by default data/meshes of libcgal-dev's data.tar.gz
unpacked into the build directory) and each region (``holes``, ``all-interior``), ``flexure fair``
runs once per metric with its defaults (midedge; w = 1 on the input's metric, 0.1 faded to 0.01
on the current one), time-boxed at ``--time-box`` seconds. A case whose every run exits 2 (a
closed mesh, a region at the boundary, a hole filled without a new vertex, an invalid mesh) is
left out of the table and listed as refused. Each row: E_midedge of the result on the input's /
the current metric, the smallest angle of the region's faces and the wall time; or the exit
status (3: not converged, the report's failed check) or "time-boxed"; "filled, nothing to fair"
where CGAL closed every hole by triangles alone.

Prints the table on stderr (Markdown, as in fair.md) and JSON on stdout. One run each: times
are as loaded as the machine is. Run with ``--meshes DIR --only blade.off,holes.off`` for a few.
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

REGIONS = ("all-interior", "holes")


def fair(flexure, mesh, region, metric, time_box, work):
    """One `flexure fair` run: its exit status ("time-boxed" past the box), wall seconds and
    report (None when none was written)."""
    report = os.path.join(work, "report.json")
    if os.path.exists(report):
        os.remove(report)
    command = [flexure, "fair", mesh, "--region", region, "--metric", metric, "-o",
               os.path.join(work, "faired.off"), "--report", report, "--quiet"]
    start = time.monotonic()
    try:
        status = subprocess.run(command, capture_output=True, timeout=time_box).returncode
    except subprocess.TimeoutExpired:
        status = "time-boxed"
    seconds = time.monotonic() - start
    loaded = None
    if status != "time-boxed" and os.path.exists(report):
        with open(report) as f:
            loaded = json.load(f)
    return status, seconds, loaded


def summary(status, seconds, report):
    """The run's record: the result's E_midedge on both metrics and smallest angle when it
    converged, the failed check when it did not."""
    record = {"exit": status, "seconds": round(seconds, 1)}
    if status == 0 and report.get("result") == "filled":  # holes closed without a new vertex
        record["filled_only"] = True
    elif status == 0:
        measures = report["measures"]["flexure"]
        record["e_input"] = measures["bending_energy"]["midedge"]
        record["e_current"] = measures["bending_energy_current_metric"]["midedge"]
        record["min_angle_degrees"] = report["checks"]["min_angle_degrees"]["result"]
    elif status == 3 and report is not None:
        record["failed_check"] = report.get("failed_check", "")
    return record


def cell(record):
    if record.get("filled_only"):
        return "filled, nothing to fair"
    if record["exit"] == 0:
        return "%.4g / %.4g, %.3g°, %.1f s" % (record["e_input"], record["e_current"],
                                               record["min_angle_degrees"], record["seconds"])
    if record["exit"] == "time-boxed":
        return "> %g s (time-boxed)" % record["seconds"]
    return "exit %s (%.0f s)" % (record["exit"], record["seconds"])


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--flexure", default=os.path.join(here, "..", "build", "cli", "flexure"))
    parser.add_argument("--meshes", required=True, help="directory of CGAL's demo .off meshes")
    parser.add_argument("--only", default="", help="comma-separated mesh file names")
    parser.add_argument("--metrics", default="input,current")
    parser.add_argument("--time-box", type=float, default=150.0)
    args = parser.parse_args()
    metrics = args.metrics.split(",")
    meshes = sorted(m for m in os.listdir(args.meshes) if m.endswith(".off"))
    if args.only:
        meshes = [m for m in meshes if m in args.only.split(",")]
    rows, refused = [], []
    print("| mesh, region | " + " | ".join("%s metric" % m for m in metrics) + " |", file=sys.stderr)
    print("|---" * (len(metrics) + 1) + "|", file=sys.stderr)
    with tempfile.TemporaryDirectory() as work:
        for mesh in meshes:
            for region in REGIONS:
                runs = {m: summary(*fair(args.flexure, os.path.join(args.meshes, mesh), region, m,
                                         args.time_box, work)) for m in metrics}
                case = {"mesh": mesh, "region": region, "runs": runs}
                if all(r["exit"] == 2 for r in runs.values()):
                    refused.append(case)
                    continue
                rows.append(case)
                print("| `%s`, %s | " % (mesh, region) +
                      " | ".join(cell(runs[m]) for m in metrics) + " |", file=sys.stderr, flush=True)
    print("refused (exit 2 on every metric): " +
          ", ".join("%s %s" % (c["mesh"], c["region"]) for c in refused), file=sys.stderr)
    json.dump({"time_box_seconds": args.time_box, "metrics": metrics, "cases": rows,
               "refused": refused}, sys.stdout, indent=1)
    print()


if __name__ == "__main__":
    main()
