"""Parameter sweeps: a run spec with ``${name}`` placeholders, run for every row of a grid on Dask.

Each case is ``flexure run case.json`` in a folder of its own, run as a subprocess on a Dask
worker (crashes stay in the subprocess; exit 2 and 3 come back as they are). A case runs in
``OUT/.CASE.partial-UUID`` and is renamed to ``OUT/CASE`` only after its ``status.json`` (the
completion marker, written atomically, last) is in it, so a folder named after its case is
always whole; a rerun skips the cases whose status says exit 0 for the same case spec. Only the
Python standard library is needed to expand and check a sweep; ``distributed`` to run it and
pandas, when present, for the DataFrame.
"""

import concurrent.futures
import csv
import io
import itertools
import json
import math
import os
import pathlib
import re
import shutil
import socket
import subprocess
import sys
import tempfile
import time
import uuid

__all__ = ["sweep", "expand_grid", "find_cli"]

_PLACEHOLDER = re.compile(r"\$\{([A-Za-z_][A-Za-z0-9_]*)\}")
_STATUS = "status.json"
_CASE_SPEC = "case.json"
_TABLE = "sweep.csv"
_TABLE_JSON = "sweep.json"  # the same rows, for programs (non-finite numbers as null)
_STATUS_COLUMNS = ["case", "status", "exit_code", "message", "seconds", "worker", "attempts"]


def find_cli(command=None):
    """The flexure command a sweep runs: ``command``, else $FLEXURE_CLI, else ``flexure`` on PATH,
    else the build tree's (build/python/flexure → build/cli/flexure). ValueError when none is an
    executable file."""
    here = pathlib.Path(__file__).resolve().parent
    candidates = [("command", command), ("FLEXURE_CLI", os.environ.get("FLEXURE_CLI")),
                  ("PATH", shutil.which("flexure")),
                  ("build tree", str(here.parent.parent / "cli" / "flexure"))]
    for where, path in candidates:
        if path and os.path.isfile(path) and os.access(path, os.X_OK):
            return os.path.abspath(path)
        if path and where in ("command", "FLEXURE_CLI"):
            raise ValueError(f"{where}: {path} is not an executable file")
    raise ValueError("the flexure command was not found: pass command=, set FLEXURE_CLI or put "
                     "flexure on PATH")


def _load_json(value, name):
    """(object, directory it came from or None): a dict/list as given, a path read as JSON."""
    if isinstance(value, (dict, list)):
        return value, None
    path = pathlib.Path(value)
    try:
        return json.loads(path.read_text()), path.resolve().parent
    except OSError as e:
        raise ValueError(f"{name}: cannot read {path}: {e.strerror}") from None
    except json.JSONDecodeError as e:
        raise ValueError(f"{name}: {path} is not valid JSON: {e}") from None


def _placeholders(node, found):
    if isinstance(node, str):
        found.update(_PLACEHOLDER.findall(node))
    elif isinstance(node, dict):
        for key, value in node.items():
            _placeholders(key, found)
            _placeholders(value, found)
    elif isinstance(node, list):
        for item in node:
            _placeholders(item, found)
    return found


def _check_value(value, where):
    ok = isinstance(value, (str, bool, int)) or (isinstance(value, float) and math.isfinite(value))
    if not ok:
        raise ValueError(f"{where}: expected a string, a number or true/false, got {value!r}")
    return value


