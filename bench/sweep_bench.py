#!/usr/bin/env python3
"""The throughput of flexure.sweep: equal cases on a local Dask cluster against the same cases run
one after another.

Run by ``scripts/bench sweep [ARGS]`` (not a test). Needs the module on PYTHONPATH (build/python)
and the flexure command (FLEXURE_CLI, else build/cli/flexure beside the module).

A case is ``flexure mesh --family patch48 --n N`` and a Newton ``flexure minimize --energy
midedge --boundary quadratic:1,0,-1 --threads 1`` of that plate (one thread, so that the workers'
processes, not the solver's threads, use the cores). ``--cases`` equal cases (they differ only in
an output name) run

- serially: ``flexure run case.json`` in a fresh folder for each, one after another;
- as plain processes, ``--workers`` at a time (no Dask, no checks): the floor of any scheduler on
  these cores;
- as a sweep: ``flexure.sweep`` on a LocalCluster of ``--workers`` single-threaded worker
  processes, started beforehand (its start-up time is printed apart).

Each side runs ``--trials`` times, alternating (the machine may be shared), and keeps its fastest.
Prints the seconds and the throughput ratio serial / sweep on stderr, JSON on stdout.
"""

import argparse
import json
import os
import pathlib
import subprocess
import sys
import tempfile
import time

import distributed

import flexure
from flexure.sweep import find_cli


def spec_of(n):
    return {"steps": [
        {"command": "mesh", "options": {"family": "patch48", "n": n, "o": "plate.obj"}},
        {"command": "minimize",
         "options": {"rest": "plate.obj", "energy": "midedge", "boundary": "quadratic:1,0,-1",
                     "threads": 1, "o": "bent-${copy}.obj", "report": "report.json"}}]}


def case_folder(spec, copy, scratch):
    folder = pathlib.Path(tempfile.mkdtemp(dir=scratch))
    (folder / "case.json").write_text(json.dumps(spec).replace("${copy}", str(copy)))
    return folder


def serial_seconds(cli, spec, cases, scratch):
    start = time.perf_counter()
    for copy in range(cases):
        subprocess.run([cli, "--quiet", "run", "case.json"], cwd=case_folder(spec, copy, scratch),
                       check=True)
    return time.perf_counter() - start


def parallel_seconds(cli, spec, cases, workers, scratch):
    """The floor of any scheduler: the cases as plain processes, `workers` at a time (no Dask,
    no checks): what the cores give two equal solves at once."""
    start = time.perf_counter()
    running = []
    for copy in range(cases):
        if len(running) == workers:
            running.pop(0).wait()
        running.append(subprocess.Popen([cli, "--quiet", "run", "case.json"],
                                        cwd=case_folder(spec, copy, scratch)))
    for process in running:
        process.wait()
    return time.perf_counter() - start


def sweep_seconds(client, cli, spec, cases, scratch):
    out = tempfile.mkdtemp(dir=scratch)
    start = time.perf_counter()
    table = flexure.sweep(spec, {"copy": list(range(cases))}, client=client, out_dir=out,
                          command=cli)
    seconds = time.perf_counter() - start
    if set(table["status"]) != {"done"}:
        sys.exit(f"sweep_bench: a case did not finish: {table[['case', 'message']]}")
    return seconds, float(table["seconds"].mean())


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cases", type=int, default=8)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--n", type=int, default=160, help="patch48 cells per side")
    parser.add_argument("--trials", type=int, default=2)
    args = parser.parse_args()
    cli = find_cli()
    spec = spec_of(args.n)
    start = time.perf_counter()
    cluster = distributed.LocalCluster(n_workers=args.workers, threads_per_worker=1,
                                       processes=True, dashboard_address=None)
    client = distributed.Client(cluster)
    startup = time.perf_counter() - start
    serial, parallel, swept, case_seconds = [], [], [], []
    with tempfile.TemporaryDirectory(prefix="sweep-bench-") as scratch:
        for trial in range(args.trials):
            serial.append(serial_seconds(cli, spec, args.cases, scratch))
            parallel.append(parallel_seconds(cli, spec, args.cases, args.workers, scratch))
            seconds, mean_case = sweep_seconds(client, cli, spec, args.cases, scratch)
            swept.append(seconds)
            case_seconds.append(mean_case)
            print(f"trial {trial + 1}: serial {serial[-1]:.2f} s, plain processes "
                  f"{parallel[-1]:.2f} s, sweep {seconds:.2f} s (a case {mean_case:.2f} s on a "
                  f"worker)", file=sys.stderr)
    client.close()
    cluster.close()
    ratio, floor = min(serial) / min(swept), min(serial) / min(parallel)
    print(f"{args.cases} cases (patch48 n = {args.n}, midedge Newton, 1 thread), "
          f"{args.workers} workers on {os.cpu_count()} cores: serial {min(serial):.2f} s, "
          f"plain processes {min(parallel):.2f} s, sweep {min(swept):.2f} s (cluster start-up "
          f"{startup:.2f} s apart): throughput ratio {ratio:.2f}x; plain processes "
          f"{floor:.2f}x (the cores' floor); the sweep reaches {ratio / floor:.0%} of it",
          file=sys.stderr)
    json.dump({"cases": args.cases, "workers": args.workers, "n": args.n, "cores": os.cpu_count(),
               "serial_seconds": min(serial), "plain_process_seconds": min(parallel),
               "sweep_seconds": min(swept), "cluster_startup_seconds": startup,
               "mean_case_seconds": case_seconds, "throughput_ratio": ratio,
               "plain_process_ratio": floor}, sys.stdout, indent=1)
    print()


if __name__ == "__main__":
    main()
