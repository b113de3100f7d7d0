"""The pictures rendered in forked processes beside the other output (solver.io.parallel_plots):
one child per group of pictures writes them and reports their names; a missing matplotlib
becomes the reason given, any other failure of a child is raised in the caller with its own type
and message, and a child that dies has its pictures rendered in the caller. The rendering itself
is replaced here by a stand-in that writes one file per group naming the process that wrote it."""

import multiprocessing
import os
import pickle
import threading
import time

import pytest

from ibfem.solver.io import parallel_plots, plots


def _stand_in(monkeypatch, behaviour):
    parent = os.getpid()

    def write_plots(out_dir, problem, solution, summary, outputs, groups):
        behaviour(parent)
        paths = [out_dir / f"{group}.txt" for group in groups]
        for path in paths:
            path.write_text(str(os.getpid()))
        return paths

    monkeypatch.setattr(plots, "write_plots", write_plots)


def _job(tmp_path, parallel=True, idle=2):
    parallel_plots.idle_cores, cores = (lambda: idle), parallel_plots.idle_cores  # the machine's load aside
    try:
        return parallel_plots.PlotJob(tmp_path, None, None, {}, {}, parallel=parallel)
    finally:
        parallel_plots.idle_cores = cores


def test_each_group_of_pictures_is_rendered_in_a_process_of_its_own(tmp_path, monkeypatch):
    _stand_in(monkeypatch, lambda parent: None)
    if threading.active_count() > 1:  # another test left a thread: this process does not fork
        pytest.skip("a thread of another test is alive; the fallback is tested below")
    job = _job(tmp_path)
    assert job.parallel
    files, reason, seconds = job.result()
    assert files == [tmp_path / "fields.txt", tmp_path / "profiles.txt"] and reason is None and seconds >= 0.0
    writers = {int(f.read_text()) for f in files}
    assert len(writers) == 2 and os.getpid() not in writers
    for idle in (1, 0):  # one idle core or none: one child renders both groups beside the run
        files, _, _ = _job(tmp_path, idle=idle).result()
        assert len(files) == 2 and len({int(f.read_text()) for f in files} - {os.getpid()}) == 1
    job = _job(tmp_path, parallel=False)  # asked not to
    assert not job.parallel
    files, _, _ = job.result()
    assert sorted(f.name for f in files) == ["fields.txt", "profiles.txt"]
    assert {int(f.read_text()) for f in files} == {os.getpid()}


def test_a_missing_matplotlib_is_the_reason_given(tmp_path, monkeypatch):
    def missing(parent):
        raise ImportError("No module named 'matplotlib'")

    _stand_in(monkeypatch, missing)
    files, reason, _ = _job(tmp_path).result()
    assert files == [] and "matplotlib is not installed" in reason and "ibfem[pictures]" in reason


def test_a_failure_in_the_child_is_raised_in_the_caller(tmp_path, monkeypatch):
    def fails(parent):
        raise ValueError("the section planes need a contact point")

    _stand_in(monkeypatch, fails)
    with pytest.raises(ValueError, match="section planes need a contact point"):
        _job(tmp_path).result()


def test_a_child_that_dies_leaves_the_pictures_to_the_caller(tmp_path, monkeypatch):
    def dies_in_the_child(parent):
        if os.getpid() != parent:
            os._exit(3)

    _stand_in(monkeypatch, dies_in_the_child)
    files, reason, _ = _job(tmp_path).result()
    assert reason is None and len(files) == 2 and {int(f.read_text()) for f in files} == {os.getpid()}


def test_the_idle_cores_are_counted_from_the_load():
    assert 0 <= parallel_plots.idle_cores() <= (os.cpu_count() or 1)


def test_a_process_with_another_thread_renders_here(tmp_path, monkeypatch):
    # forking copies one thread only (a lock another holds stays locked in the child)
    _stand_in(monkeypatch, lambda parent: None)
    release = threading.Event()
    thread = threading.Thread(target=release.wait)
    thread.start()
    try:
        job = _job(tmp_path)
        assert not job.parallel
        files, _, _ = job.result()
    finally:
        release.set()
        thread.join()
    assert {int(f.read_text()) for f in files} == {os.getpid()} and len(files) == 2


def _worker_job(tmp_path, idle=2):
    parallel_plots.idle_cores, cores = (lambda: idle), parallel_plots.idle_cores
    try:
        worker = parallel_plots.PictureWorker.start(None)
        assert worker is not None
        return parallel_plots.PlotJob(tmp_path, None, None, {}, {}, worker=worker)
    finally:
        parallel_plots.idle_cores = cores