def expand_grid(grid):
    """The rows of a grid: a dict {name: [values…]} gives their product (the last name varying
    fastest), a list of dicts gives its rows as they are (all with the same names). ValueError
    naming the name (or row) for an empty list, a missing name, a value that is not a string,
    number or bool."""
    if isinstance(grid, dict):
        if not grid:
            raise ValueError("grid: no names (expected {name: [values, ...]})")
        names = list(grid)
        for name in names:
            values = grid[name]
            if not isinstance(values, list):
                raise ValueError(f"grid: {name}: expected a list of values, got {values!r}")
            if not values:
                raise ValueError(f"grid: {name}: the list of values is empty")
            for k, value in enumerate(values):
                _check_value(value, f"grid: {name}[{k}]")
        return [dict(zip(names, row)) for row in itertools.product(*grid.values())]
    if isinstance(grid, list):
        if not grid:
            raise ValueError("grid: the list of rows is empty")
        names = None
        for k, row in enumerate(grid):
            if not isinstance(row, dict) or not row:
                raise ValueError(f"grid: row {k}: expected an object {{name: value, ...}}")
            if names is None:
                names = set(row)
            elif set(row) != names:
                raise ValueError(f"grid: row {k}: names {sorted(row)} differ from row 0's "
                                 f"{sorted(names)}")
            for name, value in row.items():
                _check_value(value, f"grid: row {k}: {name}")
        return [dict(row) for row in grid]
    raise ValueError("grid: expected {name: [values, ...]} or a list of rows [{name: value}, ...]")


def _value_text(value):
    if isinstance(value, bool):
        return "true" if value else "false"
    return repr(value) if isinstance(value, float) else str(value)


def _substitute(node, row, spec_dir):
    """The spec with ``${name}`` replaced by row[name]: a string that is only the placeholder
    takes the value itself (a number stays a number), otherwise its text; ``${spec_dir}`` becomes
    the original spec's directory, since the case spec is written into the case folder."""
    if isinstance(node, str):
        whole = _PLACEHOLDER.fullmatch(node)
        if whole and whole.group(1) in row:
            return row[whole.group(1)]

        def text(match):
            name = match.group(1)
            if name in row:
                return _value_text(row[name])
            return spec_dir if name == "spec_dir" else match.group(0)
        return _PLACEHOLDER.sub(text, node)
    if isinstance(node, dict):
        return {_substitute(k, row, spec_dir): _substitute(v, row, spec_dir)
                for k, v in node.items()}
    if isinstance(node, list):
        return [_substitute(item, row, spec_dir) for item in node]
    return node


def _case_id(row, taken):
    """A folder name readable from the row (name=value joined by '_'), unique within the sweep."""
    text = "_".join(f"{k}={_value_text(v)}" for k, v in row.items())
    text = re.sub(r"[^A-Za-z0-9._=+-]+", "-", text).strip("-.")[:100] or "case"
    base, k = text, 2
    while text in taken:
        text, k = f"{base}_{k}", k + 1
    taken.add(text)
    return text


def _check_case(cli, spec, case_id):
    """``flexure run --check`` on the case spec in a scratch folder: (exit code, stderr)."""
    with tempfile.TemporaryDirectory(prefix="flexure-sweep-check-") as scratch:
        path = os.path.join(scratch, _CASE_SPEC)
        with open(path, "w") as f:
            json.dump(spec, f, indent=1)
        done = subprocess.run([cli, "--quiet", "run", "--check", path], cwd=scratch,
                              capture_output=True, text=True)
    return done.returncode, done.stderr.replace(path, f"case {case_id}")


def _check_cases(cli, cases, rows):
    """Every case checked by the command before any runs; ValueError naming the grid values of
    the first case the command refuses and its message."""
    threads = max(1, min(len(cases), os.cpu_count() or 1))
    with concurrent.futures.ThreadPoolExecutor(threads) as pool:
        results = list(pool.map(lambda c: _check_case(cli, c[1], c[0]), cases))
    for (case_id, _), row, (code, stderr) in zip(cases, rows, results):
        if code != 0:
            values = ", ".join(f"{k}={_value_text(v)!s}" for k, v in row.items())
            lines = [line for line in stderr.splitlines() if line.strip()]
            reason = "; ".join(line for line in lines if "no step was run" not in line)
            raise ValueError(f"grid: the case {values} is refused by flexure run (exit {code}): "
                             f"{reason or stderr.strip()}; no case was run")


