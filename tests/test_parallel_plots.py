"""The pictures rendered in a forked process beside the other output (solver.io.parallel_plots):
the child writes them and reports their names; a missing matplotlib becomes the reason given,
any other failure of the child is raised in the caller with its own type and message, and a
child that dies has the pictures rendered in the caller. The rendering itself is replaced here
by a stand-in that writes one file naming the process that wrote it."""

import os

import pytest

from ibfem.solver.io import parallel_plots, plots


def _stand_in(monkeypatch, behaviour):
    parent = os.getpid()

    def write_plots(out_dir, problem, solution, summary, outputs):
        behaviour(parent)
        path = out_dir / "picture.txt"
        path.write_text(str(os.getpid()))
        return [path]

    monkeypatch.setattr(plots, "write_plots", write_plots)


def _job(tmp_path, parallel=True):
    return parallel_plots.PlotJob(tmp_path, None, None, {}, {}, parallel=parallel)


def test_the_pictures_are_rendered_in_a_second_process(tmp_path, monkeypatch):
    _stand_in(monkeypatch, lambda parent: None)
    job = _job(tmp_path)
    assert job.parallel
    files, reason, seconds = job.result()
    assert files == [tmp_path / "picture.txt"] and reason is None and seconds >= 0.0
    assert int(files[0].read_text()) != os.getpid()
    job = _job(tmp_path, parallel=False)
    assert not job.parallel
    files, _, _ = job.result()
    assert int(files[0].read_text()) == os.getpid()


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
    assert reason is None and int(files[0].read_text()) == os.getpid()
