"""``ibfem compile``'s warm-up: within it every size threshold selects the compiled path, and
every threshold is restored after it (the warm-up runs in the user's process: it must leave the
solver's choices as they were)."""

import os

from ibfem.solver import kernel_warmup


def _values():
    return [(owner, name, getattr(owner, name)) for owner, name, _ in kernel_warmup._every_path_settings(True)]


def test_every_threshold_is_set_within_and_restored_after():
    before, threads = _values(), os.environ.get("IBFEM_THREADS")
    for streamed in (True, False):
        with kernel_warmup._every_path(streamed):
            for owner, name, value in kernel_warmup._every_path_settings(streamed):
                assert getattr(owner, name) == value, name
            assert os.environ["IBFEM_THREADS"] == "2"
    assert _values() == before
    assert os.environ.get("IBFEM_THREADS") == threads


def test_thresholds_are_restored_when_a_solve_fails():
    before = _values()
    try:
        with kernel_warmup._every_path(True):
            raise RuntimeError("a failed warm-up solve")
    except RuntimeError:
        pass
    assert _values() == before


def test_the_streamed_and_in_memory_scenes_both_run():
    # the in-memory factor's kernels (numeric_work, multifrontal_range, solve) compile only where
    # a factor stays in memory: the scenes must cover both
    assert {streamed for _, streamed in kernel_warmup.WARM_SCENES} == {True, False}