def _slow(parent):
    if os.getpid() != parent:  # a picture takes a while: the other process takes the next one
        time.sleep(0.5)


def test_a_worker_started_early_and_its_helper_take_a_picture_each(tmp_path, monkeypatch):
    _stand_in(monkeypatch, _slow)  # before the start: the worker is forked with it
    if threading.active_count() > 1:
        pytest.skip("a thread of another test is alive; the fallback is tested above")
    job = _worker_job(tmp_path)  # two idle cores: the helper starts at once
    assert job.parallel and job.worker is not None
    files, reason, seconds = job.result()
    assert files == [tmp_path / "fields.txt", tmp_path / "profiles.txt"] and reason is None and seconds >= 0.0
    writers = {int(f.read_text()) for f in files}
    assert len(writers) == 2 and os.getpid() not in writers and job.warm_up_s > 0.0 and job.processes == 2


def test_the_helper_waits_until_the_run_has_written_its_own_files(tmp_path, monkeypatch):
    _stand_in(monkeypatch, lambda parent: None)
    if threading.active_count() > 1:
        pytest.skip("a thread of another test is alive")
    job = _worker_job(tmp_path, idle=0)  # no idle core: the helper waits for result()
    wanted = [tmp_path / "fields.txt", tmp_path / "profiles.txt"]
    deadline = time.monotonic() + 60.0
    while not all(f.exists() for f in wanted) and time.monotonic() < deadline:
        time.sleep(0.05)  # the run's own writing, meanwhile
    files, _, _ = job.result()
    assert files == wanted and len({int(f.read_text()) for f in files}) == 1 and job.processes == 1
    assert os.getpid() not in {int(f.read_text()) for f in files}


def test_a_worker_that_fails_or_dies_leaves_the_pictures_to_the_caller(tmp_path, monkeypatch):
    def fails(parent):
        raise ValueError("the section planes need a contact point")

    _stand_in(monkeypatch, fails)
    if threading.active_count() > 1:
        pytest.skip("a thread of another test is alive")
    with pytest.raises(ValueError, match="section planes need a contact point"):
        _worker_job(tmp_path).result()

    def dies_in_the_worker(parent):
        if os.getpid() != parent:
            os._exit(3)

    _stand_in(monkeypatch, dies_in_the_worker)
    files, reason, _ = _worker_job(tmp_path).result()
    assert reason is None and len(files) == 2 and {int(f.read_text()) for f in files} == {os.getpid()}


def test_no_worker_for_a_problem_that_does_not_pickle(monkeypatch):
    assert parallel_plots.PictureWorker.start(threading.Lock()) is None  # forked children later


def test_a_problem_with_local_functions_is_sent_to_the_worker_by_reference(tmp_path, monkeypatch):
    # a part's geometry may hold closures: they do not pickle, but the worker, forked after the
    # problem was made, holds the same objects; the job refers to them
    if threading.active_count() > 1:
        pytest.skip("a thread of another test is alive")
    offset = 3.0
    problem = {"mapping": lambda x: x + offset}

    def write_plots(out_dir, problem, solution, summary, outputs, groups):
        path = out_dir / f"{groups[0]}.txt"
        path.write_text(f"{os.getpid()} {problem['mapping'](solution)}")
        return [path]

    monkeypatch.setattr(plots, "write_plots", write_plots)
    worker = parallel_plots.PictureWorker.start(problem)
    assert worker is not None
    job = parallel_plots.PlotJob(tmp_path, problem, 2.0, {}, {}, worker=worker)
    files, _, _ = job.result()
    assert {f.read_text().split()[1] for f in files} == {"5.0"}
    assert os.getpid() not in {int(f.read_text().split()[0]) for f in files}


def _scene_file(tmp_path, output: str):
    path = tmp_path / "scene.toml"
    path.write_text(f'name = "s"\n[[bodies]]\nname = "b"\n{output}')
    return path


def test_a_worker_is_started_before_the_scene_loads_only_when_the_scene_asks_for_plots(tmp_path):
    if threading.active_count() > 1:
        pytest.skip("a thread of another test is alive")
    assert parallel_plots.PictureWorker.early(_scene_file(tmp_path, "[output]\nplots = false\n")) is None
    assert parallel_plots.PictureWorker.early(_scene_file(tmp_path, "")) is None
    assert parallel_plots.PictureWorker.early(_scene_file(tmp_path, "[output]\nplots = tru\n")) is None  # invalid
    assert parallel_plots.PictureWorker.early(tmp_path / "missing.toml") is None
    early = parallel_plots.PictureWorker.early(_scene_file(tmp_path, "[output]\nplots = true\n"))
    assert early is not None and early.process.is_alive()
    early.stop(at_once=True)
    assert not early.process.is_alive()


