"""flexure.sweep on a 2-worker local Dask cluster: the table against the cases run one by one, a
worker killed mid-case, a rerun after an interrupted sweep, grids refused before any case runs."""

import csv
import json
import os
import pathlib
import signal
import subprocess
import threading
import time

import distributed
import pytest

import flexure
from flexure.sweep import main as sweep_main

# A tiny clamped plate: the mesh, then Newton on one thread (< 1 s a case).
SPEC = {"steps": [
    {"command": "mesh", "options": {"family": "patch48", "n": "${n}", "o": "plate.obj"}},
    {"command": "minimize",
     "options": {"rest": "plate.obj", "energy": "${energy}", "boundary": "quadratic:${a},0,1",
                 "threads": 1, "o": "bent.obj", "report": "report.json"}}]}
GRID = {"energy": ["midedge", "hinge"], "a": [0.2, -0.5], "n": [6, 8]}


@pytest.fixture(scope="module")
def cli_path():
    path = os.environ.get("FLEXURE_CLI") or str(pathlib.Path("cli/flexure").resolve())
    assert os.access(path, os.X_OK), f"the flexure CLI is not at {path} (set FLEXURE_CLI)"
    return path


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                       dashboard_address=None)
    with distributed.Client(cluster) as c:
        yield c
    cluster.close()


def one_by_one(cli_path, folder, energy, a, n):
    """The case run by hand (the spec written out here, not by the sweep): its report."""
    folder.mkdir(parents=True)
    text = json.dumps(SPEC).replace('"${n}"', str(n)).replace("${energy}", energy)
    (folder / "case.json").write_text(text.replace("${a}", repr(a)))
    subprocess.run([cli_path, "--quiet", "run", "case.json"], cwd=folder, check=True)
    return json.loads((folder / "report.json").read_text())


def test_sweep_on_two_workers_equals_the_cases_run_one_by_one(client, cli_path, tmp_path):
    table = flexure.sweep(SPEC, GRID, client=client, out_dir=tmp_path / "sweep", command=cli_path)
    assert len(table) == 8 and set(table["status"]) == {"done"}
    assert (table["exit_code"] == 0).all() and (table["attempts"] == 1).all()
    assert table["worker"].nunique() == 2  # both workers ran cases
    on_disk = list(csv.DictReader(open(tmp_path / "sweep" / "sweep.csv")))
    assert [r["case"] for r in on_disk] == list(table["case"])
    as_json = json.loads((tmp_path / "sweep" / "sweep.json").read_text())
    assert [r["case"] for r in as_json] == list(table["case"])
    compared = 0
    for k, row in table.iterrows():
        report = one_by_one(cli_path, tmp_path / "serial" / row["case"], row["energy"], row["a"],
                            row["n"])
        assert report["converged"] is True
        for key, value in report.items():
            if isinstance(value, (int, float)) and "seconds" not in key:
                column = f"report.{key}" if f"report.{key}" in table.columns else key
                assert row[column] == value, (row["case"], key)
                text = repr(value) if isinstance(value, float) else str(value)
                assert on_disk[k][column] == text, (row["case"], key)
                compared += 1
        folder = tmp_path / "sweep" / row["case"]
        assert (folder / "bent.obj").read_bytes() == (
            tmp_path / "serial" / row["case"] / "bent.obj").read_bytes()
    assert compared >= 8 * 5
    assert not [p for p in (tmp_path / "sweep").iterdir() if p.name.startswith(".")]


def test_a_worker_killed_mid_case_has_its_case_retried_and_its_folder_whole(client, cli_path,
                                                                            tmp_path):
    # Four cases of about 1 s each, so both workers are busy when one is killed.
    grid = {"energy": ["midedge"], "a": [0.2, 0.4, 0.6, 0.8], "n": [160]}
    out = tmp_path / "sweep"
    result = {}
    thread = threading.Thread(target=lambda: result.update(table=flexure.sweep(
        SPEC, grid, client=client, out_dir=out, command=cli_path)))
    thread.start()
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        if out.is_dir() and len([p for p in out.iterdir() if ".partial-" in p.name]) == 2:
            break
        time.sleep(0.02)
    else:
        pytest.fail("the two workers did not start their cases")
    pids = client.run(os.getpid)
    killed_address, killed_pid = sorted(pids.items())[0]
    os.kill(killed_pid, signal.SIGKILL)
    thread.join(120)
    assert not thread.is_alive()
    table = result["table"]
    assert list(table["status"]) == ["done"] * 4
    assert sorted(table["attempts"]) == [1, 1, 1, 2]  # the killed worker's case ran again
    assert killed_address not in set(table["worker"])  # it finished elsewhere
    for case in table["case"]:
        folder = out / case
        assert json.loads((folder / "status.json").read_text())["exit_code"] == 0
        assert json.loads((folder / "report.json").read_text())["converged"] is True
        assert (folder / "bent.obj").stat().st_size > 0
    tables = ["sweep.csv", "sweep.json"]
    assert sorted(p.name for p in out.iterdir()) == sorted(list(table["case"]) + tables)
    client.wait_for_workers(2, timeout=60)