def _write_json_atomically(path, data):
    temporary = f"{path}.{uuid.uuid4().hex}.tmp"
    with open(temporary, "w") as f:
        json.dump(data, f, indent=1)
        f.flush()
        os.fsync(f.fileno())
    os.replace(temporary, path)


def _finite(table):
    """The table with NaN and infinite numbers as None: JSON has no spelling for them."""
    return [{k: (None if isinstance(v, float) and not math.isfinite(v) else v)
             for k, v in entry.items()} for entry in table]


def _headline(report_path):
    """The report's top-level numbers and booleans (its headline), {} without a readable one."""
    try:
        report = json.loads(pathlib.Path(report_path).read_text())
    except (OSError, ValueError):
        return {}
    if not isinstance(report, dict):
        return {}
    return {k: v for k, v in report.items()
            if isinstance(v, (bool, int, float)) and not (isinstance(v, float) and math.isnan(v))}


def _find_report(folder, spec, report):
    """The case's report: ``report`` (relative to the case folder) when given, else the last
    step's "report" option, else the first report.json under the folder (sorted paths)."""
    if report is None:
        steps = spec.get("steps", [spec]) if isinstance(spec, dict) else []
        options = steps[-1].get("options", {}) if steps and isinstance(steps[-1], dict) else {}
        report = options.get("report") if isinstance(options, dict) else None
    if report is not None:
        path = os.path.join(folder, report)
        return path if os.path.isfile(path) else None
    found = sorted(pathlib.Path(folder).rglob("report.json"))
    return str(found[0]) if found else None


def _worker_name():
    try:
        from distributed import get_worker
        return get_worker().address
    except (ImportError, ValueError):
        return f"{socket.gethostname()}:{os.getpid()}"


def _die_with_parent():
    """In the case's subprocess: SIGKILL when the worker process that started it dies (Linux's
    PR_SET_PDEATHSIG), so a killed worker leaves no case running into a folder nobody reads."""
    try:
        import ctypes
        import signal
        ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG = 1
    except (OSError, AttributeError):
        pass


def _run_case(cli, out_dir, case_id, spec, report):
    """One case on a worker: run it in a fresh partial folder, write its status, rename the
    folder into place. Returns the status dict (also in the folder's status.json)."""
    partial = os.path.join(out_dir, f".{case_id}.partial-{uuid.uuid4().hex}")
    os.makedirs(partial)
    _write_json_atomically(os.path.join(partial, _CASE_SPEC), spec)
    start = time.perf_counter()
    with open(os.path.join(partial, "stdout.txt"), "w") as out, \
            open(os.path.join(partial, "stderr.txt"), "w+") as err:
        code = subprocess.run([cli, "run", _CASE_SPEC], cwd=partial, stdout=out, stderr=err,
                              preexec_fn=_die_with_parent if sys.platform == "linux" else None
                              ).returncode
        err.seek(0)
        lines = [line.strip() for line in err.read().splitlines() if line.strip()]
    seconds = time.perf_counter() - start
    status = {"case": case_id, "exit_code": code, "seconds": seconds, "worker": _worker_name()}
    found = _find_report(partial, spec, report) if code == 0 else None
    if code == 0 and report is not None and found is None:
        status["exit_code"], status["message"] = 2, f"the report {report} was not written"
    elif code != 0:
        failed = [line for line in lines if not line.startswith("flexure run: [")]
        status["message"] = " | ".join(failed[-3:]) or f"exit {code}"
    status["report"] = _headline(found) if found else {}
    status["report_file"] = os.path.relpath(found, partial) if found else None
    _write_json_atomically(os.path.join(partial, _STATUS), status)
    final = os.path.join(out_dir, case_id)
    if os.path.lexists(final):  # a failed or stale earlier run: moved aside, then removed
        stale = os.path.join(out_dir, f".{case_id}.stale-{uuid.uuid4().hex}")
        os.rename(final, stale)
        shutil.rmtree(stale, ignore_errors=True)
    try:
        os.rename(partial, final)
    except OSError:  # another attempt of this case (a worker thought lost) finished first
        shutil.rmtree(partial, ignore_errors=True)
    return status