def test_the_early_worker_renders_a_problem_without_local_functions(tmp_path, monkeypatch):
    _stand_in(monkeypatch, lambda parent: None)  # before the start: the worker is forked with it
    if threading.active_count() > 1:
        pytest.skip("a thread of another test is alive")
    early = parallel_plots.PictureWorker.early(_scene_file(tmp_path, "[output]\nplots = true\n"))
    problem = {"name": "made after the worker"}
    worker = parallel_plots.PictureWorker.start(problem, early)
    assert worker is early
    files, reason, _ = parallel_plots.PlotJob(tmp_path, problem, None, {}, {}, worker=worker).result()
    assert reason is None and len(files) == 2 and os.getpid() not in {int(f.read_text()) for f in files}


def test_a_problem_with_local_functions_replaces_the_early_worker(tmp_path, monkeypatch):
    # the early worker was forked before the problem's closures existed: a worker forked now
    # holds them (the job refers to them by reference)
    if threading.active_count() > 1:
        pytest.skip("a thread of another test is alive")
    offset = 3.0

    def write_plots(out_dir, problem, solution, summary, outputs, groups):
        path = out_dir / f"{groups[0]}.txt"
        path.write_text(f"{os.getpid()} {problem['mapping'](solution)}")
        return [path]

    monkeypatch.setattr(plots, "write_plots", write_plots)
    early = parallel_plots.PictureWorker.early(_scene_file(tmp_path, "[output]\nplots = true\n"))
    problem = {"mapping": lambda x: x + offset}
    worker = parallel_plots.PictureWorker.start(problem, early)
    assert worker is not None and worker is not early and not early.process.is_alive()
    files, _, _ = parallel_plots.PlotJob(tmp_path, problem, 2.0, {}, {}, worker=worker).result()
    assert {f.read_text().split()[1] for f in files} == {"5.0"}


class _Body:
    def __init__(self, name):
        self.name = name


class _Problem2D:
    dim = 2
    bodies = [_Body("upper"), _Body("lower")]


def test_a_2d_job_goes_without_its_solution_only_when_every_body_has_its_output_mesh(tmp_path):
    solution = object()
    both = parallel_plots.PlotJob(tmp_path, _Problem2D(), solution, {}, {"upper": 1, "lower": 2}, parallel=False)
    one = parallel_plots.PlotJob(tmp_path, _Problem2D(), solution, {}, {"upper": 1}, parallel=False)
    assert both._job_args()[2] is None and one._job_args()[2] is solution
    assert both.args[2] is solution  # kept for the pictures rendered here after a failure


def test_the_projections_thread_pool_does_not_keep_pictures_from_other_processes(monkeypatch):
    # a CAD part's projections leave a thread pool alive; a process forks safely with one thread
    # only, so the pool is stopped before the pictures' processes are forked, and made again by
    # the next projection that needs it
    from ibfem.geometry import _jit

    monkeypatch.setenv("IBFEM_THREADS", "2")
    covered = []
    _jit.run_ranges(lambda lo, hi: covered.append((lo, hi)), 4 * _jit.MIN_RANGE)
    assert threading.active_count() > 1
    assert parallel_plots._fork_context() is not None
    assert threading.active_count() == 1
    _jit.run_ranges(lambda lo, hi: covered.append((lo, hi)), 4 * _jit.MIN_RANGE)
    assert sum(hi - lo for lo, hi in covered) == 8 * _jit.MIN_RANGE  # every point, both times
    _jit.release_threads()


def test_a_layout_sent_ahead_has_the_fixed_parts_drawn_unless_the_job_waits(monkeypatch):
    """A layout message before the job (PictureWorker.start) is drawn while the worker waits;
    when the job is already waiting it is skipped; the job is what the worker gets either way."""
    drawn = []
    monkeypatch.setattr("ibfem.solver.io.plots.prepare_field_background", lambda *layout: drawn.append(layout))
    layout = parallel_plots._LAYOUT + pickle.dumps(("scene", (0.0, 1.0, 0.0, 2.0)))
    for waiting in (False, True):
        reader, writer = multiprocessing.Pipe()
        writer.send_bytes(layout)
        if waiting:
            writer.send_bytes(b"the job")
            assert parallel_plots._next_job(reader) == b"the job"
            continue
        later = threading.Timer(0.2, writer.send_bytes, (b"the job",))  # after the layout is drawn
        later.start()
        assert parallel_plots._next_job(reader) == b"the job"
        later.join()
    assert drawn == [("scene", (0.0, 1.0, 0.0, 2.0))]