def test_a_rerun_after_an_interrupted_sweep_runs_only_the_missing_cases(client, cli_path,
                                                                        tmp_path):
    out = tmp_path / "sweep"
    first = {"energy": ["midedge", "hinge"], "a": [0.2], "n": [6, 8]}
    table = flexure.sweep(SPEC, first, client=client, out_dir=out, command=cli_path)
    cases = list(table["case"])
    # The interruption: one case's folder never renamed into place (only its partial folder is
    # left), another without its completion marker; the grid then grows by four cases.
    lost, unmarked, *kept = cases
    (out / lost).rename(out / f".{lost}.partial-{'0' * 32}")
    (out / unmarked / "status.json").unlink()
    stamps = {case: (out / case / "status.json").stat().st_mtime_ns for case in kept}
    table = flexure.sweep(SPEC, GRID, client=client, out_dir=out, command=cli_path)
    ran = set(table.loc[table["status"] == "done", "case"])
    assert set(table.loc[table["status"] == "skipped", "case"]) == set(kept)
    assert ran == set(table["case"]) - set(kept) and lost in ran and unmarked in ran
    assert len(ran) == 6
    assert {case: (out / case / "status.json").stat().st_mtime_ns for case in kept} == stamps
    assert not [p for p in out.iterdir() if p.name.startswith(".")]
    # Nothing missing: no case runs, and no cluster is started.
    again = flexure.sweep(SPEC, GRID, client="tcp://127.0.0.1:1", out_dir=out, command=cli_path)
    assert set(again["status"]) == {"skipped"}
    assert list(again["final_energy"]) == list(table["final_energy"])


def test_a_failing_case_is_recorded_and_the_others_go_on(client, cli_path, tmp_path):
    # Two iterations are too few for Newton from the flat plate (start given): exit 3.
    spec = json.loads(json.dumps(SPEC))
    spec["steps"][1]["options"].update({"start": "${start}", "max-iterations": 2})
    grid = {"energy": ["midedge"], "a": [3.0], "n": [8], "start": ["linearized", "given"]}
    table = flexure.sweep(spec, grid, client=client, out_dir=tmp_path / "s", command=cli_path)
    codes = dict(zip(table["start"], table["exit_code"]))
    assert codes["given"] == 3 and codes["linearized"] in (0, 3)
    failed = table[table["start"] == "given"].iloc[0]
    assert failed["status"] == "failed" and failed["message"]
    # From a shell, on the same scheduler: the failed case runs again and its code is the exit.
    (tmp_path / "spec.json").write_text(json.dumps(spec))
    (tmp_path / "grid.json").write_text(json.dumps(grid))
    code = sweep_main([str(tmp_path / "spec.json"), str(tmp_path / "grid.json"),
                       "--out", str(tmp_path / "s"), "--command", cli_path,
                       "--scheduler", client.scheduler.address])
    assert code == 3
    again = list(csv.DictReader(open(tmp_path / "s" / "sweep.csv")))
    assert {r["start"]: r["status"] for r in again}["given"] == "failed"


@pytest.mark.parametrize("grid, message", [
    ({"energy": ["midedge"], "a": [0.2]}, r"placeholder \$\{n\} is not a grid name"),
    ({"energy": [], "a": [0.2], "n": [6]}, "energy: the list of values is empty"),
    ({"energy": ["midedge"], "a": [0.2], "n": [6], "m": [1]}, "m is not a placeholder of the spec"),
    ({"energy": ["midedge", "midedgee"], "a": [0.2], "n": [6]}, "energy=midedgee.*midedgee"),
    ({"energy": ["hinge"], "a": [0.2], "n": [6, -3]}, "n=-3"),
    ([{"energy": "hinge", "a": 0.2, "n": 6}, {"energy": "hinge", "a": 0.2}], "row 1"),
])
def test_a_bad_grid_is_refused_before_any_case_runs(cli_path, tmp_path, grid, message):
    with pytest.raises(ValueError, match=message):
        flexure.sweep(SPEC, grid, client="tcp://127.0.0.1:1", out_dir=tmp_path / "s",
                      command=cli_path)
    assert not (tmp_path / "s").exists()