def _done_status(out_dir, case_id, spec):
    """The status of a finished case folder for this very case spec with exit 0, else None."""
    folder = os.path.join(out_dir, case_id)
    try:
        with open(os.path.join(folder, _STATUS)) as f:
            status = json.load(f)
        with open(os.path.join(folder, _CASE_SPEC)) as f:
            same = json.load(f) == spec
    except (OSError, ValueError):
        return None
    return status if same and status.get("exit_code") == 0 else None


def _partials(out_dir, kinds=("partial", "stale")):
    """{case id: [folders]}: attempts that began and never finished (partial), earlier results
    being replaced (stale)."""
    found = {}
    for entry in os.scandir(out_dir):
        match = re.fullmatch(r"\.(.+)\.(partial|stale)-[0-9a-f]{32}", entry.name)
        if match and match.group(2) in kinds and entry.is_dir(follow_symlinks=False):
            found.setdefault(match.group(1), []).append(entry.path)
    return found


def _client_of(client, workers):
    """(client, owned): the Client given, one connected to a scheduler address, or a new local
    cluster of ``workers`` single-threaded worker processes (then owned: closed at the end)."""
    try:
        import distributed
    except ImportError:
        raise ImportError("flexure.sweep needs Dask's distributed (Debian: python3-distributed, "
                          "pip: distributed)") from None
    # The task travels by value, so workers need the flexure command but not this package.
    try:
        import cloudpickle
        cloudpickle.register_pickle_by_value(sys.modules[__name__])
    except (ImportError, AttributeError):  # cloudpickle < 2: workers import flexure.sweep
        pass
    if isinstance(client, distributed.Client):
        return client, False
    if isinstance(client, str):
        return distributed.Client(client), True
    if client is not None:
        raise ValueError(f"client: expected a distributed.Client or a scheduler address, got "
                         f"{client!r}")
    n = workers or os.cpu_count() or 1
    cluster = distributed.LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                       dashboard_address=None)
    return distributed.Client(cluster), True


def _gather(client, futures):
    """{case id: status} as the futures finish; a case whose task failed beyond its retries (its
    workers killed each time) is recorded as lost, not raised."""
    from distributed import as_completed
    results = {}
    by_future = {future: case_id for case_id, future in futures.items()}
    for future in as_completed(list(futures.values())):
        case_id = by_future[future]
        try:
            results[case_id] = future.result()
        except Exception as e:  # KilledWorker, or an OSError in the task after its retries
            results[case_id] = {"case": case_id, "exit_code": None, "status": "lost",
                                "message": f"{type(e).__name__}: {e}", "report": {}}
    return results


def _table(rows, ids, statuses, attempts):
    """The rows of the sweep's table: the grid values, the case's status, its report's headline."""
    names = list(rows[0])
    table, report_columns = [], []
    for row, case_id in zip(rows, ids):
        status = statuses[case_id]
        entry = dict(row)
        kind = status.get("status") or ("failed" if status["exit_code"] else "done")
        entry.update(case=case_id, status=kind, exit_code=status["exit_code"],
                     message=status.get("message", ""), seconds=status.get("seconds"),
                     worker=status.get("worker"), attempts=attempts.get(case_id, 0))
        for key, value in status.get("report", {}).items():
            column = key if key not in names and key not in _STATUS_COLUMNS else f"report.{key}"
            if column not in report_columns:
                report_columns.append(column)
            entry[column] = value
        table.append(entry)
    return table, names + _STATUS_COLUMNS + report_columns


