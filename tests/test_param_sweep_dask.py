"""``ibfem sweep`` on Dask distributed: the embedded cluster on a 6-case sweep with an
invalid, a non-converging and a raising case; a scheduler and two workers started as
subprocesses on 127.0.0.1 with one worker killed mid-sweep. Truths: force balance of each
contact case (the two reactions and the contact's normal force agree), one record per case."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytest.importorskip("distributed")

from test_param_sweep import ROOT, contact_scene  # noqa: E402

from ibfem.solver.sweep.engine import EngineOptions  # noqa: E402
from ibfem.solver.sweep.run import run_sweep  # noqa: E402
from ibfem.solver.sweep.spec import sweep_from_dict  # noqa: E402
from ibfem.solver.sweep.worker import run_case  # noqa: E402

COLUMNS = ["converged", "reactions.cyl/flat.1", "reactions.block/bottom.1", "contacts.0.normal_force"]
BIN = Path(sys.executable).parent


def failing_runner(payload: dict) -> dict:
    """The real task, with the solver made to raise for the scene named "raises"."""
    import ibfem.solver.solving
    from ibfem import solver

    if payload["scene"].get("name") != "raises":
        return run_case(payload)
    original = solver.solving.solve

    def broken(problem, progress=None):
        raise RuntimeError("injected failure inside solve")

    solver.solving.solve = broken
    try:
        return run_case(payload)
    finally:
        solver.solving.solve = original


def _assert_balanced(outputs: dict) -> None:
    top, bottom, n = (outputs[c] for c in COLUMNS[1:])
    assert n > 0 and top == pytest.approx(-n, rel=1e-6) and bottom == pytest.approx(n, rel=1e-6)


def test_embedded_cluster_six_cases_with_invalid_nonconverging_and_raising(tmp_path):
    import cloudpickle

    cloudpickle.register_pickle_by_value(sys.modules[__name__])  # the workers need not import this file
    (tmp_path / "scene.json").write_text(json.dumps(contact_scene()))
    cases = [{"boundary_conditions.cyl/flat.value.1": -1e-3}, {"boundary_conditions.cyl/flat.value.1": -2e-3},
             {"materials.steel.youngs_modulus": -1.0}, {"solver.max_iterations": 1}, {"name": "raises"},
             {"boundary_conditions.cyl/flat.value.1": -3e-3}]
    data = {"sweep": {"scene": "scene.json", "mode": "list", "cases": cases, "outputs": {"columns": COLUMNS}}}
    outcome = run_sweep(sweep_from_dict(data, "embedded.toml", tmp_path), tmp_path / "out",
                        EngineOptions(workers=2), quiet=True, runner=failing_runner, plots=False)
    assert outcome.engine == "an embedded cluster of 2 worker processes"
    rec = [outcome.record(c) for c in outcome.cases]
    assert [r["status"] for r in rec] == ["ok", "ok", "invalid", "not_converged", "error", "ok"]
    for r in (rec[0], rec[1], rec[5]):
        _assert_balanced(r["outputs"])
    n = [rec[k]["outputs"]["contacts.0.normal_force"] for k in (0, 1, 5)]
    assert n[0] < n[1] < n[2]
    assert "youngs_modulus = -1" in rec[2]["message"]
    assert "not converged after 1 iterations" in rec[3]["message"] and rec[3]["outputs"]["converged"] is False
    assert rec[4]["message"] == "RuntimeError: injected failure inside solve"
    assert len({r["worker"] for r in rec if r.get("worker")}) == 2  # both workers ran cases
    table = (tmp_path / "out" / "results.csv").read_text().splitlines()
    assert len(table) == 7 and table[0].startswith("case,hash,")


def _start(cmd: list[str], log: Path) -> subprocess.Popen:
    return subprocess.Popen(cmd, stdout=open(log, "w"), stderr=subprocess.STDOUT, start_new_session=True,
                            cwd=ROOT)


def _stop(proc: subprocess.Popen) -> None:
    if proc.poll() is None:
        os.killpg(proc.pid, signal.SIGKILL)
    proc.wait(timeout=10)


def _wait(predicate, seconds: float, what: str) -> None:
    deadline = time.time() + seconds
    while not predicate():
        if time.time() > deadline:
            raise AssertionError(f"timed out waiting for {what}")
        time.sleep(0.05)


def test_scheduler_and_workers_as_subprocesses_survive_a_killed_worker(tmp_path):
    scheduler_file = tmp_path / "scheduler.json"
    procs = [_start([str(BIN / "dask"), "scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                     "--scheduler-file", str(scheduler_file)], tmp_path / "scheduler.log")]
    try:
        _wait(scheduler_file.is_file, 30, "the scheduler")
        address = json.loads(scheduler_file.read_text())["address"]
        for k in range(2):
            procs.append(_start([str(BIN / "dask"), "worker", address, "--nthreads", "1", "--nworkers", "1",
                                 "--host", "127.0.0.1", "--no-dashboard", "--name", f"w{k}"],
                                tmp_path / f"worker{k}.log"))
        scene = contact_scene()
        for body in scene["bodies"]:
            body["element_size"] = 0.03  # about 1 s per case
        (tmp_path / "scene.json").write_text(json.dumps(scene))
        uys = [-1e-3, -1.5e-3, -2e-3, -2.5e-3, -3e-3, -3.5e-3]
        (tmp_path / "sweep.toml").write_text(
            '[sweep]\nscene = "scene.json"\n[sweep.parameters]\n"boundary_conditions.cyl/flat.value.1" = '
            f"{json.dumps(uys)}\n[sweep.outputs]\ncolumns = {json.dumps(COLUMNS)}\n")
        out = tmp_path / "out"
        env = dict(os.environ, DASK_SCHEDULER_ADDRESS=address)
        driver = subprocess.Popen([sys.executable, "-m", "ibfem.solver.cli", "sweep", str(tmp_path / "sweep.toml"),
                                   "--out", str(out), "--no-plots"], cwd=ROOT, env=env,
                                  stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        jsonl = out / "results.jsonl"
        _wait(lambda: jsonl.is_file() and jsonl.read_text().count("\n") >= 1, 60, "the first case")
        _stop(procs[1])  # worker 0 and its nanny, most likely in the middle of its second case
        stdout, stderr = driver.communicate(timeout=60)
        assert driver.returncode == 0, stderr
        assert "on the cluster at " + address in stdout
        lines = [json.loads(line) for line in jsonl.read_text().splitlines()]
        assert sorted(r["params"]["boundary_conditions.cyl/flat.value.1"] for r in lines) == sorted(uys)
        assert len({r["hash"] for r in lines}) == len(lines) == 6  # nothing lost, nothing twice
        for r in lines:
            assert r["status"] == "ok"
            _assert_balanced(r["outputs"])
        assert len((out / "results.csv").read_text().splitlines()) == 7
    finally:
        for proc in reversed(procs):
            _stop(proc)


def _worker_state() -> dict:
    import os
    import sys

    return {"threads": {k: os.environ.get(k) for k in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "IBFEM_THREADS")},
            "warm": "ibfem.solver.solving" in sys.modules, "trim": os.environ.get("MALLOC_TRIM_THRESHOLD_")}


@pytest.mark.parametrize("start", ["fork server", "spawn"])
def test_embedded_workers_start_with_one_blas_thread(monkeypatch, start):
    """Workers forked from the warm fork server (the default where there is one) must still get
    what Dask's pre-spawn variables give spawned workers, one BLAS thread each (two workers with
    two threads each would share two cores), and not Dask's malloc trim threshold; with
    IBFEM_SWEEP_START=spawn every worker is a fresh interpreter."""
    import multiprocessing

    import cloudpickle

    from ibfem.solver.sweep.engine import _connect

    if start == "fork server" and "forkserver" not in multiprocessing.get_all_start_methods():
        pytest.skip("no fork server on this platform")
    if start == "spawn":
        monkeypatch.setenv("IBFEM_SWEEP_START", "spawn")
    cloudpickle.register_pickle_by_value(sys.modules[__name__])
    client, cluster, _ = _connect(EngineOptions(workers=1))
    try:
        client.wait_for_workers(1, timeout=60)
        (state,) = client.run(_worker_state).values()
    finally:
        client.close()
        cluster.close()
    assert state["threads"] == {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "IBFEM_THREADS": "1"}
    assert state["trim"] is None
    if start == "fork server":
        assert state["warm"]  # imported and solved once in the server, before the fork