def test_flexure_run_grid_runs_the_sweep_from_the_command(client, cli_path, tmp_path):
    (tmp_path / "spec.json").write_text(json.dumps(SPEC))
    (tmp_path / "grid.json").write_text(json.dumps({"energy": ["midedge", "hinge"], "a": [0.2],
                                                    "n": [6]}))
    done = subprocess.run([cli_path, "run", "spec.json", "--grid", "grid.json", "-o", "out",
                           "--scheduler", client.scheduler.address], cwd=tmp_path,
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    rows = list(csv.DictReader(open(tmp_path / "out" / "sweep.csv")))
    assert [(r["energy"], r["status"]) for r in rows] == [("midedge", "done"), ("hinge", "done")]
    for r in rows:
        report = json.loads((tmp_path / "out" / r["case"] / "report.json").read_text())
        assert r["final_energy"] == repr(report["final_energy"])
    (tmp_path / "bad.json").write_text(json.dumps({"energy": ["hinge"], "a": [0.2]}))
    done = subprocess.run([cli_path, "run", "spec.json", "--grid", "bad.json", "-o", "bad"],
                          cwd=tmp_path, capture_output=True, text=True)
    assert done.returncode == 2 and "${n}" in done.stderr
    assert not (tmp_path / "bad").exists()


def test_an_out_dir_that_is_a_file_is_refused(cli_path, tmp_path):
    (tmp_path / "s").write_text("not a folder")
    with pytest.raises(ValueError, match="out_dir: .*s exists and is not a folder"):
        flexure.sweep(SPEC, GRID, client="tcp://127.0.0.1:1", out_dir=tmp_path / "s",
                      command=cli_path)
    assert (tmp_path / "s").read_text() == "not a folder"


def test_flexure_converge_on_a_scheduler_writes_a_local_runs_tables(client, cli_path, tmp_path):
    """Each energy's part of the study is a case of the sweep; joined, the tables and plots are
    the local run's byte for byte (a user mesh named as given); a rerun runs only a lost part."""
    def flexure_cli(*args):
        return subprocess.run([cli_path, *args], cwd=tmp_path, capture_output=True, text=True)

    assert flexure_cli("mesh", "--family", "delaunay", "-n", "5", "-o", "mine.obj").returncode == 0
    study = ["converge", "--energies", "hinge,midedge:free,cotan", "--families",
             "patch48,delaunay", "--mesh", "mine.obj", "-n", "4", "--levels", "2",
             "--amplitudes", "2"]
    local = flexure_cli(*study, "-o", "local")
    assert local.returncode == 0, local.stderr
    dist = flexure_cli(*study, "-o", "dist", "--scheduler", client.scheduler.address)
    assert dist.returncode == 0, dist.stderr
    assert dist.stdout == local.stdout  # summary.md, printed

    def same_files():
        names = sorted(p.name for p in (tmp_path / "local").iterdir())
        assert sorted(p.name for p in (tmp_path / "dist").iterdir()) == sorted(names + ["cases"])
        for name in names:
            assert (tmp_path / "dist" / name).read_bytes() == \
                (tmp_path / "local" / name).read_bytes(), name
        return names

    assert "summary.md" in same_files() and "c2_delaunay.png" in same_files()
    assert "mine.obj" in (tmp_path / "dist" / "results.csv").read_text()
    cases = tmp_path / "dist" / "cases"
    rows = json.loads((cases / "sweep.json").read_text())
    assert [(r["energy"], r["status"]) for r in rows] == [
        ("hinge", "done"), ("midedge:free", "done"), ("cotan:voronoi", "done")]

    lost = rows[1]["case"]
    subprocess.run(["rm", "-r", str(cases / lost), str(tmp_path / "dist" / "results.json")],
                   check=True)
    again = flexure_cli(*study, "-o", "dist", "--scheduler", client.scheduler.address)
    assert again.returncode == 0, again.stderr
    rows = json.loads((cases / "sweep.json").read_text())
    assert [r["status"] for r in rows] == ["skipped", "done", "skipped"]
    same_files()

    modes = flexure_cli("converge", "--measure", "modes", "--workers", "2", "-o", "m")
    assert modes.returncode == 2
    assert "--scheduler and --workers apply to --measure c1c2" in modes.stderr
    # A sweep that cannot start leaves no folder behind.
    refused = subprocess.run([cli_path, *study, "-o", "refused", "--workers", "2"], cwd=tmp_path,
                             capture_output=True, text=True,
                             env=dict(os.environ, FLEXURE_PYTHON=str(tmp_path / "no-python")))
    assert refused.returncode == 2 and "cannot start" in refused.stderr
    assert not (tmp_path / "refused").exists()