def _write_csv(path, table, columns):
    text = io.StringIO()
    writer = csv.DictWriter(text, fieldnames=columns, restval="", lineterminator="\n")
    writer.writeheader()
    for entry in table:
        writer.writerow({k: (repr(v) if isinstance(v, float) else v) for k, v in entry.items()})
    temporary = f"{path}.{uuid.uuid4().hex}.tmp"
    with open(temporary, "w") as f:
        f.write(text.getvalue())
    os.replace(temporary, path)


def _run_cases(client, workers, cli, out_dir, todo, report, retries):
    """Runs the cases (id, spec) on Dask: ({case id: status}, {case id: runs started}), the
    folders of killed runs counted, then removed."""
    client, owned = _client_of(client, workers)
    try:
        futures = {case_id: client.submit(_run_case, cli, out_dir, case_id, case_spec, report,
                                          retries=retries, pure=False,
                                          key=f"flexure-case-{case_id}-{uuid.uuid4().hex}")
                   for case_id, case_spec in todo}
        statuses = _gather(client, futures)
    finally:
        if owned:
            cluster = getattr(client, "cluster", None)
            client.close()
            if cluster is not None:
                cluster.close()
    abandoned = _partials(out_dir, ("partial",))
    attempts = {case_id: len(paths) for case_id, paths in abandoned.items()}
    for paths in _partials(out_dir).values():
        for path in paths:
            shutil.rmtree(path, ignore_errors=True)
    for case_id, _ in todo:  # the run that finished (a lost case has none)
        attempts[case_id] = attempts.get(case_id, 0) + (statuses[case_id]["exit_code"] is not None)
    return statuses, attempts


def sweep(spec, grid, client=None, out_dir="sweep", workers=None, command=None, report=None,
          retries=2):
    """Run a run spec for every row of a grid, each case in its own folder, on Dask workers.

    spec: a run spec (the JSON of ``flexure run``: a dict, or the path of a .json file) whose
    strings hold ``${name}`` placeholders; a string that is only a placeholder takes the value
    itself (a number stays a number). ``${spec_dir}`` is the spec file's directory (a dict's:
    the current one). grid: {name: [values…]} (their product) or [{name: value, …}, …] (rows as
    given), or the path of a .json file holding either. Every placeholder must be a grid name
    and every grid name used; then each case is checked by ``flexure run --check`` before any
    runs: a bad grid raises ValueError naming the placeholder, the name or the refused values.

    client: a ``distributed.Client``, a scheduler address ("tcp://host:8786"), or None for a
    local cluster of ``workers`` (default: the CPU count) single-threaded worker processes,
    closed at the end. out_dir: the sweep's folder; case folders ``out_dir/<name=value_…>`` hold
    case.json, stdout.txt, stderr.txt, status.json and the case's outputs. command: the flexure
    executable (default: $FLEXURE_CLI, ``flexure`` on PATH, the build tree's). report: the
    report file, relative to a case folder (default: the last step's "report" option, else the
    first report.json found). retries: reruns of a case whose task raised (a worker killed
    mid-case is rescheduled by Dask itself, up to its allowed-failures).

    A case whose folder holds a status with exit 0 for the same case spec is skipped (status
    "skipped"); a case that exits 2 or 3 is recorded with its message ("failed") and the others
    go on. Returns the table — a pandas DataFrame when pandas is installed, else a list of dicts,
    also written to ``out_dir/sweep.csv`` and ``out_dir/sweep.json`` (non-finite numbers null):
    the grid values, case, status (done | skipped | failed | lost), exit_code, message, seconds,
    worker, attempts (runs started for the case in this sweep, killed ones included), and the
    report's top-level numbers and booleans.
    """
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int)
                                or workers < 1):
        raise ValueError(f"workers: expected a whole number >= 1, got {workers!r}")
    if isinstance(retries, bool) or not isinstance(retries, int) or retries < 0:
        raise ValueError(f"retries: expected a whole number >= 0, got {retries!r}")
    if os.path.exists(out_dir) and not os.path.isdir(out_dir):
        raise ValueError(f"out_dir: {out_dir} exists and is not a folder")
    spec, spec_dir = _load_json(spec, "spec")
    if isinstance(grid, (str, os.PathLike)):
        grid, _ = _load_json(grid, "grid")
    rows = expand_grid(grid)
    used = _placeholders(spec, set()) - {"spec_dir"}
    for name in sorted(used - set(rows[0])):
        raise ValueError(f"spec: the placeholder ${{{name}}} is not a grid name (grid names: "
                         f"{', '.join(rows[0])})")
    for name in rows[0]:
        if name not in used:
            raise ValueError(f"grid: {name} is not a placeholder of the spec (placeholders: "
                             f"{', '.join(sorted(used)) or 'none'})")
    cli = find_cli(command)
    spec_dir = str(spec_dir or pathlib.Path.cwd())
    taken = set()
    cases = [(_case_id(row, taken), _substitute(spec, row, spec_dir)) for row in rows]
    _check_cases(cli, cases, rows)

    out_dir = os.path.abspath(out_dir)
    os.makedirs(out_dir, exist_ok=True)
    for paths in _partials(out_dir).values():  # an interrupted sweep's: never a case's result
        for path in paths:
            shutil.rmtree(path, ignore_errors=True)
    statuses = {}
    todo = []
    for case_id, case_spec in cases:
        status = _done_status(out_dir, case_id, case_spec)
        if status is not None:
            statuses[case_id] = dict(status, status="skipped")
        else:
            todo.append((case_id, case_spec))
    attempts = {}  # case id: runs started in this sweep
    if todo:
        ran, attempts = _run_cases(client, workers, cli, out_dir, todo, report, retries)
        statuses.update(ran)
    table, columns = _table(rows, [c for c, _ in cases], statuses, attempts)
    _write_csv(os.path.join(out_dir, _TABLE), table, columns)
    _write_json_atomically(os.path.join(out_dir, _TABLE_JSON), _finite(table))
    try:
        import pandas
    except ImportError:
        return table
    return pandas.DataFrame(table, columns=columns)


def main(argv=None):
    """``python3 -m flexure sweep SPEC GRID [--out DIR] [--scheduler ADDRESS] [--workers N]``:
    the sweep from a shell. Exit 0 when every case is done or skipped; 2 for a refused grid or
    spec (nothing run); else the largest exit code of the failed cases (3 for a lost one)."""
    import argparse
    parser = argparse.ArgumentParser(prog="python3 -m flexure sweep",
                                     description="Run a flexure run spec over a grid on Dask.")
    parser.add_argument("spec", help="run spec (.json) with ${name} placeholders")
    parser.add_argument("grid", help="grid (.json): {name: [values]} or [{name: value}]")
    parser.add_argument("--out", default="sweep", help="the sweep's folder (default: sweep)")
    parser.add_argument("--scheduler", help="a Dask scheduler's address (default: local workers)")
    parser.add_argument("--workers", type=int, help="local worker processes (default: CPUs)")
    parser.add_argument("--command", help="the flexure executable")
    parser.add_argument("--report", help="the report file, relative to a case folder")
    args = parser.parse_args(argv)
    try:
        table = sweep(args.spec, args.grid, client=args.scheduler, out_dir=args.out,
                      workers=args.workers, command=args.command, report=args.report)
    except ValueError as e:
        print(f"flexure sweep: {e}", file=sys.stderr)
        return 2
    rows = table.to_dict("records") if hasattr(table, "to_dict") else table
    counts = {}
    for row in rows:
        counts[row["status"]] = counts.get(row["status"], 0) + 1
    summary = ", ".join(f"{n} {status}" for status, n in counts.items())
    print(f"flexure sweep: {len(rows)} cases ({summary}): {os.path.join(args.out, _TABLE)}",
          file=sys.stderr)
    codes = [3 if row["status"] == "lost" else int(row["exit_code"]) for row in rows
             if row["status"] in ("failed", "lost")]
    return max(codes, default=0)

